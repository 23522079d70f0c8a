"""Every energy and method through the client gives exactly what `depath solve` gives (one engine,
same seed), and the numbers obey the geometry: exact references, analytic identities."""
import itertools
import json

import numpy as np
import pytest

from conftest import REPO, grid

DATA = REPO / "tests" / "data"
KITTEN, TERRAIN, CONE = DATA / "kitten.off", DATA / "terrain_grid30.obj", DATA / "cone.off"
_counter = itertools.count()


def terrain_field():
    """A per-vertex field on the 30 x 30 terrain: a swirl around its centre plus a drift."""
    V = np.array([l.split()[1:4] for l in TERRAIN.read_text().splitlines() if l.startswith("v ")], dtype=float)
    return np.column_stack([-V[:, 1] + 3.0, V[:, 0], np.zeros(len(V))])


def write_rows(path, rows):
    np.savetxt(path, rows, fmt="%.17g")
    return path


# (id, mesh, source, target, client keyword arguments, `depath solve` flags); arrays given to the
# client are written to files for the CLI (17 significant digits: the same doubles).
CASES = [
    ("geodesic-de", KITTEN, 0, 320, dict(population=12, generations=15, seed=7), []),
    ("geodesic-density-seeded-refined", KITTEN, 0, 320,
     dict(density=np.loadtxt(DATA / "kitten.bumps.density"), seed_with_problem=True, refine=True, population=10,
          generations=8, seed=2), ["--density", DATA / "kitten.bumps.density"]),
    ("geodesic-fmm", KITTEN, 366, 230, dict(method="fmm"), []),
    ("geodesic-descent-refine", KITTEN, 366, 230, dict(method="descent", refine=True), []),
    ("geodesic-smoothness-shade", KITTEN, 465, 969,
     dict(smoothness=0.5, strategy="shade", population=10, generations=12, stall=5, seed=9), []),
    ("geodesic-F-CR", CONE, 0, 600, dict(F=0.7, CR=0.3, population=8, generations=10, seed=11), []),
    ("vector-field-given", TERRAIN, 0, 899, dict(energy="vector_field", field=terrain_field(), population=10,
                                                 generations=10, seed=5), ["--field", "FIELD"]),
    ("vector-field-from-height-rotated", TERRAIN, 31, 868,
     dict(energy="vector_field", field_from_height=True, rotate=45.0, population=10, generations=10, seed=6), []),
    ("constant-slope-cone-up-y", CONE, 10, 700,
     dict(energy="constant_slope", slope=0.4, up="y", population=10, generations=10, seed=8), []),
]

FLAGS = {"energy": "--energy", "method": "--method", "population": "--population", "generations": "--generations",
         "stall": "--stall", "seed": "--seed", "F": "--F", "CR": "--CR", "strategy": "--strategy",
         "smoothness": "--smoothness", "rotate": "--rotate", "slope": "--slope", "up": "--up"}
SWITCHES = {"refine": "--refine", "seed_with_problem": "--seed-with-problem",
            "field_from_height": "--field-from-height"}


def cli_flags(options, extra, tmp_path):
    flags = []
    for key, value in options.items():
        if key in FLAGS:
            flags += [FLAGS[key], value]
        elif key in SWITCHES:
            flags += [SWITCHES[key]] if value else []
    for item in extra:
        flags.append(write_rows(tmp_path / "field.txt", options["field"]) if item == "FIELD" else item)
    return flags


def solve(cli, tmp_path, mesh, source, target, flags):
    out = tmp_path / ("ref%d.json" % next(_counter))
    cli("solve", mesh, "-s", source, "-t", target, "--threads", 2, *flags, "--out", out)
    return json.loads(out.read_text())


