#!/usr/bin/env python3
"""Figures of depathd under the hostile cases of issue 14, measured with the real binaries:
  python3 bench/hostile_figures.py [--build build] [--only CASE ...] [--scale 1.0]
Each case runs against a fresh depathd (default limits unless the case says otherwise) and
prints the error the client got, the server's resident memory before, at its peak (VmHWM, reset
through /proc/PID/clear_refs before the case) and after, and latencies where they matter:
  mtllib      OBJ files whose mtllib names /dev/urandom and /dev/zero
  population  population 5000 and 1e6 on bunny; generations 2^31-1
  cycles      1500 submit+cancel cycles carrying a bunny-sized density (HTTP API, 4 clients)
  queued      30 queued jobs on distinct ~10 MB meshes (memory store, 21 MB cache budget; and SQLite)
  uploads     6 concurrent ~200 MB uploads (--max-upload-bytes allows 256 MB), with the latency of a
              small upload, a submit on a cached mesh and health while they run; once without the
              upload memory budget (--max-upload-memory-bytes 2^62) and once with its default
  restart     8 concurrent `depath submit` right after a restart on a persisted ~100 MB mesh, with
              health and `depath jobs` latency while the reloads run
--scale shrinks (or grows) the generated meshes (1.0 = the sizes above). Latencies are of the
`depath` CLI (one process per call, so they include its start; the idle figure is printed too).
Not a test: it asserts nothing."""
import argparse
import concurrent.futures as cf
import json
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request

A = None
TMP = tempfile.mkdtemp(prefix="depath_hostile_bench_")
SHARED = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "data", "meshes")
BUNNY = os.path.join(SHARED, "bunny.off")
KITTEN = os.path.join(SHARED, "kitten.off")


class Server:
    started = 0

    def __init__(self, name, args, http=False):
        Server.started += 1
        name = "%s-%d" % (name, Server.started)  # fresh port files: a stale one names a stopped server
        self.name = name
        pf = os.path.join(TMP, name + ".port")
        hf = os.path.join(TMP, name + ".http")
        self.log = os.path.join(TMP, name + ".log")
        extra = ["--http-listen", "127.0.0.1:0", "--http-port-file", hf] if http else []
        self.p = subprocess.Popen([A.depathd, "--listen", "127.0.0.1:0", "--port-file", pf, "--log-level", "warn"] +
                                  extra + args, stdout=subprocess.DEVNULL, stderr=open(self.log, "w"))
        for f in [pf] + ([hf] if http else []):
            while not (os.path.exists(f) and open(f).read().strip()):
                if self.p.poll() is not None:
                    sys.exit("depathd exited: " + open(self.log).read()[-500:])
                time.sleep(0.01)
        self.addr = "127.0.0.1:" + open(pf).read().strip()
        self.http = "http://127.0.0.1:" + open(hf).read().strip() if http else None

    def status(self, key):
        for line in open("/proc/%d/status" % self.p.pid):
            if line.startswith(key + ":"):
                return int(line.split()[1]) // 1024  # MB
        return 0

    def rss(self):
        return self.status("VmRSS")

    def reset_peak(self):
        with open("/proc/%d/clear_refs" % self.p.pid, "w") as f:
            f.write("5")  # resets VmHWM to the current RSS

    def peak(self):
        return self.status("VmHWM")

    def stop(self):
        self.p.terminate()
        try:
            self.p.wait(60)
        except subprocess.TimeoutExpired:
            self.p.kill()
            self.p.wait()


def depath(*args, timeout=600):
    t0 = time.monotonic()
    r = subprocess.run([A.depath] + [str(a) for a in args], capture_output=True, text=True, timeout=timeout)
    return r, time.monotonic() - t0


def first_line(r):
    text = (r.stderr.strip() or r.stdout.strip()).splitlines()
    return text[-1][:220] if text else ""


def outcome(r):
    return ("ok: " + r.stdout.strip().splitlines()[0][:120]) if r.returncode == 0 else "refused: " + first_line(r)


