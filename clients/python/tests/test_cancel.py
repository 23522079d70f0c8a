"""Cancelling: Job.cancel from Python, and Ctrl-C in a script running Client.run."""
import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import depath
from conftest import TIME_SCALE, grid

V, F = grid(12, lambda x, y: 0.3 * np.sin(3 * x) * np.cos(2 * y))
ENDLESS = dict(population=8, generations=1000000)


def first_progress(job):
    for event in job.watch(timeout=60 * TIME_SCALE):
        if isinstance(event, depath.ProgressEvent):
            return event
    raise AssertionError("the job ended before any progress")


def test_cancel_a_running_job_keeps_its_best_path(client):
    job = client.submit((V, F), 0, 143, **ENDLESS)
    first_progress(job)
    assert job.cancel() in ("running", "cancelled")
    # Liveness: the server stops a job within a generation; the bound is generous.
    events = list(job.watch(timeout=30 * TIME_SCALE))
    assert events[-1].state == "cancelled" and events[-1].terminal
    assert job.state == "cancelled"
    with pytest.raises(depath.JobCancelled) as caught:
        job.result()
    err = caught.value
    assert err.code.name == "CANCELLED" and err.job_id == job.id and isinstance(err, depath.DepathError)
    assert err.result is not None and err.result.stop_reason == "cancelled"
    np.testing.assert_allclose(err.result.points[[0, -1]], V[[0, 143]], atol=1e-6)
    assert job.cancel() == "cancelled"  # idempotent


def test_cancel_a_queued_job(start_server):
    server = start_server("--max-running-jobs", "1")
    with depath.Client(server.address, timeout=30 * TIME_SCALE) as c:
        running = c.submit((V, F), 0, 143, **ENDLESS)
        first_progress(running)
        queued = c.submit((V, F), 0, 143, **ENDLESS)
        assert queued.state == "queued" and queued.info().queue_position == 1
        queued.cancel()
        events = list(queued.watch(timeout=30 * TIME_SCALE))
        assert events[-1].state == "cancelled"
        assert not [e for e in events if isinstance(e, depath.ProgressEvent)]
        running.cancel()
        assert list(running.watch(timeout=30 * TIME_SCALE))[-1].state == "cancelled"


SCRIPT = r"""
import json, sys
import numpy as np
import depath
V, F = [np.array(a) for a in json.loads(sys.argv[2])]
client = depath.Client(sys.argv[1])
announced = []
def progress(p):
    if not announced:
        announced.append(p)
        print("progress", flush=True)
try:
    client.run((V, F), 0, 143, population=8, generations=1000000, progress=progress)
    print(json.dumps({"outcome": "finished"}))
except depath.Interrupted as e:
    print(json.dumps({"outcome": "interrupted", "job": e.job_id, "isinstance": isinstance(e, KeyboardInterrupt),
                      "points": None if e.result is None else len(e.result.points),
                      "stop": None if e.result is None else e.result.stop_reason}), flush=True)
"""


def test_ctrl_c_cancels_the_job_on_the_server(server, client):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    child = subprocess.Popen([sys.executable, "-c", SCRIPT, server.address, json.dumps([V.tolist(), F.tolist()])],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        line = child.stdout.readline()
        assert line == "progress\n", child.stderr.read()
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=60 * TIME_SCALE)
    finally:
        if child.poll() is None:
            child.kill()
    assert child.returncode == 0, err
    report = json.loads(out)
    assert report["outcome"] == "interrupted" and report["isinstance"], report
    assert report["stop"] == "cancelled" and report["points"] >= 2
    assert client.job(report["job"]).state == "cancelled"
