#!/usr/bin/env python3
"""depathd's HTTP face (--http-listen) with the real binaries, over real sockets (urllib/http.client).

Checked: every /v1 route against the same job seen through gRPC (`depath result` writes the same bytes
as the result.json download); the SSE stream (ids strictly increasing and equal to the event sequences,
state/progress/path/result kinds, the stream ends after the terminal state; resume with Last-Event-ID
and ?after= gives exactly the events after N); error mapping (400/404/409/429 with the gRPC code name);
auth (401 without or with a wrong token, exempt routes); path traversal refused; the web root and the
plain fallback page; the per-generation progress history (GET /v1/jobs/ID/progress: one point per
generation, equal to the streamed figures, best non-increasing; thinned past 1000 points as documented;
complete after a SIGTERM/restart on SQLite that suspends and resumes the job); the field of a
vector-field job (GET /v1/jobs/ID/field, the height gradient of the terrain); /metrics parsed by prometheus_client after a real job, with counters equal to
the job's own figures (evaluations, generations, uploads, 401s).

Liveness bounds come from the configured limits, scaled by DEPATH_TEST_TIME_SCALE."""
import argparse
import hashlib
import http.client
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

from prometheus_client.parser import text_string_to_metric_families

SCALE = float(os.environ.get("DEPATH_TEST_TIME_SCALE", "1"))
TOKEN = "s3cret-token"
ARGS = None
WORK = None
failures = []


def check(cond, message):
    if not cond:
        raise AssertionError(message)


class Daemon:
    def __init__(self, name, binary, extra=(), store="memory"):
        self.port_file = os.path.join(WORK, name + ".port")
        self.http_port_file = os.path.join(WORK, name + ".hport")
        self.log = os.path.join(WORK, name + ".log")
        self.proc = subprocess.Popen([binary, "--store", store, "--listen", "127.0.0.1:0", "--port-file",
                                      self.port_file, "--http-listen", "127.0.0.1:0", "--http-port-file",
                                      self.http_port_file, "--threads", "2", "--log-format", "json"] + list(extra),
                                     stdout=subprocess.DEVNULL, stderr=open(self.log, "w"))
        deadline = time.monotonic() + 30 * SCALE
        while not (os.path.exists(self.http_port_file) and open(self.http_port_file).read().strip()):
            check(self.proc.poll() is None, "depathd exited at start: " + open(self.log).read()[-400:])
            check(time.monotonic() < deadline, "depathd did not start")
            time.sleep(0.02)
        self.grpc = "127.0.0.1:" + open(self.port_file).read().strip()
        self.port = int(open(self.http_port_file).read().strip())
        self.base = "http://127.0.0.1:%d" % self.port

    def stop(self):
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            self.proc.wait(timeout=60 * SCALE)


def request(d, method, path, body=None, token=TOKEN, headers=None, timeout=60):
    """(status, headers, body bytes); never raises for an HTTP error status."""
    h = dict(headers or {})
    if token is not None:
        h["Authorization"] = "Bearer " + token
    req = urllib.request.Request(d.base + path, data=body, method=method, headers=h)
    try:
        with urllib.request.urlopen(req, timeout=timeout * SCALE) as r:
            return r.status, r.headers, r.read()
    except urllib.error.HTTPError as e:
        return e.code, e.headers, e.read()


def get_json(d, path, **kw):
    status, headers, body = request(d, "GET", path, **kw)
    check(status == 200, "GET %s: %d %s" % (path, status, body[:300]))
    check(headers.get("Content-Type", "").startswith("application/json"), "GET %s content type" % path)
    return json.loads(body)


def post_json(d, path, obj, **kw):
    status, _, body = request(d, "POST", path, json.dumps(obj).encode(), headers={"Content-Type": "application/json"},
                              **kw)
    return status, json.loads(body) if body else None


def expect_error(status, body, http_status, code, words=""):
    check(status == http_status, "expected HTTP %d, got %d: %s" % (http_status, status, body))
    err = body["error"] if isinstance(body, dict) else json.loads(body)["error"]
    check(err["code"] == code, "expected %s, got %s" % (code, err))
    check(words in err["message"], "message %r lacks %r" % (err["message"], words))


def raw_get(d, path, headers=None):
    """GET with the path sent exactly as given (no client-side normalisation)."""
    c = http.client.HTTPConnection("127.0.0.1", d.port, timeout=30 * SCALE)
    c.putrequest("GET", path, skip_accept_encoding=True)
    for k, v in (headers or {}).items():
        c.putheader(k, v)
    c.endheaders()
    r = c.getresponse()
    body = r.read()
    c.close()
    return r.status, body


