# SPDX-License-Identifier: MIT
"""What the bench scripts that time the real binaries share: their command line (mesh, end
points, repeats, where depathd and depath are) and starting a depathd that reports its port.
"""
import argparse
import os
import subprocess
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def binaries_parser(doc, source, target, repeat):
    """An argument parser with --mesh (kitten), -s/--source, -t/--target, --repeat, --depathd and
    --depath (the build tree's binaries) at the given defaults; the caller adds its own options."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mesh", default=os.path.join(ROOT, "tests", "data", "kitten.off"))
    ap.add_argument("-s", "--source", type=int, default=source)
    ap.add_argument("-t", "--target", type=int, default=target)
    ap.add_argument("--repeat", type=int, default=repeat)
    ap.add_argument("--depathd", default=os.path.join(ROOT, "build", "server", "depathd"))
    ap.add_argument("--depath", default=os.path.join(ROOT, "build", "client", "depath"))
    return ap


def start_depathd(depathd, port_file, log_file, flags=(), timeout=30):
    """Starts `depathd --listen 127.0.0.1:0 --port-file PORT_FILE --threads 2 FLAGS...`, its stderr
    to log_file, and waits for the port; returns (process, port). Exits with the log if depathd
    stops or gives no port within `timeout` seconds (the process is then stopped)."""
    server = subprocess.Popen([depathd, "--listen", "127.0.0.1:0", "--port-file", port_file, "--threads", "2", *flags],
                              stderr=open(log_file, "wb"))
    deadline = time.monotonic() + timeout
    while not (os.path.exists(port_file) and open(port_file).read().strip()):
        if server.poll() is not None or time.monotonic() > deadline:
            server.kill()
            server.wait()
            raise SystemExit("depathd did not start: %s" % open(log_file).read())
        time.sleep(0.02)
    return server, open(port_file).read().strip()
