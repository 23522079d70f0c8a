#!/usr/bin/env python3
"""Weighted geodesic on a mesh given as numpy arrays.

Builds a density that is 5x higher on three Gaussian bumps placed between SOURCE and TARGET
and asks depathd for the path that minimizes the integral of the density (DE-Path seeded with
the density, then local refinement). Prints it next to the classic FMM path on the same density
and the unweighted geodesic, and saves the path as an (n, 3) array.

    depathd --listen 127.0.0.1:50051 &
    python3 weighted_geodesic.py tests/data/kitten.off --source 0 --target 320 --out path.npy
"""
import argparse

import numpy as np

import depath
from mesh_arrays import load


def bumps(V, source, target, height=4.0, width=0.12):
    """1 + height x three Gaussian bumps (sigma = width x bounding-box diagonal), centred on the
    vertices nearest to 1/4, 1/2 and 3/4 of the way from source to target."""
    sigma = width * np.linalg.norm(V.max(axis=0) - V.min(axis=0))
    rho = np.ones(len(V))
    for f in (0.25, 0.5, 0.75):
        c = V[np.argmin(np.linalg.norm(V - ((1 - f) * V[source] + f * V[target]), axis=1))]
        rho += height * np.exp(-np.sum((V - c) ** 2, axis=1) / (2 * sigma ** 2))
    return rho


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mesh", help=".off or .obj file")
    ap.add_argument("--source", type=int, default=0)
    ap.add_argument("--target", type=int, default=320)
    ap.add_argument("--generations", type=int, default=60)
    ap.add_argument("--population", type=int, default=20)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", help="save the weighted path's points here (.npy)")
    ap.add_argument("--server", default="localhost:50051")
    ap.add_argument("--token")
    args = ap.parse_args()

    V, F = load(args.mesh)
    rho = bumps(V, args.source, args.target)
    with depath.Client(args.server, token=args.token) as client:
        plain = client.run((V, F), args.source, args.target, method="fmm")
        weighted = client.run((V, F), args.source, args.target, density=rho, seed_with_problem=True, refine=True,
                              population=args.population, generations=args.generations, seed=args.seed,
                              progress=True)
    print("unweighted geodesic (fmm): length %.6f" % plain.length)
    print("weighted path: energy %.6f (fmm on the same density: %.6f, %.2f%% lower), length %.6f, %d points"
          % (weighted.energy, weighted.fmm_energy, 100 * (1 - weighted.energy / weighted.fmm_energy),
             weighted.length, len(weighted.points)))
    if args.out:
        np.save(args.out, weighted.points)
        print("saved %s: (%d, 3) array, source first" % (args.out, len(weighted.points)))


if __name__ == "__main__":
    main()
