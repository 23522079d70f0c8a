#!/usr/bin/env python3
"""Figures of the durable job store (issue 11), measured with the real binaries:
  python3 bench/store_figures.py --build build [--pg-dsn postgresql://...] [--only NAME ...]
checkpoint: size and store write time per checkpoint for N agents x n vertices (SQLite), and
            its cost at the default --checkpoint-seconds 30;
restart:    kill -9 mid-job, restart on the same SQLite store: seconds to the job running again;
size:       the SQLite store's size after 1,000 finished jobs;
replicas:   (needs --pg-dsn) jobs per minute with 1 and 2 replicas, cross-replica watch
            latency, seconds from a replica's kill -9 to its job running on the other."""
import argparse
import json
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time

A = None
TMP = tempfile.mkdtemp(prefix="depath_store_bench_")
SHARED = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "data", "meshes")


def start(args, name):
    pf = os.path.join(TMP, name + ".port")
    log = os.path.join(TMP, name + ".log")
    p = subprocess.Popen([A.depathd, "--listen", "127.0.0.1:0", "--port-file", pf, "--log-format", "json",
                          "--log-level", "debug"] + args, stdout=subprocess.DEVNULL, stderr=open(log, "w"))
    while not (os.path.exists(pf) and open(pf).read().strip()):
        if p.poll() is not None:
            sys.exit("depathd exited: " + open(log).read()[-300:])
        time.sleep(0.01)
    return p, "127.0.0.1:" + open(pf).read().strip(), log


def log_events(log, event):
    out = []
    for line in open(log):
        try:
            e = json.loads(line)
        except ValueError:
            continue
        if e.get("event") == event:
            out.append(e)
    return out


def depath(*args):
    return subprocess.run([A.depath] + list(args), capture_output=True, text=True, timeout=3600)


def submit(addr, mesh, spec):
    r = depath("submit", mesh, *spec, "--server", addr)
    if r.returncode:
        sys.exit("submit: " + r.stderr)
    return r.stdout.strip()


def run_job(mesh, N, gens, interval, name):
    p, addr, log = start(["--data-dir", os.path.join(TMP, name), "--checkpoint-seconds", str(interval),
                          "--threads", "2", "--max-upload-bytes", str(1 << 30), "--max-message-bytes",
                          str(1 << 30)], name)
    job = submit(addr, mesh, ["-s", "1", "-t", "100", "--population", str(N), "--generations", str(gens),
                              "--strategy", "shade"])
    depath("watch", job, "--server", addr)
    p.terminate()
    p.wait()
    done = [e for e in log_events(log, "job.finished") if e.get("job") == job]
    return done[0]["seconds"], log_events(log, "job.checkpointed")


def checkpoint():
    for mesh, n, N, gens in (("dragon.obj", "10,002", 100, 40), ("bunny.off", "34,835", 400, 4)):
        path = os.path.join(SHARED, mesh)
        plain, _ = run_job(path, N, gens, 0, "plain-" + mesh)
        every, ck = run_job(path, N, gens, 0.01, "every-" + mesh)
        size = ck[-1]["bytes"]
        write = sum(e["seconds"] for e in ck) / len(ck)
        per = max(0.0, every - plain) / len(ck)
        print("checkpoint %s: %d agents x %s vertices: %.1f MB (population + archive); store write %.3f s each, "
              "beside the run; job %.1f s without checkpoints, %.1f s with one every generation (%d): %.3f s per "
              "checkpoint for the run = %.2f%% at --checkpoint-seconds 30"
              % (mesh, N, n, size / 1e6, write, plain, every, len(ck), per, 100 * per / 30))


def restart():
    data = os.path.join(TMP, "restart")
    mesh = os.path.join(SHARED, "dragon.obj")
    p, addr, log = start(["--data-dir", data, "--checkpoint-seconds", "1", "--threads", "2"], "r1")
    job = submit(addr, mesh, ["-s", "1", "-t", "1281", "--population", "24", "--generations", "400", "--strategy",
                              "shade", "--seed", "5"])
    w = subprocess.Popen([A.depath, "watch", job, "--json", "--server", addr], stdout=subprocess.PIPE, text=True)
    for line in w.stdout:
        if json.loads(line).get("generation", 0) >= 150:
            break
    p.send_signal(signal.SIGKILL)
    p.wait()
    w.kill()
    t0 = time.time()
    p, addr, log = start(["--data-dir", data, "--checkpoint-seconds", "1", "--threads", "2"], "r2")
    resumed = None
    while resumed is None:
        r = log_events(log, "job.resumed")
        resumed = r[0] if r else None
        time.sleep(0.01)
    ts = resumed["time"]
    t1 = ts if isinstance(ts, (int, float)) else time.time()
    print("restart: kill -9 at generation >= 150, restart on the same SQLite store: job running again %.2f s "
          "after the new process started (resumed from generation %d)" % (t1 - t0, resumed["checkpoint_generation"]))
    depath("watch", job, "--server", addr)
    p.terminate()
    p.wait()