def http_post(url, body, content_type="application/json"):
    data = body if isinstance(body, bytes) else json.dumps(body).encode()
    req = urllib.request.Request(url, data=data, headers={"Content-Type": content_type}, method="POST")
    try:
        with urllib.request.urlopen(req, timeout=600) as resp:
            return resp.status, json.loads(resp.read() or b"{}")
    except urllib.error.HTTPError as e:
        return e.code, json.loads(e.read() or b"{}")


def grid_obj(path, n, tag):
    """An n x n grid as OBJ text; `tag` (a comment) makes the bytes, hence the mesh id, distinct."""
    with open(path, "w") as f:
        f.write("# %s\n" % tag)
        f.write("".join("v %.6f %.6f %.6f\n" % (i / (n - 1), j / (n - 1), 0.1 * ((i * j) % 7) / 7)
                        for j in range(n) for i in range(n)))
        for j in range(n - 1):
            rows = []
            for i in range(n - 1):
                a = j * n + i + 1
                rows.append("f %d %d %d\nf %d %d %d\n" % (a, a + 1, a + n + 1, a, a + n + 1, a + n))
            f.write("".join(rows))
    return path


def grid_for_bytes(target_bytes):
    """Side of a grid whose OBJ text is about target_bytes (about 76 bytes per vertex)."""
    return max(10, int((target_bytes * A.scale / 76) ** 0.5))


def report(case, **fields):
    print(json.dumps(dict(case=case, **fields)), flush=True)


# ---- cases --------------------------------------------------------------------------------

def case_mtllib():
    s = Server("mtllib", ["--store", "memory"])
    try:
        for dev in ("/dev/urandom", "/dev/zero"):
            path = os.path.join(TMP, "mtllib.obj")
            open(path, "w").write("mtllib %s\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n" % dev)
            s.reset_peak()
            before = s.rss()
            r, t = depath("upload", path, "--server", s.addr, timeout=120)
            after_small, t_small = depath("upload", KITTEN, "--server", s.addr, "--force")
            report("mtllib " + dev, result=outcome(r), seconds=round(t, 3), rss_before_mb=before, rss_peak_mb=s.peak(),
                   rss_after_mb=s.rss(), next_upload=outcome(after_small), next_upload_seconds=round(t_small, 3))
    finally:
        s.stop()


def case_population():
    s = Server("population", ["--store", "memory"])
    try:
        depath("upload", BUNNY, "--server", s.addr)
        for label, args in (("population 5000 on bunny", ["--population", 5000, "--generations", 10]),
                            ("population 1e6 on bunny", ["--population", 1000000, "--generations", 10]),
                            ("generations 2^31-1 on bunny", ["--population", 10, "--generations", 2**31 - 1])):
            s.reset_peak()
            before = s.rss()
            r, t = depath("submit", BUNNY, "-s", 0, "-t", 1000, *args, "--server", s.addr)
            if r.returncode == 0:
                depath("cancel", r.stdout.strip(), "--server", s.addr)
            report(label, result=outcome(r), seconds=round(t, 3), rss_before_mb=before, rss_peak_mb=s.peak(),
                   rss_after_mb=s.rss())
    finally:
        s.stop()


def case_cycles(n=1500, clients=4):
    s = Server("cycles", ["--store", "memory"], http=True)
    try:
        mesh = depath("upload", BUNNY, "--server", s.addr)[0].stdout.split()[0]
        density = [1.5] * 34835
        errors = {}
        lock = threading.Lock()
        s.reset_peak()
        before = s.rss()

        def cycle(i):
            code, body = http_post(s.http + "/v1/jobs", {"mesh_id": mesh, "source": 0, "target": 1000,
                                                        "density": density, "generations": 100000, "seed": i})
            if code == 200:
                http_post(s.http + "/v1/jobs/%s/cancel" % body["id"], b"", "text/plain")
            else:
                with lock:
                    key = "%d %s" % (code, str(body.get("error", body))[:120])
                    errors[key] = errors.get(key, 0) + 1

        t0 = time.monotonic()
        with cf.ThreadPoolExecutor(clients) as pool:
            list(pool.map(cycle, range(n)))
        report("%d submit+cancel cycles, bunny-sized density" % n, seconds=round(time.monotonic() - t0, 1),
               refused=errors, rss_before_mb=before, rss_peak_mb=s.peak(), rss_after_mb=s.rss())
    finally:
        s.stop()


