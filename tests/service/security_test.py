#!/usr/bin/env python3
"""Transport security, tokens and per-client limits of the real depathd, driven by the real `depath`
client and by raw gRPC calls (Debian's python3-grpcio), with real certificates made here by openssl.

Checked: TLS (a plaintext client and a client that does not trust the CA are refused); mutual TLS
(plaintext, certificate-less and foreign-CA clients refused; `depath run` over it gives a path);
a certificate reload without restart (a second CA's certificate is served once the files change);
bad TLS files are refused at start with a message naming the flag; several tokens from
--auth-token (repeated), --auth-token-file and DEPATHD_AUTH_TOKENS, the client's --token,
--token-file and DEPATH_TOKEN; failed attempts logged with method and peer and never the token;
failed attempts limited per peer (RESOURCE_EXHAUSTED even for the right token, health exempt,
served again after the refill time); reflection answers nothing without a token; quotas
--max-jobs-per-client, --max-requests-per-second-per-client and --max-concurrent-uploads refuse
with RESOURCE_EXHAUSTED naming the flag; --max-upload-memory-bytes bounds gRPC and HTTP uploads
together (refused naming the flag and figures, room given back after success, failure, cancel
and a dropped connection).

Liveness bounds derive from the configured intervals and are scaled by DEPATH_TEST_TIME_SCALE."""
import argparse
import http.client
import json
import os
import select
import shutil
import socket
import subprocess
import sys
import tempfile
import threading
import time
import urllib.error
import urllib.request

import grpc

SCALE = float(os.environ.get("DEPATH_TEST_TIME_SCALE", "1"))
ARGS = None
WORK = None
HEALTH = "/grpc.health.v1.Health/Check"
LIST_JOBS = "/depath.v1.JobService/ListJobs"
UPLOAD = "/depath.v1.MeshService/UploadMesh"
REFLECTION = "/grpc.reflection.v1alpha.ServerReflection/ServerReflectionInfo"
SERVING = b"\x08\x01"  # HealthCheckResponse{status: SERVING}


def check(cond, message):
    if not cond:
        raise AssertionError(message)


def openssl(*args):
    subprocess.run(["openssl", *args], cwd=WORK, check=True, capture_output=True)


def make_ca(name):
    openssl("req", "-x509", "-newkey", "rsa:2048", "-nodes", "-keyout", name + ".key", "-out", name + ".pem",
            "-days", "2", "-subj", "/CN=" + name)


def make_cert(name, ca):
    """A certificate for DNS:localhost / IP:127.0.0.1 signed by `ca`."""
    openssl("req", "-newkey", "rsa:2048", "-nodes", "-keyout", name + ".key", "-out", name + ".csr", "-subj", "/CN=" + name)
    with open(os.path.join(WORK, "san.ext"), "w") as f:
        f.write("subjectAltName=DNS:localhost,IP:127.0.0.1\n")
    openssl("x509", "-req", "-in", name + ".csr", "-CA", ca + ".pem", "-CAkey", ca + ".key", "-CAcreateserial",
            "-out", name + ".pem", "-days", "2", "-extfile", "san.ext")


def path(name):
    return os.path.join(WORK, name)


def read(name):
    with open(path(name), "rb") as f:
        return f.read()


class Server:
    def __init__(self, *flags, env=None):
        self.port_file = path("port")
        if os.path.exists(self.port_file):
            os.remove(self.port_file)
        self.log_path = path("depathd-%d.log" % time.monotonic_ns())
        self.log = open(self.log_path, "w")
        self.proc = subprocess.Popen([ARGS.depathd, "--store", "memory", "--listen", "127.0.0.1:0", "--port-file",
                                      self.port_file, "--max-running-jobs", "1", *map(str, flags)],
                                     stdout=self.log, stderr=subprocess.STDOUT, env={**os.environ, **(env or {})})
        deadline = time.monotonic() + 30 * SCALE
        while not os.path.exists(self.port_file):
            check(self.proc.poll() is None, "depathd exited: " + self.log_text())
            check(time.monotonic() < deadline, "depathd did not start")
            time.sleep(0.05)
        with open(self.port_file) as f:
            self.port = int(f.read())
        self.address = "localhost:%d" % self.port

    def log_text(self):
        self.log.flush()
        with open(self.log_path) as f:
            return f.read()

    def stop(self):
        self.proc.terminate()
        try:
            self.proc.wait(timeout=30 * SCALE)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        self.log.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop()


