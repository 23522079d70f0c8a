#!/usr/bin/env python3
"""A path that follows a vector field, on a terrain built with numpy.

The terrain is MATLAB's `peaks` on an n x n grid; the field is its height gradient turned by
90 degrees in the xy-plane, i.e. the direction of the contour lines, given per vertex as an
(n*n, 3) array (the server projects it onto each face). DE-Path looks for the path between
two corners whose direction deviates least from the field lines (energy: integral of the
acute angle). The same run with the server's own generator (field_from_height, rotate=90)
is shown beside it.

    depathd --listen 127.0.0.1:50051 &
    python3 vector_field_path.py --n 41 --generations 60
"""
import argparse

import numpy as np

import depath


def peaks_grid(n):
    """Vertices (n*n, 3) of z = peaks(x, y) / 4 over [-3, 3]^2, triangles (2 (n-1)^2, 3), and the
    height gradient (dz/dx, dz/dy) per vertex."""
    x, y = np.meshgrid(np.linspace(-3, 3, n), np.linspace(-3, 3, n))
    z = (3 * (1 - x) ** 2 * np.exp(-x ** 2 - (y + 1) ** 2) - 10 * (x / 5 - x ** 3 - y ** 5) * np.exp(-x ** 2 - y ** 2)
         - np.exp(-(x + 1) ** 2 - y ** 2) / 3) / 4
    step = 6 / (n - 1)
    dz_dy, dz_dx = np.gradient(z, step)
    V = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    a = (np.arange(n - 1)[None, :] + n * np.arange(n - 1)[:, None]).ravel()
    F = np.concatenate([np.column_stack([a, a + 1, a + n + 1]), np.column_stack([a, a + n + 1, a + n])])
    return V, F, np.column_stack([dz_dx.ravel(), dz_dy.ravel()])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=41, help="grid size (n x n vertices)")
    ap.add_argument("--generations", type=int, default=60)
    ap.add_argument("--population", type=int, default=20)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--server", default="localhost:50051")
    ap.add_argument("--token")
    args = ap.parse_args()

    V, F, grad = peaks_grid(args.n)
    contour = np.column_stack([-grad[:, 1], grad[:, 0], np.zeros(len(V))])  # gradient turned by 90 degrees
    source, target = 0, args.n * args.n - 1
    options = dict(energy="vector_field", refine=True, population=args.population, generations=args.generations,
                   seed=args.seed)
    with depath.Client(args.server, token=args.token) as client:
        given = client.run((V, F), source, target, field=contour, progress=True, **options)
        generated = client.run((V, F), source, target, field_from_height=True, rotate=90, **options)
    for name, r in (("field from numpy", given), ("field_from_height, rotate 90", generated)):
        print("%-30s energy %.5f (fmm path: %.5f), mean angle to the field %.2f deg, length %.3f, %d points"
              % (name, r.energy, r.fmm_energy, np.degrees(r.metrics["normalized_energy"]), r.length, len(r.points)))


if __name__ == "__main__":
    main()