def case_queued(count=30):
    side = grid_for_bytes(10e6 * 76 / 292)  # ~10 MB in memory (the figure): ~292 bytes a vertex
    paths = [grid_obj(os.path.join(TMP, "q%d.obj" % k), side, "queued %d" % k) for k in range(count)]
    for label, args in (("memory store, --mesh-cache-bytes 21 MB", ["--store", "memory"]),
                        ("SQLite store, --mesh-cache-bytes 21 MB", ["--data-dir", os.path.join(TMP, "queued-db")])):
        s = Server("queued", args + ["--mesh-cache-bytes", str(21 << 20), "--max-running-jobs", "1"], http=True)
        try:
            for p in paths:
                depath("upload", p, "--server", s.addr)
            s.reset_peak()
            before = s.rss()
            outcomes = {}
            for p in paths:
                r, _ = depath("submit", p, "-s", 0, "-t", side * side - 1, "--generations", 1000000, "--population",
                              8, "--server", s.addr)
                key = "accepted" if r.returncode == 0 else first_line(r)[:160]
                outcomes[key] = outcomes.get(key, 0) + 1
            if s.p.poll() is not None:
                report("queued (%s)" % label, submits=outcomes, depathd_exited=s.p.returncode,
                       log=open(s.log).read()[-2000:])
                continue
            metrics = urllib.request.urlopen(s.http + "/metrics", timeout=60).read().decode()
            mem = next((float(l.split()[-1]) for l in metrics.splitlines()
                        if l.startswith("depath_mesh_cache_bytes ")), None)
            report("%d queued jobs on distinct %d-vertex meshes (%s)" % (count, side * side, label), submits=outcomes,
                   cache_bytes_mb=round(mem / 2**20, 1) if mem else mem, rss_before_mb=before,
                   rss_peak_mb=s.peak(), rss_after_mb=s.rss())
        finally:
            s.stop()


def concurrently(calls, probe):
    """Runs `calls` (functions returning depath()'s (result, seconds)) at once while probe(stop)
    runs in a thread; returns their results and the seconds until the last one ended."""
    stop = threading.Event()
    th = threading.Thread(target=probe, args=(stop,))
    th.start()
    t0 = time.monotonic()
    with cf.ThreadPoolExecutor(len(calls)) as pool:
        results = list(pool.map(lambda call: call(), calls))
    took = time.monotonic() - t0
    stop.set()
    th.join()
    return results, took


def tally(results):
    outcomes = {}
    for r, _ in results:
        key = "ok" if r.returncode == 0 else first_line(r)[:160]
        outcomes[key] = outcomes.get(key, 0) + 1
    return outcomes


def latency_probe(s, stop, out):
    """Health, a small upload and a submit on a cached mesh, in turn, until `stop` is set."""
    while not stop.is_set():
        for what, args in (("health", ["health"]), ("upload", ["upload", KITTEN, "--force"]),
                           ("submit", ["submit", KITTEN, "-s", 366, "-t", 230, "--method", "fmm"])):
            r, t = depath(*args, "--server", s.addr, timeout=600)
            out.setdefault(what, []).append((t, r.returncode))
            if stop.is_set():
                break