def read_events(d, job_id, headers=None, query="", timeout=120):
    """All SSE events of one stream until the server ends it: list of (id, event, data)."""
    h = {"Authorization": "Bearer " + TOKEN, "Accept": "text/event-stream"}
    h.update(headers or {})
    req = urllib.request.Request(d.base + "/v1/jobs/%s/events%s" % (job_id, query), headers=h)
    events, cur = [], {}
    with urllib.request.urlopen(req, timeout=timeout * SCALE) as r:
        check(r.headers.get("Content-Type", "").startswith("text/event-stream"), "SSE content type")
        for raw in r:
            line = raw.decode().rstrip("\n")
            if line == "":
                if "data" in cur:
                    events.append((int(cur["id"]), cur["event"], json.loads(cur["data"])))
                cur = {}
            elif line.startswith(":"):
                continue
            else:
                key, _, value = line.partition(": ")
                cur[key] = value
    return events


def off_mesh(path):
    words = open(path).read().split()
    check(words[0] == "OFF", "not an OFF file")
    nv, nf = int(words[1]), int(words[2])
    vals = words[4:]
    verts = [float(x) for x in vals[:3 * nv]]
    faces = []
    rest = vals[3 * nv:]
    for i in range(nf):
        n = int(rest[4 * i])
        check(n == 3, "triangles only")
        faces += [int(x) for x in rest[4 * i + 1:4 * i + 4]]
    return verts, faces


def metrics(d):
    status, headers, body = request(d, "GET", "/metrics", token=None)
    check(status == 200, "/metrics status %d" % status)
    check(headers.get("Content-Type", "").startswith("text/plain; version=0.0.4"),
          "metrics content type: %s" % headers.get("Content-Type"))
    samples = {}
    families = list(text_string_to_metric_families(body.decode()))  # raises on any malformed line
    for fam in families:
        for s in fam.samples:
            samples[(s.name, tuple(sorted(s.labels.items())))] = s.value
    return families, samples


def sample(samples, name, **labels):
    return samples.get((name, tuple(sorted(labels.items()))), 0.0)


def depath(*args, timeout=120):
    return subprocess.run([ARGS.depath] + list(args), capture_output=True, text=True, timeout=timeout * SCALE)


