#!/usr/bin/env python3
"""Python client vs the C++ CLI on the same job: same result, and the client-side overhead.

Starts a depathd, then alternates `depath run MESH ...` (a process per run, as a user types it)
and `depath.Client.run(MESH, ...)` (one client, as in a script or notebook) REPEAT times with
the same settings, and reports for each: the energy (must be identical), the wall-clock time,
the server's own solve time (result.seconds) and their difference = everything that is not
solving (process start, mesh hashing/lookup, submit, event streaming, result transfer).

    python3 bench/python_client_overhead.py [--mesh tests/data/kitten.off -s 0 -t 320] [--repeat 5]
(needs the package importable: PYTHONPATH=clients/python, or installed with pip)
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import depath
from depathd_bench import binaries_parser, start_depathd


def main():
    args = binaries_parser(__doc__, source=0, target=320, repeat=5).parse_args()

    work = tempfile.mkdtemp(prefix="depath-overhead-")
    server, port = start_depathd(args.depathd, os.path.join(work, "port"), os.path.join(work, "depathd.log"),
                                 ["--store", "memory"])  # a benchmark writes nothing into the user's state directory
    try:
        address = "127.0.0.1:" + port
        rows = {"cli": [], "python": []}
        with depath.Client(address) as client:
            for i in range(args.repeat):
                out = os.path.join(work, "cli%d.json" % i)
                t0 = time.perf_counter()
                subprocess.run([args.depath, "run", args.mesh, "-s", str(args.source), "-t", str(args.target),
                                "--server", address, "--json", "--out", out], check=True, stdout=subprocess.DEVNULL)
                wall = time.perf_counter() - t0
                ref = json.load(open(out))
                rows["cli"].append((ref["energy"], wall, ref["seconds"]))
                t0 = time.perf_counter()
                res = client.run(args.mesh, args.source, args.target)
                wall = time.perf_counter() - t0
                rows["python"].append((res.energy, wall, res.seconds))
    finally:
        server.terminate()
        server.wait()
    energies = {e for r in rows.values() for e, _, _ in r}
    print("%s %d -> %d, default settings, %d runs each (median; first run of each in brackets)"
          % (os.path.basename(args.mesh), args.source, args.target, args.repeat))
    for name, r in rows.items():
        walls, solves = [w for _, w, _ in r], [s for _, _, s in r]
        over = [w - s for _, w, s in r]
        print("  %-7s energy %.10f  wall %.1f ms  solve %.1f ms  overhead %.1f ms  [first: overhead %.1f ms]"
              % (name, r[0][0], 1e3 * statistics.median(walls), 1e3 * statistics.median(solves),
                 1e3 * statistics.median(over), 1e3 * over[0]))
    print("  energies identical across all runs: %s" % (len(energies) == 1))
    return 0 if len(energies) == 1 else 1


if __name__ == "__main__":
    sys.exit(main())