def depath(*args, env=None):
    return subprocess.run([ARGS.depath, *map(str, args)], capture_output=True, text=True,
                          env={**os.environ, **(env or {})}, timeout=120 * SCALE)


def channel(server, ca=None, cert=None, key=None):
    if ca is None:
        return grpc.insecure_channel("127.0.0.1:%d" % server.port)
    creds = grpc.ssl_channel_credentials(root_certificates=read(ca), private_key=key and read(key),
                                         certificate_chain=cert and read(cert))
    return grpc.secure_channel("localhost:%d" % server.port, creds)


def raw_call(chan, method, request=b"", token=None, timeout=None):
    """A unary call with raw bytes; returns (status code, details, reply bytes)."""
    call = chan.unary_unary(method, request_serializer=lambda x: x, response_deserializer=lambda x: x)
    metadata = (("authorization", "Bearer " + token),) if token else None
    try:
        return grpc.StatusCode.OK, "", call(request, metadata=metadata, timeout=timeout or 10 * SCALE)
    except grpc.RpcError as e:
        return e.code(), e.details(), None


def refused(chan, what):
    code, details, _ = raw_call(chan, HEALTH, timeout=5 * SCALE)
    check(code == grpc.StatusCode.UNAVAILABLE, "%s was served: %s %s" % (what, code, details))


def served(chan, what):
    code, details, reply = raw_call(chan, HEALTH, timeout=10 * SCALE)
    check(code == grpc.StatusCode.OK and reply == SERVING, "%s was not served: %s %s" % (what, code, details))


# ---- TLS ----------------------------------------------------------------------------------------

def test_tls():
    with Server("--tls-cert", path("server.pem"), "--tls-key", path("server.key")) as s:
        check("tls=tls" in s.log_text(), "start log does not say tls: " + s.log_text())
        served(channel(s, "ca.pem"), "a TLS client trusting the CA")
        refused(channel(s), "a plaintext client")
        refused(channel(s, "other-ca.pem"), "a TLS client not trusting the server's CA")
        r = depath("health", "--server", s.address, "--tls-ca", path("ca.pem"))
        check(r.returncode == 0 and "SERVING" in r.stdout, "depath health over TLS: " + r.stdout + r.stderr)
        r = depath("health", "--server", s.address, env={"DEPATH_TLS_CA": path("ca.pem")})
        check(r.returncode == 0, "DEPATH_TLS_CA not used: " + r.stderr)
        r = depath("health", "--server", s.address)
        check(r.returncode != 0, "depath health in plaintext against a TLS server succeeded")
        # The certificate names localhost and 127.0.0.1, not "depathd": a name check that must fail...
        r = depath("health", "--server", s.address, "--tls-ca", path("ca.pem"), "--tls-server-name", "depathd")
        check(r.returncode != 0, "a certificate was accepted for a name it does not hold")


def test_health_port():
    """--health-listen: plaintext, the health service only, while the main port needs mutual TLS."""
    import re
    with Server("--tls-cert", path("server.pem"), "--tls-key", path("server.key"), "--tls-client-ca", path("ca.pem"),
                "--auth-token", "right-token", "--health-listen", "127.0.0.1:0") as s:
        found = re.search(r"health_port=(\d+)", s.log_text())
        check(found and int(found.group(1)) not in (0, s.port), "no health port in the log: " + s.log_text())
        health = grpc.insecure_channel("127.0.0.1:" + found.group(1))
        served(health, "plaintext health on --health-listen")
        code, details, _ = raw_call(health, LIST_JOBS, token="right-token")
        check(code == grpc.StatusCode.UNIMPLEMENTED, "the health port serves jobs: %s %s" % (code, details))
        refused(channel(s), "a plaintext client on the main port")
        r = depath("health", "--server", "127.0.0.1:" + found.group(1))
        check(r.returncode == 0 and "SERVING" in r.stdout, "depath health on the health port: " + r.stderr)