def size():
    data = os.path.join(TMP, "size")
    mesh = os.path.join(SHARED, "kitten.off")
    p, addr, log = start(["--data-dir", data, "--threads", "2", "--max-running-jobs", "2", "--max-queued-jobs",
                          "2000"], "size")
    t0 = time.monotonic()
    jobs = [submit(addr, mesh, ["-s", "0", "-t", "1400", "--population", "8", "--generations", "5", "--seed",
                                str(k), "--request-id", "size-%d" % k] if False else
                   ["-s", "0", "-t", "1400", "--population", "8", "--generations", "5", "--seed", str(k)])
            for k in range(1000)]
    for job in jobs:
        depath("watch", job, "--server", addr)
    took = time.monotonic() - t0
    p.terminate()
    p.wait()
    total = sum(os.path.getsize(os.path.join(data, f)) for f in os.listdir(data))
    print("size: SQLite store after 1,000 finished jobs (kitten, 8 x 5 DE, results of ~%d points): %.1f MB "
          "(%.1f kB per job, mesh included); %.0f jobs/min through one server incl. client start-up"
          % (0, total / 1e6, total / 1e3 / 1000, 1000 / took * 60))


def replicas():
    mesh = os.path.join(SHARED, "kitten.off")
    for n in (1, 2):
        procs = [start(["--store", A.pg_dsn, "--threads", "1", "--max-running-jobs", "1", "--max-queued-jobs",
                        "1000"], "rep%d-%d" % (n, k)) for k in range(n)]
        t0 = time.monotonic()
        jobs = [submit(procs[k % n][1], mesh, ["-s", "0", "-t", "1400", "--population", "16", "--generations", "40",
                                               "--seed", str(k)]) for k in range(60)]
        for job in jobs:
            depath("watch", job, "--server", procs[0][1])
        took = time.monotonic() - t0
        print("replicas: %d replica(s) x 1 thread on PostgreSQL: %.0f jobs/min (60 jobs kitten 16 x 40)" %
              (n, 60 / took * 60))
        for p, _, _ in procs:
            p.terminate()
            p.wait()
    # Watch latency across replicas and takeover time.
    pa, a, la = start(["--store", A.pg_dsn, "--threads", "2", "--lease-seconds", "5", "--checkpoint-seconds", "1"], "wa")
    job = submit(a, os.path.join(SHARED, "dragon.obj"), ["-s", "1", "-t", "1281", "--population", "24",
                                                          "--generations", "2000", "--strategy", "shade"])
    time.sleep(1)
    pb, b, lb = start(["--store", A.pg_dsn, "--threads", "2", "--lease-seconds", "5"], "wb")
    seen = {a: {}, b: {}}

    def follow(addr):
        w = subprocess.Popen([A.depath, "watch", job, "--json", "--server", addr], stdout=subprocess.PIPE, text=True)
        for line in w.stdout:
            e = json.loads(line)
            if "generation" in e and e["generation"] not in seen[addr]:
                seen[addr][e["generation"]] = time.monotonic()
            if len(seen[addr]) > 400:
                break
        w.kill()

    threads = [threading.Thread(target=follow, args=(x,)) for x in (a, b)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    lat = sorted(seen[b][g] - seen[a][g] for g in seen[b] if g in seen[a])
    print("replicas: watch latency on the other replica vs the running one: median %.3f s, max %.3f s over %d "
          "generations both saw" % (lat[len(lat) // 2], lat[-1], len(lat)))
    t0 = time.time()
    pa.send_signal(signal.SIGKILL)
    pa.wait()
    resumed = []
    while not resumed:
        resumed = log_events(lb, "job.resumed")
        time.sleep(0.02)
    print("replicas: kill -9 of the running replica -> job running on the other after %.2f s (--lease-seconds 5)"
          % (time.time() - t0))
    depath("cancel", job, "--server", b)
    pb.terminate()
    pb.wait()


def main():
    global A
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default="build")
    ap.add_argument("--pg-dsn")
    ap.add_argument("--only", nargs="*")
    A = ap.parse_args()
    A.depathd = os.path.join(A.build, "server", "depathd")
    A.depath = os.path.join(A.build, "client", "depath")
    for name, fn in (("checkpoint", checkpoint), ("restart", restart), ("size", size), ("replicas", replicas)):
        if A.only and name not in A.only:
            continue
        if name == "replicas" and not A.pg_dsn:
            print("replicas: skipped (no --pg-dsn)")
            continue
        fn()


if __name__ == "__main__":
    main()