def summary(samples):
    if not samples:
        return None
    ts = sorted(t for t, _ in samples)
    return {"n": len(ts), "median_s": round(ts[len(ts) // 2], 3), "max_s": round(ts[-1], 3),
            "failed": sum(1 for _, rc in samples if rc)}


def case_uploads(count=6):
    side = grid_for_bytes(200e6)
    paths = [grid_obj(os.path.join(TMP, "big%d.obj" % k), side, "big %d" % k) for k in range(count)]
    size_mb = os.path.getsize(paths[0]) // 2**20
    # Without the memory budget (as before it existed: a budget nothing reaches), then with its default.
    for label, extra in (("--max-upload-memory-bytes 2^62, i.e. unbounded", ["--max-upload-memory-bytes", str(1 << 62)]),
                         ("default --max-upload-memory-bytes", [])):
        s = Server("uploads", ["--store", "memory", "--max-upload-bytes", str(256 << 20)] + extra)
        try:
            depath("upload", KITTEN, "--server", s.addr)
            idle = {}
            for _ in range(3):
                for what, args in (("health", ["health"]), ("upload", ["upload", KITTEN, "--force"]),
                                   ("submit", ["submit", KITTEN, "-s", 366, "-t", 230, "--method", "fmm"])):
                    r, t = depath(*args, "--server", s.addr)
                    idle.setdefault(what, []).append((t, r.returncode))
            s.reset_peak()
            before = s.rss()
            during = {}
            results, took = concurrently([lambda p=p: depath("upload", p, "--server", s.addr, timeout=1200)
                                          for p in paths], lambda stop: latency_probe(s, stop, during))
            report("%d concurrent %d MB uploads (%d vertices each), %s" % (count, size_mb, side * side, label),
                   uploads=tally(results), seconds=round(took, 1), rss_before_mb=before, rss_peak_mb=s.peak(),
                   rss_after_mb=s.rss(), idle={k: summary(v) for k, v in idle.items()},
                   during={k: summary(v) for k, v in during.items()})
        finally:
            s.stop()


def case_restart(count=8):
    side = grid_for_bytes(100e6)
    path = grid_obj(os.path.join(TMP, "persisted.obj"), side, "persisted")
    size_mb = os.path.getsize(path) // 2**20
    data = os.path.join(TMP, "restart-db")
    args = ["--data-dir", data, "--max-upload-bytes", str(256 << 20), "--max-running-jobs", "1"]
    s = Server("restart1", args)
    r, _ = depath("upload", path, "--server", s.addr)
    s.stop()
    if r.returncode:
        report("restart", error=first_line(r))
        return
    s = Server("restart2", args)
    try:
        idle = [depath("health", "--server", s.addr)[1] for _ in range(5)]
        s.reset_peak()
        before = s.rss()
        probes = {"health": [], "jobs": []}

        def probe(stop):
            while not stop.is_set():
                for what in ("health", "jobs"):
                    r, t = depath(what, "--server", s.addr)
                    probes[what].append((t, r.returncode))
                time.sleep(0.05)

        results, took = concurrently([lambda i=i: depath("submit", path, "-s", 0, "-t", side - 1, "--method", "fmm",
                                                         "--seed", i, "--server", s.addr, timeout=1200)
                                      for i in range(count)], probe)
        outcomes = tally(results)
        for r, _ in results:
            if r.returncode == 0:
                depath("cancel", r.stdout.strip(), "--server", s.addr)
        report("%d submits right after a restart on a persisted %d MB mesh (%d vertices)" % (count, size_mb, side * side),
               submits=outcomes, submit_seconds=sorted(round(t, 2) for _, t in results), all_done_seconds=round(took, 2),
               health_idle_max_s=round(max(idle), 3), health_during=summary(probes["health"]),
               jobs_during=summary(probes["jobs"]), rss_before_mb=before, rss_peak_mb=s.peak(), rss_after_mb=s.rss())
    finally:
        s.stop()


CASES = {"mtllib": case_mtllib, "population": case_population, "cycles": case_cycles, "queued": case_queued,
         "uploads": case_uploads, "restart": case_restart}


def main():
    global A
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "build"))
    ap.add_argument("--only", nargs="*", choices=sorted(CASES), default=None)
    ap.add_argument("--scale", type=float, default=1.0, help="size factor of the generated meshes")
    A = ap.parse_args()
    A.depathd = os.path.join(A.build, "server", "depathd")
    A.depath = os.path.join(A.build, "client", "depath")
    try:
        for name in A.only or list(CASES):
            CASES[name]()
    finally:
        shutil.rmtree(TMP, ignore_errors=True)


if __name__ == "__main__":
    main()