def test_main(d):
    mesh_bytes = open(ARGS.mesh, "rb").read()
    verts, faces = off_mesh(ARGS.mesh)

    # -- health, readiness, metrics before anything ran
    check(request(d, "GET", "/healthz", token=None)[0] == 200, "/healthz")
    check(request(d, "GET", "/readyz", token=None)[0] == 200, "/readyz")
    _, before = metrics(d)
    check(sample(before, "depath_evaluations_total") == 0, "no evaluations yet")

    # -- auth: /v1 needs the token; probes and metrics do not
    s, _, b = request(d, "GET", "/v1/jobs", token=None)
    expect_error(s, json.loads(b), 401, "UNAUTHENTICATED", "missing")
    s, _, b = request(d, "GET", "/v1/jobs", token="wrong")
    expect_error(s, json.loads(b), 401, "UNAUTHENTICATED", "invalid token")
    s, _, b = request(d, "GET", "/v1/jobs?access_token=" + TOKEN, token=None)
    check(s == 200 and json.loads(b) == {"jobs": []}, "access_token query parameter: %d %s" % (s, b))
    s, _, b = request(d, "POST", "/v1/meshes?format=off", mesh_bytes, token=None)
    expect_error(s, json.loads(b), 401, "UNAUTHENTICATED")
    auth_failures = 3

    # -- upload: the mesh id is the SHA-256 of the bytes, counts from the file
    s, _, b = request(d, "POST", "/v1/meshes?format=off", mesh_bytes, headers={"Content-Type": "application/octet-stream"})
    check(s == 200, "upload: %d %s" % (s, b))
    info = json.loads(b)
    mesh_id = hashlib.sha256(mesh_bytes).hexdigest()
    check(info["mesh_id"] == mesh_id, "mesh id %s != sha256 %s" % (info["mesh_id"], mesh_id))
    check(info["vertices"] == len(verts) // 3 and info["faces"] == len(faces) // 3, "mesh counts %s" % info)
    # a form-encoded upload (curl's default) is read as bytes too, and is already present
    s, _, b = request(d, "POST", "/v1/meshes?name=kitten.off", mesh_bytes,
                      headers={"Content-Type": "application/x-www-form-urlencoded"})
    check(s == 200 and json.loads(b)["already_present"] is True, "second upload: %d %s" % (s, b[:200]))

    # -- geometry: flat arrays, positions in single precision, faces exact
    g = get_json(d, "/v1/meshes/%s/geometry" % mesh_id)
    check(g["faces"] == faces, "geometry faces differ from the file")
    check(len(g["vertices"]) == len(verts), "geometry has %d coordinates, file %d" % (len(g["vertices"]), len(verts)))
    worst = max(abs(a - b) / max(1.0, abs(b)) for a, b in zip(g["vertices"], verts))
    check(worst <= 1.2e-7, "geometry positions off by %g (relative), more than float precision" % worst)

    # -- submit and follow the job from the start
    spec = {"mesh_id": mesh_id, "source": 366, "target": 230, "generations": 40, "population": 16, "seed": 7,
            "path_every": 10, "client_request_id": "http-test-1"}
    s, reply = post_json(d, "/v1/jobs", spec)
    check(s == 200 and reply["id"].startswith("job-") and reply["existing"] is False, "submit: %d %s" % (s, reply))
    job = reply["id"]
    s, again = post_json(d, "/v1/jobs", spec)
    check(s == 200 and again["id"] == job and again["existing"] is True, "idempotent resubmit: %s" % again)
    events = read_events(d, job)
    ids = [e[0] for e in events]
    check(ids == sorted(set(ids)) and ids[0] >= 1, "event ids not strictly increasing: %s" % ids)
    check(all(e[0] == e[2]["sequence"] for e in events), "SSE id != event sequence")
    kinds = [e[1] for e in events]
    check(set(kinds) <= {"state", "progress", "path", "result"}, "unknown kinds %s" % set(kinds))
    check(kinds[0] == "state" and events[0][2]["state"] in ("queued", "running"), "first event %s" % (events[0],))
    check(kinds[-1] == "state" and events[-1][2]["state"] == "succeeded", "last event %s" % (events[-1],))
    check(kinds[-2] == "result", "the result precedes the terminal state: %s" % kinds[-3:])
    check("path" in kinds, "no best-path event with path_every 10: %s" % kinds)
    for _, kind, data in events:
        if kind == "path":
            check(data["generation"] % 10 == 0 and len(data["path"]["points"]) >= 2, "path event %s" % data)
        if kind in ("progress", "path"):
            check(1 <= data["generation"] <= 40 and data["best_energy"] <= data["mean_energy"] + 1e-9,
                  "progress figures %s" % data)
    result_event = events[-2][2]["result"]

    # -- resume: Last-Event-ID and ?after= give exactly the events after N
    n = events[-3][0]
    tail = read_events(d, job, headers={"Last-Event-ID": str(n)})
    check([e[0] for e in tail] == [e[0] for e in events if e[0] > n], "Last-Event-ID resume: %s" % tail)
    tail2 = read_events(d, job, query="?after=%d" % n)
    check([(e[0], e[1]) for e in tail2] == [(e[0], e[1]) for e in tail], "?after= resume differs")
    check(read_events(d, job, headers={"Last-Event-ID": str(events[-1][0])}) == [], "resume after the end")
    s, _, b = request(d, "GET", "/v1/jobs/%s/events" % job, headers={"Last-Event-ID": "x1"})
    expect_error(s, json.loads(b), 400, "INVALID_ARGUMENT", "Last-Event-ID")

    # -- list and detail
    listed = get_json(d, "/v1/jobs")["jobs"]
    check([j["id"] for j in listed] == [job], "list %s" % listed)
    j = listed[0]
    check(j["state"] == "succeeded" and j["mesh_id"] == mesh_id and j["energy"] == "geodesic" and j["method"] == "de"
          and j["generations"] == 40 and j["generation"] == result_event["generations"], "summary %s" % j)
    detail = get_json(d, "/v1/jobs/" + job)
    check(detail["spec"]["source"] == 366 and detail["spec"]["target"] == 230 and detail["spec"]["seed"] == 7
          and detail["spec"]["population"] == 16 and detail["spec"]["generations"] == 40, "spec %s" % detail["spec"])
    check(detail["error"] is None and detail["progress"]["generation"] == result_event["generations"], "detail")
    check(detail["result"]["points"] == result_event["points"] and detail["result"]["energy"] == result_event["energy"],
          "detail result differs from the result event")
    check(detail["result"]["elapsed_seconds"] == detail["result"]["seconds"], "elapsed_seconds")

    # -- downloads: the CLI's writers; result.json is byte-identical to `depath result --out x.json` over gRPC
    out = os.path.join(WORK, "cli.json")
    r = depath("result", job, "--server", d.grpc, "--token", TOKEN, "--out", out)
    check(r.returncode == 0, "depath result: " + r.stderr[-300:])
    s, h, body = request(d, "GET", "/v1/jobs/%s/result.json" % job)
    check(s == 200 and body == open(out, "rb").read(), "result.json differs from depath result --out")
    check(job + ".json" in h.get("Content-Disposition", ""), "download file name")
    npts = len(result_event["points"])
    s, _, obj = request(d, "GET", "/v1/jobs/%s/result.obj" % job)
    check(s == 200 and sum(1 for l in obj.decode().splitlines() if l.startswith("v ")) == npts, "obj points")
    s, _, ply = request(d, "GET", "/v1/jobs/%s/result.ply" % job)
    check(s == 200 and ("element vertex %d" % npts) in ply.decode(), "ply header")
    s, _, csv = request(d, "GET", "/v1/jobs/%s/result.csv" % job)
    check(s == 200 and len(csv.decode().strip().splitlines()) == npts + 1, "csv rows")

    # -- errors: status from the gRPC code of the same operation
    s, _, b = request(d, "GET", "/v1/jobs/job-0000000000000000")
    expect_error(s, json.loads(b), 404, "NOT_FOUND", "not found")
    s, b = post_json(d, "/v1/jobs", dict(spec, target=366, client_request_id="other"))
    expect_error(s, b, 400, "INVALID_ARGUMENT")
    s, b = post_json(d, "/v1/jobs", dict(spec, colour="red"))
    expect_error(s, b, 400, "INVALID_ARGUMENT", "unknown field 'colour'")
    s, b = post_json(d, "/v1/jobs", dict(spec, generations="many"))
    expect_error(s, b, 400, "INVALID_ARGUMENT", "'generations' must be an integer")
    s, _, b = request(d, "POST", "/v1/jobs", b"{not json")
    expect_error(s, json.loads(b), 400, "INVALID_ARGUMENT", "not JSON")
    s, b = post_json(d, "/v1/jobs", dict(spec, mesh_id="0" * 64, client_request_id="x2"))
    expect_error(s, b, 404, "NOT_FOUND")
    s, b = post_json(d, "/v1/jobs", dict(spec, client_request_id="http-test-1", seed=8))
    expect_error(s, b, 409, "ALREADY_EXISTS", "different spec")
    s, _, b = request(d, "POST", "/v1/meshes?format=dwg", b"x")
    expect_error(s, json.loads(b), 400, "INVALID_ARGUMENT", "dwg")
    bad_mesh = b"OFF\n3 1 0\n0 0 0\n1 0 0\n"
    s, _, b = request(d, "POST", "/v1/meshes?format=off", bad_mesh)
    expect_error(s, json.loads(b), 400, "INVALID_ARGUMENT")
    s, _, b = request(d, "GET", "/v1/nothing")
    expect_error(s, json.loads(b), 404, "NOT_FOUND", "no such route")

    # -- cancel a long job: 409 for its result while it runs, then CANCELLED promptly
    long_spec = dict(spec, generations=100000, population=40, path_every=0, client_request_id="long")
    s, reply = post_json(d, "/v1/jobs", long_spec)
    check(s == 200, "long submit %s" % reply)
    long_job = reply["id"]
    deadline = time.monotonic() + 60 * SCALE
    while get_json(d, "/v1/jobs/" + long_job)["state"] != "running":
        check(time.monotonic() < deadline, "long job did not start")
        time.sleep(0.05)
    s, _, b = request(d, "GET", "/v1/jobs/%s/result.json" % long_job)
    expect_error(s, json.loads(b), 409, "FAILED_PRECONDITION", "no result yet")
    # queue full (--max-queued-jobs 0, the only driver busy): 429
    s, b = post_json(d, "/v1/jobs", dict(spec, client_request_id="third"))
    expect_error(s, b, 429, "RESOURCE_EXHAUSTED", "--max-queued-jobs")
    s, b = post_json(d, "/v1/jobs/%s/cancel" % long_job, {})
    check(s == 200 and b["id"] == long_job, "cancel: %d %s" % (s, b))
    # the stream ends with the terminal CANCELLED state, within the shutdown bound (the job checks
    # for cancellation between evaluations)
    t0 = time.monotonic()
    tail = read_events(d, long_job, headers={"Last-Event-ID": "2"}, timeout=30)
    check(tail and tail[-1][1] == "state" and tail[-1][2]["state"] == "cancelled", "cancel stream %s" % tail[-1:])
    check(tail[-1][2]["error"]["code"] == "CANCELLED", "cancel error %s" % tail[-1][2])
    check(time.monotonic() - t0 < 30 * SCALE, "cancel took too long")

    # -- metrics after real jobs: every series parses, counters equal the jobs' own figures
    fams, after = metrics(d)
    names = {f.name for f in fams}
    for needed in ["depath_jobs", "depath_queue_depth", "depath_evaluations", "depath_generations",
                   "depath_decode_seconds", "depath_mesh_cache_bytes", "depath_mesh_cache_hits",
                   "depath_mesh_cache_misses", "depath_mesh_cache_evictions", "depath_uploads",
                   "depath_upload_bytes", "depath_rpcs", "depath_watchers", "depath_auth_failures",
                   "depath_http_requests", "depath_stencil_builds"]:
        check(needed in names, "metric family %s missing (have %s)" % (needed, sorted(names)))
    long_info = get_json(d, "/v1/jobs/" + long_job)
    long_evals = long_info["result"]["evaluations"] if long_info["result"] else long_info["progress"]["evaluations"]
    check(sample(after, "depath_evaluations_total") == result_event["evaluations"] + long_evals,
          "evaluations_total %g != %d + %d" % (sample(after, "depath_evaluations_total"), result_event["evaluations"],
                                               long_evals))
    check(sample(after, "depath_generations_total") >= result_event["generations"], "generations_total")
    check(sample(after, "depath_jobs", state="succeeded") == 1 and sample(after, "depath_jobs", state="cancelled") == 1,
          "jobs by state")
    # uploads that reached the parser: kitten twice and the truncated OFF (the 401 and the bad format did not)
    check(sample(after, "depath_uploads_total", transport="http") == 3, "uploads_total")
    check(sample(after, "depath_upload_bytes_total", transport="http") == 2 * len(mesh_bytes) + len(bad_mesh),
          "upload bytes")
    check(sample(after, "depath_auth_failures_total", transport="http") == auth_failures, "auth failures")
    check(sample(after, "depath_decode_seconds_count") > 0, "decode histogram empty")
    check(sample(after, "depath_rpcs_total", method="/depath.v1.JobService/GetResult", code="OK") == 1,
          "the gRPC GetResult of depath result is counted")
    check(sample(after, "depath_http_requests_total", route="GET /v1/jobs", status="401") == 2, "401s by route")
    check(sample(after, "depath_mesh_cache_hits_total") > 0, "cache hits")
    # both jobs ran on the one cached kitten: its stencils were built by the first only
    check(sample(after, "depath_stencil_builds_total") == 1, "stencil builds %g" % sample(after, "depath_stencil_builds_total"))
    deadline = time.monotonic() + 10 * SCALE
    while sample(metrics(d)[1], "depath_watchers", transport="http") != 0:
        check(time.monotonic() < deadline, "the HTTP watcher gauge does not return to 0")
        time.sleep(0.05)


def test_static(d, root, secret):
    # the page and its assets need no token; the SPA answers /jobs/ID with index.html
    index = open(os.path.join(root, "index.html"), "rb").read()
    for path in ["/", "/jobs/job-123"]:
        s, h, b = request(d, "GET", path, token=None)
        check(s == 200 and b == index and h["Content-Type"].startswith("text/html"), "%s: %d" % (path, s))
    s, h, b = request(d, "GET", "/assets/app.js", token=None)
    check(s == 200 and h["Content-Type"].startswith("application/javascript") and b == b"console.log(1)\n", "asset")
    s, h, b = request(d, "GET", "/assets/style.css", token=None)
    check(s == 200 and h["Content-Type"].startswith("text/css"), "css content type")
    for path in ["/assets/../../secret.txt", "/assets/%2e%2e/%2e%2e/secret.txt", "/..%2fsecret.txt",
                 "/assets/..%2f..%2fsecret.txt", "/assets/outside.txt", "/assets/missing.js", "/%00"]:
        s, b = raw_get(d, path)
        check(s in (400, 404) and secret not in b, "traversal %s: %d %r" % (path, s, b[:80]))


def test_fallback(d):
    # no web root beside the executable: a plain page listing jobs, /jobs/ID shows the id
    s, _, b = request(d, "GET", "/", token=None)
    check(s == 200 and b"depath" in b, "fallback /: %d" % s)
    mesh_bytes = open(ARGS.mesh, "rb").read()
    s, _, b = request(d, "POST", "/v1/meshes?format=off", mesh_bytes, token=None)
    mesh_id = json.loads(b)["mesh_id"]
    s, reply = post_json(d, "/v1/jobs", {"mesh_id": mesh_id, "source": 1, "target": 2, "method": "fmm"}, token=None)
    check(s == 200, "fallback submit %s" % reply)
    s, _, b = request(d, "GET", "/", token=None)
    check(('href="/jobs/%s"' % reply["id"]).encode() in b, "fallback list lacks the job link")
    s, _, b = request(d, "GET", "/jobs/" + reply["id"], token=None)
    check(s == 200 and reply["id"].encode() in b, "fallback job page lacks the id")


def history_stride(latest):
    # store/job_store.hpp: every generation up to 1000 points, then a doubling stride
    stride = 1
    while latest // stride >= 1000:
        stride *= 2
    return stride


def get_history(d, job, token=None):
    h = get_json(d, "/v1/jobs/%s/progress" % job, token=token)
    check(h["job_id"] == job and h["max_points"] == 1000, "history header %s" % {k: h[k] for k in ("job_id", "max_points")})
    n = len(h["generation"])
    check(len(h["best_energy"]) == n and len(h["mean_energy"]) == n, "history columns of unequal length")
    best = h["best_energy"]
    check(all(b2 <= b1 for b1, b2 in zip(best, best[1:])), "best energy increases in the history: %s" % best)
    check(all(m is None or b <= m + 1e-9 for b, m in zip(best, h["mean_energy"])), "best above mean in the history")
    return h


def wait_state(d, job, states, seconds, token=None):
    deadline = time.monotonic() + seconds * SCALE
    while True:
        j = get_json(d, "/v1/jobs/" + job, token=token)
        if j["state"] in states:
            return j
        check(time.monotonic() < deadline, "job %s still %s after %g s" % (job, j["state"], seconds * SCALE))
        time.sleep(0.05)


def test_history(d, mesh_id):
    # -- one point per generation, the same figures the stream carried
    spec = {"mesh_id": mesh_id, "source": 366, "target": 230, "generations": 60, "population": 8, "seed": 5,
            "path_every": 0}
    s, reply = post_json(d, "/v1/jobs", spec, token=None)
    check(s == 200, "history job: %s" % reply)
    job = reply["id"]
    events = read_events(d, job)
    result = [e[2] for e in events if e[1] == "result"][0]["result"]
    g_end = result["generations"]
    h = get_history(d, job)
    check(h["generation"] == list(range(1, g_end + 1)),
          "history generations %s, expected 1..%d" % (h["generation"][:5] + ["..."] + h["generation"][-3:], g_end))
    by_gen = dict(zip(h["generation"], zip(h["best_energy"], h["mean_energy"])))
    streamed = [e[2] for e in events if e[1] in ("progress", "path")]
    check(streamed, "no progress in the stream")
    for p in streamed:
        check(by_gen[p["generation"]] == (p["best_energy"], p["mean_energy"]),
              "generation %d: history %s, stream %s" % (p["generation"], by_gen[p["generation"]], p))
    check(result["energy"] <= h["best_energy"][-1] + 1e-9, "the result's energy is above the history's best")
    check(h["best_energy"][0] > h["best_energy"][-1], "DE improved nothing in 60 generations: %s" % h["best_energy"])
    print("history: %d points for %d generations, best %.6g -> %.6g" % (len(h["generation"]), g_end,
                                                                      h["best_energy"][0], h["best_energy"][-1]))
    s, _, b = request(d, "GET", "/v1/jobs/job-0000000000000000/progress", token=None)
    expect_error(s, json.loads(b), 404, "NOT_FOUND")
    s, _, b = request(d, "GET", "/v1/jobs/%s/field" % job, token=None)
    expect_error(s, json.loads(b), 409, "FAILED_PRECONDITION", "geodesic")

    # -- past 1000 generations the history is thinned: the first, every stride-th and the last
    grid = os.path.join(WORK, "grid6.obj")
    r = depath("generate", "grid", "--n", "6", "--out", grid)
    check(r.returncode == 0, "generate grid: " + r.stderr)
    s, _, b = request(d, "POST", "/v1/meshes?format=obj", open(grid, "rb").read(), token=None)
    grid_id = json.loads(b)["mesh_id"]
    s, reply = post_json(d, "/v1/jobs", {"mesh_id": grid_id, "source": 0, "target": 35, "generations": 2600,
                                         "population": 6, "seed": 3, "path_every": 0}, token=None)
    check(s == 200, "long history job: %s" % reply)
    j = wait_state(d, reply["id"], ("succeeded", "failed", "cancelled"), 300)
    check(j["state"] == "succeeded", "long history job %s" % j["state"])
    g_end = j["result"]["generations"]
    check(g_end > 2000, "the long job stopped at generation %d (%s): no thinning to check" %
          (g_end, j["result"].get("stop_reason")))
    stride = history_stride(g_end)
    h = get_history(d, reply["id"])
    expected = sorted({1, g_end} | set(range(stride, g_end + 1, stride)))
    check(h["generation"] == expected, "thinned history: %d points %s..., expected %d with stride %d" %
          (len(h["generation"]), h["generation"][:6], len(expected), stride))
    check(len(expected) <= 1001, "history over its bound")
    print("history thinned: %d points for %d generations (stride %d)" % (len(expected), g_end, stride))

    # -- the field of a vector-field job: the terrain's height gradient, one vector per vertex
    peaks = os.path.join(WORK, "peaks.obj")
    check(depath("generate", "peaks", "--n", "9", "--out", peaks).returncode == 0, "generate peaks")
    s, _, b = request(d, "POST", "/v1/meshes?format=obj", open(peaks, "rb").read(), token=None)
    peaks_id = json.loads(b)["mesh_id"]
    s, reply = post_json(d, "/v1/jobs", {"mesh_id": peaks_id, "source": 0, "target": 80, "energy": "vector_field",
                                         "field_from_height": True, "method": "fmm"}, token=None)
    check(s == 200, "field job %s" % reply)
    wait_state(d, reply["id"], ("succeeded",), 60)
    f = get_json(d, "/v1/jobs/%s/field" % reply["id"], token=None)["field"]
    check(len(f) == 81 * 3, "field of %d numbers for 81 vertices" % len(f))
    # each vector lies in the horizontal plane's projection of the gradient: not all zero, finite
    check(any(abs(x) > 1e-6 for x in f) and all(x == x for x in f), "field values %s" % f[:9])
    # a field given with the job is answered as given (quarters: exact in single precision) while
    # the job is not finished
    given = [[(v % 5) * 0.25, 1.0 - (v % 3) * 0.25, 0.0] for v in range(81)]
    s, reply = post_json(d, "/v1/jobs", {"mesh_id": peaks_id, "source": 0, "target": 80, "energy": "vector_field",
                                         "field": given, "population": 40, "generations": 100000}, token=None)
    check(s == 200, "given-field job %s" % reply)
    f = get_json(d, "/v1/jobs/%s/field" % reply["id"], token=None)["field"]
    check(f == [x for v in given for x in v], "given field answered as %s..." % f[:9])
    s, b = post_json(d, "/v1/jobs/%s/cancel" % reply["id"], {})
    check(s == 200, "cancel the given-field job: %d %s" % (s, b))
    wait_state(d, reply["id"], ("cancelled",), 60)
    s, _, b = request(d, "GET", "/v1/jobs/%s/field" % reply["id"], token=None)
    expect_error(s, json.loads(b), 409, "FAILED_PRECONDITION", "a finished job keeps its result")


def test_history_restart(depathd):
    """SQLite: a job suspended by SIGTERM mid-run resumes after the restart from its checkpoint; its
    history then has every generation once, and it is still there after a second restart."""
    store = "sqlite:" + os.path.join(WORK, "history.db")
    extra = ["--checkpoint-seconds", "0.2"]
    d = Daemon("durable1", depathd, extra, store=store)
    try:
        mesh_bytes = open(ARGS.mesh, "rb").read()
        s, _, b = request(d, "POST", "/v1/meshes?format=off", mesh_bytes, token=None)
        mesh_id = json.loads(b)["mesh_id"]
        s, reply = post_json(d, "/v1/jobs", {"mesh_id": mesh_id, "source": 366, "target": 230, "generations": 400,
                                             "population": 24, "seed": 11, "path_every": 0}, token=None)
        check(s == 200, "durable job %s" % reply)
        job = reply["id"]
        deadline = time.monotonic() + 120 * SCALE
        while True:
            j = get_json(d, "/v1/jobs/" + job, token=None)
            if j["state"] == "running" and (j["progress"] or {}).get("generation", 0) >= 20:
                break
            check(j["state"] in ("queued", "running"), "durable job ended before the restart: %s" % j["state"])
            check(time.monotonic() < deadline, "durable job did not reach generation 20")
            time.sleep(0.05)
        before = get_history(d, job)["generation"]
    finally:
        d.stop()
    d = Daemon("durable2", depathd, extra, store=store)
    try:
        j = wait_state(d, job, ("succeeded", "failed", "cancelled"), 600)
        check(j["state"] == "succeeded", "resumed job %s" % j["state"])
        g_end = j["result"]["generations"]
        h = get_history(d, job)
        check(h["generation"] == list(range(1, g_end + 1)),
              "history after a restart has gaps or repeats: %d points for %d generations" % (len(h["generation"]), g_end))
        check(len(before) >= 20 and h["generation"][:len(before)] == before, "history before the restart changed")
        resumed = [json.loads(l) for l in open(d.log) if '"job.resumed"' in l]
        check(len(resumed) == 1 and 20 <= resumed[0]["checkpoint_generation"] < g_end,
              "the job did not resume from a mid-run checkpoint: %s" % resumed)
        resumed_at = resumed[0]["checkpoint_generation"]
    finally:
        d.stop()
    d = Daemon("durable3", depathd, extra, store=store)
    try:
        check(get_history(d, job) == h, "the finished job's history changed across a restart")
    finally:
        d.stop()
    print("history on SQLite across restarts: %d generations, resumed after generation %d" % (g_end, resumed_at))


def test_shutdown(d):
    """SIGTERM with an open event stream (memory store): the stream gets the job's final CANCELLED
    event and ends, and depathd exits within its shutdown bound."""
    import threading
    mesh_bytes = open(ARGS.mesh, "rb").read()
    s, _, b = request(d, "POST", "/v1/meshes?format=off", mesh_bytes, token=None)
    mesh_id = json.loads(b)["mesh_id"]
    s, reply = post_json(d, "/v1/jobs", {"mesh_id": mesh_id, "source": 366, "target": 230, "population": 40,
                                         "generations": 100000}, token=None)
    check(s == 200, "shutdown test submit %s" % reply)
    got = {}

    def follow():
        try:
            got["events"] = read_events(d, reply["id"], timeout=60)
        except Exception as e:  # reported below
            got["error"] = e

    reader = threading.Thread(target=follow)
    reader.start()
    deadline = time.monotonic() + 60 * SCALE
    while get_json(d, "/v1/jobs/" + reply["id"], token=None)["state"] != "running":
        check(time.monotonic() < deadline, "job did not start")
        time.sleep(0.05)

    # an idle stream (a job queued behind two running ones, --max-running-jobs 2) gets a keep-alive
    # comment every 15 s
    for i in range(2):
        s, queued = post_json(d, "/v1/jobs", {"mesh_id": mesh_id, "source": 366, "target": 230 + i + 1,
                                              "population": 40, "generations": 100000}, token=None)
        check(s == 200, "submit %s" % queued)
    check(get_json(d, "/v1/jobs/" + queued["id"], token=None)["state"] == "queued", "third job not queued")
    c = http.client.HTTPConnection("127.0.0.1", d.port, timeout=(15 + 15) * SCALE)
    c.request("GET", "/v1/jobs/%s/events" % queued["id"])
    r = c.getresponse()
    lines = []
    t0 = time.monotonic()
    while ": keep-alive" not in lines:
        lines.append(r.readline().decode().rstrip("\n"))
    waited = time.monotonic() - t0
    check(waited >= 14, "keep-alive after %.1f s, before the 15 s interval" % waited)
    check("event: state" in lines and "id: 1" in lines, "idle stream began without the queued event: %s" % lines)
    c.close()
    d.proc.send_signal(signal.SIGTERM)
    # depathd's own bound: --shutdown-timeout-seconds (10 by default) + 5 s before it exits hard
    rc = d.proc.wait(timeout=(15 + 15) * SCALE)
    check(rc == 0, "depathd exit code %d after SIGTERM" % rc)
    reader.join(timeout=30 * SCALE)
    check(not reader.is_alive(), "the event stream did not end at shutdown")
    check("error" not in got, "event stream failed: %r" % got.get("error"))
    last = got["events"][-1]
    check(last[1] == "state" and last[2]["state"] == "cancelled" and "shutting down" in last[2]["message"],
          "last event at shutdown: %s" % (last,))


def main():
    global ARGS, WORK
    p = argparse.ArgumentParser()
    p.add_argument("--depathd", required=True)
    p.add_argument("--depath", required=True)
    p.add_argument("--mesh", required=True)
    ARGS = p.parse_args()
    WORK = tempfile.mkdtemp(prefix="depath-http-")
    root = os.path.join(WORK, "web")
    os.makedirs(os.path.join(root, "assets"))
    open(os.path.join(root, "index.html"), "w").write("<!doctype html><title>depath</title><canvas></canvas>\n")
    open(os.path.join(root, "assets", "app.js"), "w").write("console.log(1)\n")
    open(os.path.join(root, "assets", "style.css"), "w").write("body{}\n")
    secret = b"TOP-SECRET-" + os.urandom(4).hex().encode()
    open(os.path.join(WORK, "secret.txt"), "wb").write(secret)
    os.symlink(os.path.join(WORK, "secret.txt"), os.path.join(root, "assets", "outside.txt"))
    # a copy of depathd alone in a directory: no `web` beside it, so the fallback page is served
    lone = os.path.join(WORK, "bin")
    os.makedirs(lone)
    shutil.copy2(ARGS.depathd, lone)
    daemons = []
    try:
        d = Daemon("main", ARGS.depathd, ["--auth-token", TOKEN, "--web-root", root, "--max-running-jobs", "1",
                                          "--max-queued-jobs", "0"])
        daemons.append(d)
        test_main(d)
        print("api, sse, errors, auth, metrics: ok")
        test_static(d, root, secret)
        print("static files and traversal: ok")
        f = Daemon("fallback", os.path.join(lone, os.path.basename(ARGS.depathd)))
        daemons.append(f)
        test_fallback(f)
        print("fallback page: ok")
        test_history(f, hashlib.sha256(open(ARGS.mesh, "rb").read()).hexdigest())
        print("progress history and field: ok")
        test_history_restart(ARGS.depathd)
        print("progress history across restarts: ok")
        test_shutdown(f)
        print("event stream at shutdown: ok")
    finally:
        for d in daemons:
            d.stop()
    shutil.rmtree(WORK, ignore_errors=True)
    print("http_test: all passed")


if __name__ == "__main__":
    main()
