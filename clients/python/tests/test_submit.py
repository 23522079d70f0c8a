"""Submitting: idempotent request ids, listing jobs."""
import time
import uuid

import grpc
import pytest

import depath
from conftest import TIME_SCALE, grid

V, F = grid(7)


def test_request_id_makes_resubmission_idempotent(client):
    key = "py-test-" + uuid.uuid4().hex
    first = client.submit((V, F), 0, 48, population=6, generations=5, seed=1, request_id=key)
    again = client.submit((V, F), 0, 48, population=6, generations=5, seed=1, request_id=key)
    assert again.id == first.id
    with pytest.raises(depath.AlreadyExists) as caught:
        client.submit((V, F), 0, 47, population=6, generations=5, seed=1, request_id=key)
    assert caught.value.code == grpc.StatusCode.ALREADY_EXISTS
    first.wait(timeout=60 * TIME_SCALE)
    assert first.info().client_request_id == key


def test_server_logs_the_job_as_json(client, server):
    job = client.submit((V, F), 0, 48, method="fmm")
    job.wait(timeout=60 * TIME_SCALE)
    deadline = time.monotonic() + 10 * TIME_SCALE
    while not any('"event":"job.finished"' in line and job.id in line for line in server.log().splitlines()):
        assert time.monotonic() < deadline, "no json job.finished line for %s" % job.id
        time.sleep(0.05)


def test_list_jobs_by_state_and_mesh(client):
    mesh_id = client.upload((V * 2, F))
    done = client.submit(mesh_id, 0, 48, method="fmm")
    done.wait(timeout=60 * TIME_SCALE)
    listed = client.list_jobs(mesh_id=mesh_id)
    assert [j.job_id for j in listed] == [done.id]
    assert done.id in [j.job_id for j in client.list_jobs(states=["succeeded"])]
    assert done.id not in [j.job_id for j in client.list_jobs(states=["running", "queued"])]
