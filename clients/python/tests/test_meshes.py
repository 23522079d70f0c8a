"""Uploads: files and numpy arrays, ids = SHA-256 of the bytes, bytes sent only when missing."""
import hashlib

import grpc
import numpy as np
import pytest

import depath
from conftest import TIME_SCALE, grid, read_off


class CountUploads(grpc.StreamUnaryClientInterceptor):
    """Counts UploadMesh calls that go out on the channel."""

    def __init__(self):
        self.count = 0

    def intercept_stream_unary(self, continuation, details, request_iterator):
        if details.method.endswith("/UploadMesh"):
            self.count += 1
        return continuation(details, request_iterator)


def test_file_id_is_sha256_of_its_bytes(client, kitten):
    mesh_id = client.upload(kitten)
    assert mesh_id == hashlib.sha256(kitten.read_bytes()).hexdigest()
    info = client.mesh_info(mesh_id)
    assert (info.num_vertices, info.num_faces, info.format) == (2500, 5000, "off")
    assert client.mesh_info(kitten).id == mesh_id  # looked up by file too


def test_arrays_become_the_same_mesh_as_the_file(client, kitten, kitten_arrays):
    V, F = kitten_arrays
    mesh_id = client.upload((V, F))
    assert mesh_id == hashlib.sha256(depath.arrays_to_off(V, F)).hexdigest()
    from_arrays, from_file = client.mesh_info(mesh_id), client.mesh_info(kitten)
    assert (from_arrays.num_vertices, from_arrays.num_faces) == (len(V), len(F))
    assert from_arrays.num_components == from_file.num_components
    assert from_arrays.bounding_box == from_file.bounding_box  # the server read the same coordinates


def test_array_id_depends_on_values_not_dtypes():
    V, F = grid(5)  # coordinates exact in float32
    base = depath.arrays_to_off(V, F)
    assert depath.arrays_to_off(V.astype(np.float32), F.astype(np.int32)) == base
    assert depath.arrays_to_off(V.tolist(), F.tolist()) == base
    moved = V.copy()
    moved[3, 2] = np.nextafter(0.0, 1.0)  # one ulp: a different mesh
    assert depath.arrays_to_off(moved, F) != base


def test_bytes_go_up_only_when_the_server_lacks_the_mesh(server):
    V, F = grid(9, lambda x, y: 0.1 * np.sin(7 * x + y) + np.random.default_rng().random())  # new to this server
    counter = CountUploads()
    with depath.Client(server.address, interceptors=[counter], timeout=30 * TIME_SCALE) as c:
        mesh_id = c.upload((V, F))
        assert counter.count == 1
        assert c.upload((V, F)) == mesh_id
        assert counter.count == 1
        c.run((V, F), 0, 80, method="fmm")
        assert counter.count == 1
        c.delete_mesh(mesh_id)
        with pytest.raises(depath.NotFound):
            c.mesh_info(mesh_id)
        # Evicted or deleted: run uploads again and succeeds.
        result = c.run((V, F), 0, 80, method="fmm")
        assert counter.count == 2
        assert np.allclose(result.points[0], V[0]) and np.allclose(result.points[-1], V[80])
        c.upload((V, F), force=True)
        assert counter.count == 3


def test_file_and_arrays_give_the_same_result(client, tmp_path):
    V, F = grid(12, lambda x, y: 0.3 * np.sin(3 * x) * np.cos(2 * y))
    obj = tmp_path / "wavy.obj"
    obj.write_text("".join("v %.17g %.17g %.17g\n" % tuple(v) for v in V) +
                   "".join("f %d %d %d\n" % tuple(f + 1) for f in F))
    options = dict(population=10, generations=15, seed=3)
    from_file = client.run(obj, 0, 143, **options)
    from_arrays = client.run((V, F), 0, 143, **options)
    assert from_file.energy == from_arrays.energy
    np.testing.assert_array_equal(from_file.points, from_arrays.points)


def test_mesh_id_is_accepted_in_place_of_a_mesh(client, kitten):
    mesh_id = client.upload(kitten)
    by_id = client.run(mesh_id, 0, 320, method="fmm")
    by_file = client.run(kitten, 0, 320, method="fmm")
    assert by_id.energy == by_file.energy


def test_kitten_from_arrays_matches_the_cli(client, cli, kitten, kitten_arrays, tmp_path):
    """The acceptance scenario: numpy arrays in, (n x 3) numpy path out, energy = `depath solve`'s."""
    ref = tmp_path / "ref.json"
    cli("solve", kitten, "-s", 366, "-t", 230, "--population", 20, "--generations", 30, "--seed", 4, "--out", ref)
    import json
    expected = json.loads(ref.read_text())
    result = client.run(kitten_arrays, source=366, target=230, population=20, generations=30, seed=4)
    assert result.points.shape == (len(expected["points"]), 3)
    assert result.energy == expected["energy"]
    np.testing.assert_array_equal(result.points, np.array(expected["points"]))

