#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""An installed depathd serves its web page with no --web-root.

Runs `cmake --install BUILD --prefix TMP` (the real install rules), checks the layout
(TMP/bin/depathd, TMP/bin/depath, TMP/share/depath/web/index.html and assets/app.js), starts
TMP/bin/depathd --http-listen on loopback and fetches `/`, `/jobs/ID` and the bundled script:
they must be the installed files byte for byte (not the plain fallback page). Then the same
installed binary with the web files removed answers the fallback page, so the first check
cannot pass by accident. Exit 77 (skipped) when the build has no bundled web view (no node).

  install_test.py --cmake CMAKE --build BUILD_DIR
"""
import argparse
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request

ap = argparse.ArgumentParser()
ap.add_argument("--cmake", required=True)
ap.add_argument("--build", required=True)
ARGS = ap.parse_args()
SCALE = float(os.environ.get("DEPATH_TEST_TIME_SCALE", "1") or 1)

if not os.path.isfile(os.path.join(ARGS.build, "server", "web", "index.html")):
    print("SKIP: the build has no bundled web view (node/npm missing): nothing to install")
    sys.exit(77)

failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def get(url):
    with urllib.request.urlopen(url, timeout=10 * SCALE) as r:
        return r.status, r.read()


def serve(depathd, work):
    """Starts depathd with --http-listen; returns (process, base URL)."""
    for _ in range(5):
        port = free_port()
        proc = subprocess.Popen(
            [depathd, "--listen", "127.0.0.1:0", "--port-file", os.path.join(work, "port"), "--http-listen",
             f"127.0.0.1:{port}", "--store", "memory", "--threads", "1"],
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        base = f"http://127.0.0.1:{port}"
        deadline = time.monotonic() + 20 * SCALE
        while time.monotonic() < deadline and proc.poll() is None:
            try:
                if get(base + "/healthz")[0] == 200:
                    return proc, base
            except OSError:
                time.sleep(0.1)
        proc.kill()
        err = proc.communicate()[1]
        if "in use" not in err:
            raise RuntimeError("depathd did not start: " + err[-500:])
    raise RuntimeError("no free port after 5 attempts")


def stop(proc):
    proc.send_signal(signal.SIGTERM)
    try:
        proc.wait(timeout=15 * SCALE)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
        check(False, "depathd stops on SIGTERM")


work = tempfile.mkdtemp(prefix="depath-install-")
try:
    prefix = os.path.join(work, "prefix")
    r = subprocess.run([ARGS.cmake, "--install", ARGS.build, "--prefix", prefix], capture_output=True, text=True)
    check(r.returncode == 0, "cmake --install into a temporary prefix: " + (r.stderr.strip()[-300:] or "done"))
    depathd = os.path.join(prefix, "bin", "depathd")
    web = os.path.join(prefix, "share", "depath", "web")
    for path in [depathd, os.path.join(prefix, "bin", "depath"), os.path.join(web, "index.html"),
                 os.path.join(web, "assets", "app.js"), os.path.join(web, "assets", "app.css")]:
        check(os.path.isfile(path), "installed " + os.path.relpath(path, prefix))
    check(not os.path.exists(os.path.join(prefix, "bin", "web")), "no web directory beside the installed depathd")

    with open(os.path.join(web, "index.html"), "rb") as f:
        index = f.read()
    with open(os.path.join(web, "assets", "app.js"), "rb") as f:
        app_js = f.read()
    proc, base = serve(depathd, work)
    try:
        status, body = get(base + "/")
        check(status == 200 and body == index, "GET / is the installed index.html (%d bytes)" % len(body))
        status, body = get(base + "/jobs/some-job")
        check(status == 200 and body == index, "GET /jobs/ID is the installed index.html")
        status, body = get(base + "/assets/app.js")
        check(status == 200 and body == app_js, "GET /assets/app.js is the installed bundle (%d bytes)" % len(body))
    finally:
        stop(proc)

    # Without the installed files the same binary falls back to the plain page: the check
    # above saw the installed page because depathd found it, not by chance.
    shutil.rmtree(web)
    proc, base = serve(depathd, work)
    try:
        status, body = get(base + "/")
        check(status == 200 and body != index and b"app.js" not in body,
              "without share/depath/web, GET / is the plain fallback page")
    finally:
        stop(proc)
finally:
    shutil.rmtree(work, ignore_errors=True)

print("%d failure(s)" % len(failures))
sys.exit(1 if failures else 0)
