#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""depathd driven from Python as a third-party client would: stubs generated at test time
from proto/ with protoc --python_out and grpc_python_plugin, a real depathd process."""
import argparse
import hashlib
import importlib
import math
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time

# Deadlines are liveness bounds, multiplied by the sanitizer slow-down of the depathd under test
# (tests/time_scale.hpp; set by tests/service/CMakeLists.txt).
SCALE = float(os.environ.get("DEPATH_TEST_TIME_SCALE", "1"))


def grid_obj(n):
    lines = []
    for j in range(n):
        for i in range(n):
            x, y = i / (n - 1), j / (n - 1)
            lines.append("v %.17g %.17g %.17g" % (x, y, 0.3 * math.sin(3 * x) * math.cos(2 * y)))
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i + 1
            b, c = a + 1, a + n
            d = c + 1
            lines.append("f %d %d %d" % (a, b, d))
            lines.append("f %d %d %d" % (a, d, c))
    return ("\n".join(lines) + "\n").encode()


def check(cond, message):
    if not cond:
        raise AssertionError(message)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--depathd", required=True)
    ap.add_argument("--protoc", required=True)
    ap.add_argument("--grpc-python-plugin", required=True)
    ap.add_argument("--proto-dir", required=True)
    args = ap.parse_args()

    work = tempfile.mkdtemp(prefix="depath_py_")
    protos = ["depath/v1/mesh.proto", "depath/v1/job.proto", "grpc/health/v1/health.proto"]
    subprocess.run([args.protoc, "--proto_path=" + args.proto_dir, "--python_out=" + work,
                    "--grpc_out=" + work, "--plugin=protoc-gen-grpc=" + args.grpc_python_plugin] + protos,
                   check=True)
    for pkg in ["depath", "depath/v1", "grpc_health_gen"]:
        os.makedirs(os.path.join(work, pkg), exist_ok=True)
    sys.path.insert(0, work)
    import grpc  # the installed grpcio; our generated grpc/health stubs are loaded by path below
    mesh_pb2 = importlib.import_module("depath.v1.mesh_pb2")
    job_pb2 = importlib.import_module("depath.v1.job_pb2")
    mesh_grpc = importlib.import_module("depath.v1.mesh_pb2_grpc")
    job_grpc = importlib.import_module("depath.v1.job_pb2_grpc")
    spec = importlib.util.spec_from_file_location("health_pb2", os.path.join(work, "grpc/health/v1/health_pb2.py"))
    health_pb2 = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(health_pb2)

    port_file = os.path.join(work, "port")
    server = subprocess.Popen([args.depathd, "--listen", "127.0.0.1:0", "--port-file", port_file, "--threads", "2",
                               "--auth-token", "pytoken", "--log-format", "json"],
                              stderr=subprocess.PIPE)
    try:
        for _ in range(500):
            if os.path.exists(port_file):
                break
            time.sleep(0.01)
        port = int(open(port_file).read())
        channel = grpc.insecure_channel("127.0.0.1:%d" % port)
        auth = [("authorization", "Bearer pytoken")]
        meshes = mesh_grpc.MeshServiceStub(channel)
        jobs = job_grpc.JobServiceStub(channel)

        # Health without a token, through a generic call on the standard service name.
        check_health = channel.unary_unary("/grpc.health.v1.Health/Check",
                                           request_serializer=health_pb2.HealthCheckRequest.SerializeToString,
                                           response_deserializer=health_pb2.HealthCheckResponse.FromString)
        reply = check_health(health_pb2.HealthCheckRequest(service=""), timeout=10 * SCALE)
        check(reply.status == health_pb2.HealthCheckResponse.SERVING, "health: %s" % reply)

        # Without the token: UNAUTHENTICATED.
        try:
            jobs.ListJobs(job_pb2.ListJobsRequest(), timeout=10 * SCALE)
            check(False, "ListJobs without a token succeeded")
        except grpc.RpcError as e:
            check(e.code() == grpc.StatusCode.UNAUTHENTICATED, "expected UNAUTHENTICATED, got %s" % e.code())

        data = grid_obj(12)

        def chunks():
            yield mesh_pb2.UploadMeshRequest(header=mesh_pb2.UploadMeshHeader(file_name="grid.obj"))
            for off in range(0, len(data), 1000):
                yield mesh_pb2.UploadMeshRequest(chunk=data[off:off + 1000])

        info = meshes.UploadMesh(chunks(), metadata=auth, timeout=30 * SCALE)
        check(info.id == hashlib.sha256(data).hexdigest(), "mesh id is the SHA-256 of the bytes")
        check(info.num_vertices == 144 and info.num_faces == 242, "counts: %s" % info)

        try:
            meshes.GetMesh(mesh_pb2.GetMeshRequest(id="0" * 64), metadata=auth, timeout=10 * SCALE)
            check(False, "unknown mesh found")
        except grpc.RpcError as e:
            check(e.code() == grpc.StatusCode.NOT_FOUND, "expected NOT_FOUND, got %s" % e.code())

        js = job_pb2.JobSpec(mesh_id=info.id, source=0, target=143, method=job_pb2.METHOD_DE,
                             de=job_pb2.DeOptions(population=8, generations=20), seed=5, path_every=5)
        try:
            jobs.SubmitJob(job_pb2.SubmitJobRequest(spec=job_pb2.JobSpec(mesh_id=info.id, source=1, target=1)),
                           metadata=auth, timeout=10 * SCALE)
            check(False, "s == t accepted")
        except grpc.RpcError as e:
            check(e.code() == grpc.StatusCode.INVALID_ARGUMENT, "expected INVALID_ARGUMENT, got %s" % e.code())

        submitted = jobs.SubmitJob(job_pb2.SubmitJobRequest(spec=js, client_request_id="py-1"), metadata=auth,
                                   timeout=10 * SCALE)
        again = jobs.SubmitJob(job_pb2.SubmitJobRequest(spec=js, client_request_id="py-1"), metadata=auth, timeout=10 * SCALE)
        check(again.job_id == submitted.job_id and again.existing, "idempotent submit")

        events = list(jobs.WatchJob(job_pb2.WatchJobRequest(job_id=submitted.job_id), metadata=auth, timeout=60 * SCALE))
        seqs = [e.sequence for e in events]
        check(seqs == sorted(seqs) and len(set(seqs)) == len(seqs), "sequences increase: %s" % seqs)
        states = [e.state.state for e in events if e.WhichOneof("kind") == "state"]
        check(states[-1] == job_pb2.JOB_STATE_SUCCEEDED, "final state: %s" % states)
        results = [e.result for e in events if e.WhichOneof("kind") == "result"]
        check(len(results) == 1 and len(results[0].path.points) >= 2, "one result with a path")
        fetched = jobs.GetResult(job_pb2.GetResultRequest(job_id=submitted.job_id), metadata=auth, timeout=10 * SCALE)
        check(fetched == results[0], "GetResult equals the streamed result")
        p0 = fetched.path.points[0]
        check(abs(p0.x) < 1e-12 and abs(p0.y) < 1e-12, "path starts at the source vertex")

        # Resume after the first event: no state change lost.
        tail = list(jobs.WatchJob(job_pb2.WatchJobRequest(job_id=submitted.job_id, after_sequence=1),
                                  metadata=auth, timeout=60 * SCALE))
        check(all(e.sequence > 1 for e in tail), "resume skips seen events")
        check(tail[-1].state.state == job_pb2.JOB_STATE_SUCCEEDED, "resume ends with the final state")

        # Cancel a long job from Python while another thread watches it.
        long_spec = job_pb2.JobSpec(mesh_id=info.id, source=0, target=143, method=job_pb2.METHOD_DE,
                                    de=job_pb2.DeOptions(population=8, generations=1000000))
        long_job = jobs.SubmitJob(job_pb2.SubmitJobRequest(spec=long_spec), metadata=auth, timeout=10 * SCALE).job_id
        seen = []

        def watch():
            for e in jobs.WatchJob(job_pb2.WatchJobRequest(job_id=long_job), metadata=auth, timeout=60 * SCALE):
                seen.append(e)

        t = threading.Thread(target=watch)
        t.start()
        for _ in range(500):
            if any(e.WhichOneof("kind") == "progress" for e in seen):
                break
            time.sleep(0.01)
        jobs.CancelJob(job_pb2.CancelJobRequest(job_id=long_job), metadata=auth, timeout=10 * SCALE)
        t.join(30)
        check(not t.is_alive(), "watch ended after cancel")
        check(seen[-1].state.state == job_pb2.JOB_STATE_CANCELLED, "cancelled: %s" % seen[-1])

        listed = jobs.ListJobs(job_pb2.ListJobsRequest(), metadata=auth, timeout=10 * SCALE)
        check(len(listed.jobs) == 2, "two jobs listed")
        channel.close()
    finally:
        server.send_signal(signal.SIGTERM)
        try:
            rc = server.wait(timeout=20 * SCALE)
        except subprocess.TimeoutExpired:
            server.kill()
            rc = -1
        log = server.stderr.read().decode(errors="replace")
    check(rc == 0, "depathd exit status %s; log:\n%s" % (rc, log))
    check('"event":"job.finished"' in log, "structured job logs")
    print("python client test passed")


if __name__ == "__main__":
    main()
