#!/usr/bin/env python3
"""What TLS and mutual TLS cost against plaintext, side by side in one run.

Makes a CA and certificates with openssl, starts three depathd (plaintext, TLS, mutual TLS; store
`memory`, 2 threads) and measures, interleaving the three so that load on the machine hits all alike:

- `depath run MESH -s S -t T --generations G` wall time (a process per run, as a user types it:
  connect + handshake + mesh lookup/upload + submit + watch + result), median of --repeat;
- `depath health` wall time (process start, connect, handshake, one call), median of --repeat * 3;
- connection set-up: a new channel and one health call, in-process (Python grpcio, the same gRPC C
  core), median of 50;
- per call on an established connection: 500 ListJobs calls, mean.

    python3 bench/tls_overhead.py [--mesh tests/data/kitten.off -s 366 -t 230 --generations 10] [--repeat 7]
(Debian's python3 with python3-grpcio; the mesh is uploaded by the first run, later runs find it)
"""
import os
import shutil
import statistics
import subprocess
import tempfile
import time

import grpc

from depathd_bench import binaries_parser, start_depathd

HEALTH = "/grpc.health.v1.Health/Check"
LIST_JOBS = "/depath.v1.JobService/ListJobs"


def openssl(work, *args):
    subprocess.run(["openssl", *args], cwd=work, check=True, capture_output=True)


def make_certs(work):
    openssl(work, "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-keyout", "ca.key", "-out", "ca.pem", "-days", "2",
            "-subj", "/CN=bench-ca")
    with open(os.path.join(work, "san.ext"), "w") as f:
        f.write("subjectAltName=DNS:localhost,IP:127.0.0.1\n")
    for name in ("server", "client"):
        openssl(work, "req", "-newkey", "rsa:2048", "-nodes", "-keyout", name + ".key", "-out", name + ".csr", "-subj",
                "/CN=" + name)
        openssl(work, "x509", "-req", "-in", name + ".csr", "-CA", "ca.pem", "-CAkey", "ca.key", "-CAcreateserial",
                "-out", name + ".pem", "-days", "2", "-extfile", "san.ext")


def main():
    ap = binaries_parser(__doc__, source=366, target=230, repeat=7)
    ap.add_argument("--generations", type=int, default=10)
    args = ap.parse_args()

    work = tempfile.mkdtemp(prefix="depath-tls-bench-")
    p = lambda name: os.path.join(work, name)  # noqa: E731
    make_certs(work)
    modes = {
        "plaintext": ([], []),
        "tls": (["--tls-cert", p("server.pem"), "--tls-key", p("server.key")], ["--tls-ca", p("ca.pem")]),
        "mutual tls": (["--tls-cert", p("server.pem"), "--tls-key", p("server.key"), "--tls-client-ca", p("ca.pem")],
                       ["--tls-ca", p("ca.pem"), "--tls-cert", p("client.pem"), "--tls-key", p("client.key")]),
    }
    servers, address = {}, {}
    try:
        for i, (mode, (server_flags, _)) in enumerate(modes.items()):
            servers[mode], port = start_depathd(args.depathd, p("port%d" % i), p("log%d" % i),
                                                ["--store", "memory", "--log-level", "warn", *server_flags])
            address[mode] = "localhost:" + port

        def cli(mode, *command):
            start = time.perf_counter()
            subprocess.run([args.depath, *command, "--server", address[mode], *modes[mode][1]], check=True,
                           capture_output=True)
            return time.perf_counter() - start

        run = ["run", args.mesh, "-s", str(args.source), "-t", str(args.target), "--generations", str(args.generations),
               "--out", p("path.json")]
        for mode in modes:
            cli(mode, *run)  # uploads the mesh once; warms caches
        runs = {m: [] for m in modes}
        health = {m: [] for m in modes}
        for _ in range(args.repeat):
            for mode in modes:
                runs[mode].append(cli(mode, *run))
            for _ in range(3):
                for mode in modes:
                    health[mode].append(cli(mode, "health"))

        def channel(mode):
            if mode == "plaintext":
                return grpc.insecure_channel(address[mode])
            read = lambda n: open(p(n), "rb").read()  # noqa: E731
            creds = grpc.ssl_channel_credentials(read("ca.pem"), read("client.key") if mode == "mutual tls" else None,
                                                 read("client.pem") if mode == "mutual tls" else None)
            return grpc.secure_channel(address[mode], creds)

        def call(ch, method):
            ch.unary_unary(method, request_serializer=lambda x: x, response_deserializer=lambda x: x)(b"", timeout=30)

        connect = {m: [] for m in modes}
        per_call = {}
        for _ in range(50):
            for mode in modes:
                start = time.perf_counter()
                ch = channel(mode)
                call(ch, HEALTH)
                connect[mode].append(time.perf_counter() - start)
                ch.close()
        for mode in modes:
            ch = channel(mode)
            for _ in range(50):
                call(ch, LIST_JOBS)
            start = time.perf_counter()
            for _ in range(500):
                call(ch, LIST_JOBS)
            per_call[mode] = (time.perf_counter() - start) / 500
            ch.close()

        med = statistics.median
        print("| mode | `depath run` (median of %d) | `depath health` (median of %d) | new connection + 1 call "
              "(median of 50) | call on an open connection (mean of 500) |" % (args.repeat, args.repeat * 3))
        print("| --- | --- | --- | --- | --- |")
        for mode in modes:
            print("| %s | %.1f ms | %.1f ms | %.2f ms | %.0f us |" % (
                mode, med(runs[mode]) * 1e3, med(health[mode]) * 1e3, med(connect[mode]) * 1e3, per_call[mode] * 1e6))
        base = "plaintext"
        for mode in ("tls", "mutual tls"):
            print("%s - plaintext: run %+.1f ms, health %+.1f ms, connection %+.2f ms, per call %+.0f us" % (
                mode, (med(runs[mode]) - med(runs[base])) * 1e3, (med(health[mode]) - med(health[base])) * 1e3,
                (med(connect[mode]) - med(connect[base])) * 1e3, (per_call[mode] - per_call[base]) * 1e6))
    finally:
        for s in servers.values():
            s.terminate()
            s.wait()
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
