"""Errors come back as exceptions carrying the gRPC status code and the server's message."""
import grpc
import numpy as np
import pytest

import depath
from conftest import TIME_SCALE, grid

V, F = grid(6)


def raises(kind, code, *words):
    """Context manager: the call raises `kind` with `code` and a message naming `words`."""
    class Check:
        def __enter__(self):
            self.ctx = pytest.raises(kind)
            self.info = self.ctx.__enter__()
            return self.info

        def __exit__(self, *exc):
            handled = self.ctx.__exit__(*exc)
            err = self.info.value
            assert isinstance(err, depath.DepathError) and err.code == code, err
            for w in words:
                assert w.lower() in err.message.lower(), (w, err.message)
            assert code.name in str(err)
            return handled
    return Check()


def test_unknown_mesh_and_job_ids(client):
    with raises(depath.NotFound, grpc.StatusCode.NOT_FOUND):
        client.submit("0" * 64, 0, 1)
    with raises(depath.NotFound, grpc.StatusCode.NOT_FOUND):
        client.mesh_info("f" * 64)
    job = client.job("no-such-job")
    with raises(depath.NotFound, grpc.StatusCode.NOT_FOUND):
        job.info()
    with raises(depath.NotFound, grpc.StatusCode.NOT_FOUND):
        list(job.watch())
    with raises(depath.NotFound, grpc.StatusCode.NOT_FOUND):
        job.cancel()
    with raises(depath.NotFound, grpc.StatusCode.NOT_FOUND):
        job.result()


def test_bad_vertices(client):
    with raises(depath.InvalidArgument, grpc.StatusCode.INVALID_ARGUMENT, "target"):
        client.submit((V, F), 0, 2 ** 40)
    with raises(depath.InvalidArgument, grpc.StatusCode.INVALID_ARGUMENT, "36"):
        client.submit((V, F), 0, 36)
    with raises(depath.InvalidArgument, grpc.StatusCode.INVALID_ARGUMENT):
        client.submit((V, F), 5, 5)
    with raises(depath.InvalidArgument, grpc.StatusCode.INVALID_ARGUMENT):
        client.submit((V, F), -1, 5)


@pytest.mark.parametrize("density,words", [
    (np.ones(35), ["density", "35", "36"]),
    (np.r_[np.ones(35), -1.0], ["density"]),
    (np.r_[np.ones(35), np.nan], ["density"]),
    (np.r_[np.ones(35), np.inf], ["density"]),
], ids=["short", "negative", "nan", "inf"])
def test_bad_densities(client, density, words):
    with raises(depath.InvalidArgument, grpc.StatusCode.INVALID_ARGUMENT, *words):
        client.submit((V, F), 0, 35, density=density)


def test_bad_options(client):
    for options, word in [(dict(population=3), "population"), (dict(generations=0), "generation"),
                          (dict(F=2.5), "F"), (dict(CR=1.5), "CR"),
                          (dict(energy="vector_field", field=np.ones((5, 3))), "field"),
                          (dict(strategy="no-such-strategy"), "strategy")]:
        with raises(depath.InvalidArgument, grpc.StatusCode.INVALID_ARGUMENT, word):
            client.submit((V, F), 0, 35, **options)


def test_bad_options_caught_before_sending(client):
    for options, word in [(dict(energy="geodesik"), "energy"), (dict(method="dijkstra"), "method"),
                          (dict(up="w"), "up"), (dict(density=np.ones((6, 6))), "density"),
                          (dict(field=np.ones(36)), "field"), (dict(seed=-1), "seed"),
                          (dict(generations=2 ** 31), "generations")]:
        with raises(depath.InvalidArgument, grpc.StatusCode.INVALID_ARGUMENT, word):
            client.submit((V, F), 0, 35, **options)


def test_bad_meshes(client, tmp_path):
    garbage = tmp_path / "garbage.off"
    garbage.write_bytes(b"OFF\nthis is not a mesh\n")
    with raises(depath.InvalidArgument, grpc.StatusCode.INVALID_ARGUMENT, "garbage.off"):
        client.upload(garbage)
    unknown = tmp_path / "mesh.xyz"
    unknown.write_text("1 2 3\n")
    with raises(depath.InvalidArgument, grpc.StatusCode.INVALID_ARGUMENT, "xyz"):
        client.upload(unknown)
    with raises(depath.InvalidArgument, grpc.StatusCode.INVALID_ARGUMENT, "missing vertices"):
        client.upload((V, np.r_[F, [[0, 1, 99]]]))
    bad = V.copy()
    bad[4, 1] = np.nan
    with raises(depath.InvalidArgument, grpc.StatusCode.INVALID_ARGUMENT, "vertex 4", "non-finite"):
        client.upload((bad, F))
    with raises(depath.InvalidArgument, grpc.StatusCode.INVALID_ARGUMENT, "(n, 3)"):
        client.upload((V[:, :2], F))
    with raises(depath.InvalidArgument, grpc.StatusCode.INVALID_ARGUMENT, "no-such-file.obj"):
        client.upload(tmp_path / "no-such-file.obj")
    with pytest.raises(TypeError):
        client.upload(42)


def test_disconnected_source_and_target_fail_the_precondition(client):
    two = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 0, 0], [6, 0, 0], [5, 1, 0]], dtype=float)
    faces = np.array([[0, 1, 2], [3, 4, 5]])
    with raises(depath.FailedPrecondition, grpc.StatusCode.FAILED_PRECONDITION):
        client.run((two, faces), 0, 4, method="fmm")


def test_exceptions_are_also_builtin_kinds(client):
    with pytest.raises(ValueError):
        client.submit((V, F), 5, 5)
    with pytest.raises(LookupError):
        client.job("nope").info()


def test_no_server(tmp_path):
    with depath.Client("127.0.0.1:1", timeout=1.0 * TIME_SCALE) as c:
        with pytest.raises((depath.Unavailable, depath.DeadlineExceeded)) as caught:
            c.list_jobs()
    assert isinstance(caught.value, (ConnectionError, TimeoutError))
