#!/usr/bin/env python3
"""Convergence of DE-Path, live from the progress stream: best and mean energy per generation
for the paper's rand1bin and the adaptive SHADE strategy on the same weighted problem.

Saves a plot with matplotlib when it is installed (Debian: python3-matplotlib), else prints
the table.

    depathd --listen 127.0.0.1:50051 &
    python3 convergence_plot.py tests/data/kitten.off --density tests/data/kitten.bumps.density --out conv.png
"""
import argparse

import numpy as np

import depath


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mesh", help="mesh file (any format the server reads)")
    ap.add_argument("--density", help="per-vertex density file, one value per line")
    ap.add_argument("--source", type=int, default=0)
    ap.add_argument("--target", type=int, default=320)
    ap.add_argument("--generations", type=int, default=80)
    ap.add_argument("--population", type=int, default=20)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", default="convergence.png")
    ap.add_argument("--server", default="localhost:50051")
    ap.add_argument("--token")
    args = ap.parse_args()

    density = np.loadtxt(args.density) if args.density else None
    curves = {}
    with depath.Client(args.server, token=args.token) as client:
        for strategy in ("rand1bin", "shade"):
            seen = []
            result = client.run(args.mesh, args.source, args.target, density=density, strategy=strategy,
                                population=args.population, generations=args.generations, seed=args.seed,
                                progress=seen.append)
            curves[strategy] = (np.array([p.generation for p in seen]), np.array([p.best_energy for p in seen]),
                                np.array([p.mean_energy for p in seen]), result)

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        plt = None
    if plt is None:
        print("matplotlib is not installed; the curves as a table:")
        print("%-10s %10s %16s %16s" % ("strategy", "generation", "best energy", "mean energy"))
        for strategy, (gen, best, mean, _) in curves.items():
            for g, b, m in zip(gen, best, mean):
                print("%-10s %10d %16.8f %16.8f" % (strategy, g, b, m))
    else:
        fig, ax = plt.subplots(figsize=(7, 4))
        for strategy, (gen, best, mean, _) in curves.items():
            line, = ax.plot(gen, best, label="%s best" % strategy)
            ax.plot(gen, mean, "--", color=line.get_color(), alpha=0.6, label="%s mean" % strategy)
        fmm = next(iter(curves.values()))[3].fmm_energy
        ax.axhline(fmm, color="gray", lw=0.8, label="fmm baseline")
        ax.set_xlabel("generation")
        ax.set_ylabel("energy")
        ax.set_title("DE-Path convergence, %s %d -> %d" % (args.mesh.rsplit("/", 1)[-1], args.source, args.target))
        ax.legend()
        fig.tight_layout()
        fig.savefig(args.out, dpi=120)
        print("saved %s" % args.out)
    for strategy, (_, _, _, result) in curves.items():
        print("%s: energy %.8f after %d generations (fmm %.8f)" % (strategy, result.energy, result.generations,
                                                                    result.fmm_energy))


if __name__ == "__main__":
    main()