def test_mutual_tls():
    with Server("--tls-cert", path("server.pem"), "--tls-key", path("server.key"),
                "--tls-client-ca", path("ca.pem")) as s:
        check("tls=mutual" in s.log_text(), "start log does not say mutual: " + s.log_text())
        refused(channel(s), "a plaintext client")
        refused(channel(s, "ca.pem"), "a client without a certificate")
        refused(channel(s, "ca.pem", "stranger.pem", "stranger.key"), "a client with a certificate of another CA")
        served(channel(s, "ca.pem", "client.pem", "client.key"), "a client with a certificate")
        r = depath("run", ARGS.mesh, "-s", "0", "-t", "1400", "--method", "fmm", "--server", s.address, "--tls-ca",
                   path("ca.pem"), "--tls-cert", path("client.pem"), "--tls-key", path("client.key"), "--json")
        check(r.returncode == 0 and '"points"' in r.stdout, "depath run over mutual TLS: " + r.stderr[-500:])
        env = {"DEPATH_TLS_CA": path("ca.pem"), "DEPATH_TLS_CERT": path("client.pem"),
               "DEPATH_TLS_KEY": path("client.key")}
        r = depath("jobs", "--server", s.address, env=env)
        check(r.returncode == 0, "depath jobs with DEPATH_TLS_* over mutual TLS: " + r.stderr)
        r = depath("jobs", "--server", s.address, "--tls-ca", path("ca.pem"))
        check(r.returncode != 0, "depath jobs without a client certificate succeeded")


def test_reload():
    """The server's files are replaced by a certificate of a second CA: served without a restart."""
    for name in ("server.pem", "server.key"):
        shutil.copy(path(name), path("live-" + name))
    reload_seconds = 1
    with Server("--tls-cert", path("live-server.pem"), "--tls-key", path("live-server.key"),
                "--tls-reload-seconds", reload_seconds) as s:
        served(channel(s, "ca.pem"), "a client trusting the first CA")
        refused(channel(s, "other-ca.pem"), "a client trusting only the second CA (before the reload)")
        for name in ("server.pem", "server.key"):  # replace each file atomically, key and certificate
            shutil.copy(path("other-" + name), path("new-" + name))
        os.rename(path("new-server.key"), path("live-server.key"))
        os.rename(path("new-server.pem"), path("live-server.pem"))
        deadline = time.monotonic() + (reload_seconds * 5 + 10) * SCALE
        while True:  # a new connection each time: existing ones keep their handshake
            code, _, _ = raw_call(channel(s, "other-ca.pem"), HEALTH, timeout=5 * SCALE)
            if code == grpc.StatusCode.OK:
                break
            check(time.monotonic() < deadline, "the renewed certificate was not served after %g s" % (
                reload_seconds * 5 + 10))
            time.sleep(0.2)
        refused(channel(s, "ca.pem"), "a client trusting only the first CA (after the reload)")
        check(s.proc.poll() is None, "depathd restarted")


def test_bad_tls_files():
    cases = [
        (["--tls-cert", path("server.pem"), "--tls-key", path("client.key")], "is not the private key"),
        (["--tls-cert", path("server.pem"), "--tls-key", path("missing.key")], "--tls-key"),
        (["--tls-cert", path("server.key"), "--tls-key", path("server.key")], "holds no PEM certificate"),
        (["--tls-cert", path("server.pem")], "--tls-cert and --tls-key go together"),
        (["--tls-client-ca", path("ca.pem")], "--tls-client-ca needs --tls-cert"),
    ]
    for flags, message in cases:
        r = subprocess.run([ARGS.depathd, "--store", "memory", "--listen", "127.0.0.1:0", *flags], capture_output=True,
                           text=True, timeout=30 * SCALE)
        check(r.returncode == 2 and message in r.stderr, "%s: exit %d, %r" % (flags, r.returncode, r.stderr))