@pytest.mark.parametrize("name,mesh,source,target,options,extra", CASES, ids=[c[0] for c in CASES])
def test_same_result_as_depath_solve(client, cli, tmp_path, name, mesh, source, target, options, extra):
    ref = solve(cli, tmp_path, mesh, source, target, cli_flags(options, extra, tmp_path))
    res = client.run(mesh, source, target, **options)
    assert res.energy == ref["energy"]
    assert res.length == ref["length"]
    assert res.fmm_energy == ref["fmm_energy"]
    assert (res.method, res.refined, res.generations, res.evaluations, res.stop_reason) == (
        ref["method"], ref["refined"], ref["generations"], ref["evaluations"], ref["stop_reason"])
    assert res.metrics == ref["metrics"]
    np.testing.assert_array_equal(res.points, np.array(ref["points"]))
    expected = [(c["vertex"], -1) if "vertex" in c else tuple(c["edge"]) for c in ref["crossings"]]
    assert list(zip(res.crossings.v0.tolist(), res.crossings.v1.tolist())) == expected
    np.testing.assert_array_equal(res.crossings.t[~res.crossings.is_vertex],
                                  [c["t"] for c in ref["crossings"] if "edge" in c])
    assert len(res.path.segment_faces) == len(res.points) - 1


def test_points_lie_where_the_crossings_say(client, kitten_arrays):
    V, F = kitten_arrays
    res = client.run((V, F), 0, 320, density=np.loadtxt(DATA / "kitten.bumps.density"), population=8,
                     generations=5, seed=1)
    c = res.crossings
    rebuilt = np.where(c.is_vertex[:, None], V[c.v0], (1 - c.t)[:, None] * V[c.v0] + c.t[:, None] * V[c.v1])
    # The server parses coordinates as the file format's reader does; allow float32 rounding.
    np.testing.assert_allclose(res.points, rebuilt, rtol=0, atol=1e-5)
    assert c[0] == (0, -1, 0.0) and c[len(c) - 1] == (320, -1, 0.0)
    assert np.all((c.t >= 0) & (c.t <= 1))
    assert res.length == pytest.approx(np.linalg.norm(np.diff(res.points, axis=0), axis=1).sum(), rel=1e-12)


def test_unit_density_energy_is_length_and_density_scales_it(client):
    V, F = grid(11)
    one = client.run((V, F), 0, 120, method="fmm")
    two = client.run((V, F), 0, 120, method="fmm", density=np.full(len(V), 2.0))
    assert one.energy == pytest.approx(one.length, rel=1e-12)
    assert two.energy == pytest.approx(2 * one.energy, rel=1e-12)
    np.testing.assert_array_equal(one.points, two.points)
    # The diagonal of the unit square is an edge path of this triangulation: the geodesic is straight.
    assert one.length == pytest.approx(np.sqrt(2), rel=1e-9)


def test_kitten_geodesic_against_the_exact_distance(client):
    """Exact polyhedral geodesic kitten 0 -> 320 (shared truth table, CGAL): 59.1160524045."""
    exact = 59.1160524045
    res = client.run(KITTEN, 0, 320, method="descent", refine=True)
    assert exact * (1 - 1e-9) <= res.length <= exact * 1.01
    assert res.energy <= res.fmm_energy


def test_weighted_kitten_below_the_steiner_bound(client):
    """Bump density kitten 0 -> 320: the 16-Steiner-point path costs 62.1940255443 (an upper bound;
    the optimum lies a little below). The refined, problem-seeded DE path is within 2% of it."""
    res = client.run(KITTEN, 0, 320, density=np.loadtxt(DATA / "kitten.bumps.density"), seed_with_problem=True,
                     refine=True, population=10, generations=20, seed=3)
    assert res.energy <= res.fmm_energy
    assert 62.1940255443 * 0.97 <= res.energy <= 62.1940255443 * 1.02


def test_vector_field_along_a_straight_field_line_costs_nothing(client):
    """A flat grid, field (1, 0, 0) everywhere, source and target on one grid row: the straight
    row follows the field, energy 0 (and normalized energy 0); DE + local refinement finds it."""
    V, F = grid(9)
    res = client.run((V, F), 9 * 4, 9 * 4 + 8, energy="vector_field", field=np.tile([1.0, 0, 0], (len(V), 1)),
                     refine=True, population=8, generations=10, seed=1)
    assert res.energy == pytest.approx(0, abs=1e-9)
    assert res.length == pytest.approx(1, rel=1e-9)
    assert res.metrics.get("normalized_energy") == pytest.approx(0, abs=1e-9)