# ---- tokens -------------------------------------------------------------------------------------

def test_tokens():
    with open(path("tokens.txt"), "w") as f:
        f.write("# tokens of the team\n\ntoken-from-file-1\n  token-from-file-2  \n")
    with open(path("client-token.txt"), "w") as f:
        f.write("token-from-env-2\n")
    env = {"DEPATHD_AUTH_TOKENS": "token-from-env-1, token-from-env-2"}
    with Server("--auth-token", "token-flag-1", "--auth-token", "token-flag-2", "--auth-token-file",
                path("tokens.txt"), "--auth-failure-burst", "50", env=env) as s:
        check("auth_tokens=6" in s.log_text(), "not 6 tokens: " + s.log_text())
        chan = channel(s)
        for token in ("token-flag-1", "token-flag-2", "token-from-file-1", "token-from-file-2", "token-from-env-1",
                      "token-from-env-2"):
            code, details, _ = raw_call(chan, LIST_JOBS, token=token)
            check(code == grpc.StatusCode.OK, "token %s refused: %s %s" % (token, code, details))
        for token in (None, "token-flag", "token-flag-12", "# tokens of the team", "x" * 300):
            code, details, _ = raw_call(chan, LIST_JOBS, token=token)
            check(code == grpc.StatusCode.UNAUTHENTICATED, "token %r: %s %s" % (token, code, details))
        served(chan, "health without a token")
        check(depath("jobs", "--server", s.address, "--token", "token-flag-2").returncode == 0, "depath --token")
        check(depath("jobs", "--server", s.address, "--token-file", path("client-token.txt")).returncode == 0,
              "depath --token-file")
        check(depath("jobs", "--server", s.address, env={"DEPATH_TOKEN": "token-from-file-1"}).returncode == 0,
              "depath with DEPATH_TOKEN")
        r = depath("jobs", "--server", s.address, "--token", "wrong-secret-value")
        check(r.returncode != 0 and "invalid token" in r.stderr, "wrong token: " + r.stderr)
        log = s.log_text()
        check("auth.failed" in log and "method=ListJobs" in log and "peer=ipv4:127.0.0.1:" in log,
              "failed attempts not logged with method and peer: " + log[-1000:])
        check("wrong-secret-value" not in log and "token-flag" not in log, "a token reached the log")
    r = subprocess.run([ARGS.depathd, "--store", "memory", "--auth-token-file", path("client.csr.missing")],
                       capture_output=True, text=True)
    check(r.returncode != 0 and "--auth-token-file" in r.stderr, "missing token file: " + r.stderr)


def test_auth_failure_limit():
    burst, rate = 3, 0.5
    with Server("--auth-token", "right-token", "--auth-failure-burst", burst, "--auth-failure-rate", rate) as s:
        chan = channel(s)
        for i in range(burst):
            code, details, _ = raw_call(chan, LIST_JOBS, token="guess-%d" % i)
            check(code == grpc.StatusCode.UNAUTHENTICATED, "guess %d: %s %s" % (i, code, details))
        code, details, _ = raw_call(chan, LIST_JOBS, token="guess-x")
        check(code == grpc.StatusCode.RESOURCE_EXHAUSTED and "--auth-failure-rate" in details,
              "past the burst: %s %s" % (code, details))
        code, details, _ = raw_call(chan, LIST_JOBS, token="right-token")  # no oracle while limited
        check(code == grpc.StatusCode.RESOURCE_EXHAUSTED, "right token while limited: %s %s" % (code, details))
        served(chan, "health while the peer is limited")
        deadline = time.monotonic() + (1 / rate) * 4 * SCALE + 5
        while raw_call(chan, LIST_JOBS, token="right-token")[0] != grpc.StatusCode.OK:
            check(time.monotonic() < deadline, "still limited %g s after the failures" % ((1 / rate) * 4))
            time.sleep(0.2)
        check(s.log_text().count("auth.failed") == burst, "expected %d logged failures" % burst)


def reflection_reply(chan, token):
    """ServerReflectionInfo with one list_services request: (status, replies)."""
    call = chan.stream_stream(REFLECTION, request_serializer=lambda x: x, response_deserializer=lambda x: x)
    metadata = (("authorization", "Bearer " + token),) if token else None
    replies = []
    try:
        for reply in call(iter([b"\x3a\x00"]), metadata=metadata, timeout=10 * SCALE):
            replies.append(reply)
        return grpc.StatusCode.OK, replies
    except grpc.RpcError as e:
        return e.code(), replies


def test_reflection_behind_auth():
    with Server("--auth-token", "right-token") as s:
        chan = channel(s)
        code, replies = reflection_reply(chan, None)
        check(code == grpc.StatusCode.UNAUTHENTICATED, "reflection without a token: %s" % code)
        check(all(r == b"" for r in replies), "reflection told something without a token: %r" % replies)
        code, replies = reflection_reply(chan, "right-token")
        check(code == grpc.StatusCode.OK and any(b"depath.v1.JobService" in r for r in replies),
              "reflection with the token: %s %r" % (code, replies))
    with Server() as s:  # no auth: open as before
        code, replies = reflection_reply(channel(s), None)
        check(code == grpc.StatusCode.OK and any(b"depath.v1.MeshService" in r for r in replies), "open reflection")


# ---- quotas -------------------------------------------------------------------------------------

def submit(server, token, *flags, generations=1000000):
    return depath("submit", ARGS.mesh, "-s", "0", "-t", "1400", "--population", "8", "--generations", generations,
                  "--server", server.address, "--token", token, "--json", *flags)


def job_id(result):
    import json
    for line in result.stdout.splitlines():
        if line.startswith("{") and "job_id" in line:
            return json.loads(line)["job_id"]
    raise AssertionError("no job id in: " + result.stdout + result.stderr)


def test_jobs_per_client():
    with Server("--auth-token", "alice", "--auth-token", "bob", "--max-jobs-per-client", 2) as s:
        first = job_id(submit(s, "alice"))
        job_id(submit(s, "alice"))
        r = submit(s, "alice")
        check(r.returncode != 0 and "--max-jobs-per-client 2" in r.stderr and "token #1" in r.stderr,
              "third job of one client: " + r.stderr)
        job_id(submit(s, "bob"))  # another client is not affected
        check(depath("cancel", first, "--server", s.address, "--token", "alice").returncode == 0, "cancel")
        job_id(submit(s, "alice"))  # a finished job no longer counts
        r = submit(s, "alice")
        check(r.returncode != 0 and "--max-jobs-per-client" in r.stderr, "limit again: " + r.stderr)
    with Server("--max-jobs-per-client", 1) as s:  # without auth: per peer address
        job_id(submit(s, ""))
        r = submit(s, "")
        check(r.returncode != 0 and "peer 127.0.0.1" in r.stderr, "per peer without auth: " + r.stderr)
    with Server("--max-jobs-per-client", 1, "--tls-cert", path("server.pem"), "--tls-key", path("server.key"),
                "--tls-client-ca", path("ca.pem")) as s:  # mutual TLS without tokens: per certificate
        tls = ["--tls-ca", path("ca.pem"), "--tls-cert", path("client.pem"), "--tls-key", path("client.key")]
        job_id(submit(s, "", *tls))
        r = submit(s, "", *tls)
        check(r.returncode != 0 and "certificate client" in r.stderr, "per certificate: " + r.stderr)


def test_requests_per_second():
    rate, calls = 2, 30
    with Server("--max-requests-per-second-per-client", rate) as s:
        chan = channel(s)
        start = time.monotonic()
        codes = [raw_call(chan, LIST_JOBS) for _ in range(calls)]
        elapsed = time.monotonic() - start
        ok = sum(c[0] == grpc.StatusCode.OK for c in codes)
        limited = [c for c in codes if c[0] == grpc.StatusCode.RESOURCE_EXHAUSTED]
        check(codes[0][0] == grpc.StatusCode.OK, "first call refused: %s" % (codes[0],))
        check(ok <= rate + rate * elapsed + 1, "%d calls served in %.2f s at %g per second" % (ok, elapsed, rate))
        check(len(limited) == calls - ok, "other failures: %s" % codes)
        check("--max-requests-per-second-per-client" in limited[0][1], "message: " + limited[0][1])
        served(chan, "health past the request rate")


def upload_request(header=None, chunk=None):
    if header is not None:
        name = header.encode()
        inner = b"\x0a" + bytes([len(name)]) + name
        return b"\x0a" + bytes([len(inner)]) + inner
    return b"\x12" + encode_varint(len(chunk)) + chunk


def encode_varint(n):
    out = bytearray()
    while True:
        b = n & 0x7F
        n >>= 7
        out.append(b | (0x80 if n else 0))
        if not n:
            return bytes(out)


def test_concurrent_uploads():
    with Server("--max-concurrent-uploads", 1) as s:
        chan = channel(s)
        upload = chan.stream_unary(UPLOAD, request_serializer=lambda x: x, response_deserializer=lambda x: x)
        release = threading.Event()
        with open(ARGS.mesh, "rb") as f:
            mesh = f.read()

        def slow():
            yield upload_request(header="held.off")
            release.wait(60 * SCALE)
            yield upload_request(chunk=mesh)

        future = upload.future(slow(), timeout=120 * SCALE)
        # Wait until the held stream has the slot: a second one is then refused. (A probe that
        # reaches the server first takes the slot and the held stream is refused: start it again.)
        deadline = time.monotonic() + 30 * SCALE
        while True:
            if future.done():
                future = upload.future(slow(), timeout=120 * SCALE)
            try:
                upload(iter([upload_request(header="second.off"), upload_request(chunk=mesh)]), timeout=10 * SCALE)
                check(time.monotonic() < deadline, "a second upload was never refused")
                time.sleep(0.05)
            except grpc.RpcError as e:
                check(e.code() == grpc.StatusCode.RESOURCE_EXHAUSTED and "--max-concurrent-uploads" in e.details(),
                      "second upload: %s %s" % (e.code(), e.details()))
                if not future.done():
                    break
                check(time.monotonic() < deadline, "the held upload never kept its slot")
        release.set()
        check(len(future.result()) > 0, "the held upload failed")
        upload(iter([upload_request(header="after.off"), upload_request(chunk=mesh)]), timeout=30 * SCALE)


def http_upload(port, body, name="kitten.off"):
    """POST /v1/meshes: (status, error message or mesh id)."""
    req = urllib.request.Request("http://127.0.0.1:%d/v1/meshes?name=%s" % (port, name), data=body, method="POST",
                                 headers={"Content-Type": "application/octet-stream"})
    try:
        with urllib.request.urlopen(req, timeout=60 * SCALE) as resp:
            return resp.status, json.loads(resp.read())["mesh_id"]
    except urllib.error.HTTPError as e:
        return e.code, json.loads(e.read())["error"]["message"]


def http_declared_upload(port, length, name="kitten.off"):
    """POST /v1/meshes that declares `length` bytes and sends none (a refusal comes before the
    body is read): (status, error message)."""
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=60 * SCALE)
    try:
        conn.putrequest("POST", "/v1/meshes?name=" + name)
        conn.putheader("Content-Length", str(length))
        conn.endheaders()
        resp = conn.getresponse()
        return resp.status, json.loads(resp.read())["error"]["message"]
    finally:
        conn.close()


def test_upload_memory_budget():
    """--max-upload-memory-bytes: gRPC and HTTP uploads share one budget of estimated memory
    (file bytes x 7 for OFF, upload_budget.cpp). The budget here holds one kitten upload (and a
    cone beside it) but not two kittens; an upload over the whole budget is refused at once."""
    with open(ARGS.mesh, "rb") as f:
        kitten = f.read()
    with open(os.path.join(os.path.dirname(ARGS.mesh), "cone.off"), "rb") as f:
        cone = f.read()
    kitten_need, cone_need = 7 * len(kitten), 7 * len(cone)
    budget = kitten_need + cone_need + 1000
    check(budget < 2 * kitten_need, "test data: two kittens must not fit")
    http_port_file = path("http-port")
    if os.path.exists(http_port_file):
        os.remove(http_port_file)
    with Server("--max-upload-memory-bytes", budget, "--http-listen", "127.0.0.1:0", "--http-port-file",
                http_port_file) as s:
        deadline = time.monotonic() + 30 * SCALE
        while not (os.path.exists(http_port_file) and open(http_port_file).read().strip()):
            check(time.monotonic() < deadline, "no HTTP port")
            time.sleep(0.05)
        http_port = int(open(http_port_file).read())
        chan = channel(s)
        upload = chan.stream_unary(UPLOAD, request_serializer=lambda x: x, response_deserializer=lambda x: x)

        def grpc_upload(name, data):
            try:
                upload(iter([upload_request(header=name), upload_request(chunk=data)]), timeout=60 * SCALE)
                return grpc.StatusCode.OK, ""
            except grpc.RpcError as e:
                return e.code(), e.details()

        def refused_for_memory(result, whole=False):
            code, message = result
            return (code in (grpc.StatusCode.RESOURCE_EXHAUSTED, 429) and "--max-upload-memory-bytes" in message and
                    ("whole budget" in message if whole else "try again shortly" in message))

        # Larger than the whole budget: refused at once on both transports, naming the flag and the figures.
        big = kitten * 3
        for result in (grpc_upload("big.off", big), http_declared_upload(http_port, len(big), "big.off")):
            check(refused_for_memory(result, whole=True), "upload over the whole budget: %s %s" % result)
            check(str(7 * len(big)) in result[1] and str(budget) in result[1], "figures missing: " + result[1])

        # A held gRPC upload (its kitten received, the stream kept open) takes a kitten's room.
        release = threading.Event()

        def held(tail, body=kitten):
            yield upload_request(header="held.off")
            yield upload_request(chunk=body)
            release.wait(60 * SCALE)
            yield upload_request(chunk=tail)

        def hold_room(start, lost):
            """Starts an upload that is to hold a kitten's room and returns its handle once it does
            (a kitten probe is refused). A probe may take the room first, when the held upload's
            bytes reach the server during the probe: the held one is then refused for memory
            (lost(handle)) and started again. Only the held upload can hold room between probes."""
            deadline = time.monotonic() + 30 * SCALE
            handle = start()
            time.sleep(0.2 * SCALE)  # let its bytes arrive before the first probe
            while True:
                result = grpc_upload("probe.off", kitten)
                if refused_for_memory(result):
                    return handle
                check(result[0] == grpc.StatusCode.OK, "probe upload: %s %s" % result)
                if lost(handle):
                    handle = start()
                check(time.monotonic() < deadline, "the held upload never took its room")
                time.sleep(0.05)

        def grpc_lost(future):
            if not future.done():
                return False
            e = future.exception()
            check(e is not None and refused_for_memory((e.code(), e.details())),
                  "the held upload ended otherwise: %s" % e)
            return True

        future = hold_room(lambda: upload.future(held(b"\n"), timeout=120 * SCALE), grpc_lost)
        check(refused_for_memory(http_declared_upload(http_port, len(kitten))),
              "HTTP kitten beside the held gRPC one not refused")
        check(grpc_upload("cone.off", cone)[0] == grpc.StatusCode.OK, "a cone within the budget was refused")
        check(http_upload(http_port, cone, "cone.off")[0] == 200, "an HTTP cone within the budget was refused")
        release.set()
        check(len(future.result()) > 0, "the held upload failed")
        # Its room is free again: a kitten fits (on both transports).
        check(grpc_upload("after.off", kitten)[0] == grpc.StatusCode.OK, "no room after the held upload ended")
        check(http_upload(http_port, kitten)[0] == 200, "no room for HTTP after the held upload ended")

        # Room is given back after failures too: a held upload whose bytes do not parse, one the
        # client cancels, and an HTTP upload whose client goes away after half its body.
        def until(what, cond):
            deadline = time.monotonic() + 30 * SCALE
            while True:
                result = grpc_upload("probe.off", kitten)
                if cond(result):
                    return
                check(time.monotonic() < deadline, "%s: %s %s" % (what, result[0], result[1]))
                time.sleep(0.05)

        def kitten_fits(result):
            return result[0] == grpc.StatusCode.OK

        release.clear()
        future = hold_room(lambda: upload.future(held(b"\n", b"#" * len(kitten)), timeout=120 * SCALE),  # no OFF header
                           grpc_lost)
        release.set()
        try:
            future.result()
            check(False, "bad bytes were accepted")
        except grpc.RpcError as e:
            check(e.code() == grpc.StatusCode.INVALID_ARGUMENT, "bad bytes: %s %s" % (e.code(), e.details()))
        check(kitten_fits(grpc_upload("after-bad.off", kitten)), "no room after a failed parse")

        release.clear()
        future = hold_room(lambda: upload.future(held(b"\n"), timeout=120 * SCALE), grpc_lost)
        future.cancel()
        until("room never given back after a cancel", kitten_fits)  # the server sees the cancel on its own time
        release.set()

        def http_half():
            sock = socket.create_connection(("127.0.0.1", http_port))
            sock.sendall(b"POST /v1/meshes?name=half.off HTTP/1.1\r\nHost: x\r\nContent-Length: %d\r\n\r\n"
                         % len(kitten) + kitten[:len(kitten) // 2])
            return sock

        def http_lost(sock):  # the server answers a half-sent upload only to refuse it
            if not select.select([sock], [], [], 0)[0]:
                return False
            answer = sock.recv(65536)
            sock.close()
            check(answer.startswith(b"HTTP/1.1 429"), "the half-sent HTTP upload got: %r" % answer[:200])
            return True

        hold_room(http_half, http_lost).close()
        until("room never given back after a dropped HTTP upload", kitten_fits)
        check(http_upload(http_port, kitten)[0] == 200, "no room for HTTP after the failures")

def main():
    global ARGS, WORK
    parser = argparse.ArgumentParser()
    parser.add_argument("--depathd", required=True)
    parser.add_argument("--depath", required=True)
    parser.add_argument("--mesh", required=True)
    parser.add_argument("tests", nargs="*")
    ARGS = parser.parse_args()
    check(shutil.which("openssl"), "openssl is needed (Debian package openssl)")
    WORK = tempfile.mkdtemp(prefix="depath-security-")
    try:
        make_ca("ca")
        make_ca("other-ca")
        make_cert("server", "ca")
        make_cert("client", "ca")
        make_cert("stranger", "other-ca")
        make_cert("other-server", "other-ca")
        tests = [t for name, t in sorted(globals().items()) if name.startswith("test_")]
        if ARGS.tests:
            tests = [t for t in tests if any(w in t.__name__ for w in ARGS.tests)]
        for t in tests:
            start = time.monotonic()
            t()
            print("ok %s (%.1f s)" % (t.__name__, time.monotonic() - start), flush=True)
    finally:
        shutil.rmtree(WORK, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
