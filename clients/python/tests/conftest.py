"""Fixtures: a real depathd (started here, stopped at the end, its exit status checked), the
depath CLI for reference results, meshes as files and as numpy arrays.

Binaries come from DEPATHD / DEPATH_CLI (ctest sets them), else from the repository's build/.
Liveness bounds are multiplied by DEPATH_TEST_TIME_SCALE (sanitizer builds set it higher).
"""
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest

import depath

REPO = Path(__file__).resolve().parents[3]
# ctest installs the package with pip and names the target: the tests must use that copy.
if os.environ.get("DEPATH_PYTHON_SITE"):
    assert Path(depath.__file__).resolve().is_relative_to(Path(os.environ["DEPATH_PYTHON_SITE"]).resolve()), \
        "testing %s instead of the installed package" % depath.__file__
TIME_SCALE = float(os.environ.get("DEPATH_TEST_TIME_SCALE") or 1)
KITTEN = REPO / "tests" / "data" / "kitten.off"


def binary(env, relative):
    path = os.environ.get(env) or str(REPO / "build" / relative)
    if not os.access(path, os.X_OK):
        raise RuntimeError("%s not found at %s: build the project (scripts/build.sh) or set %s" % (relative, path, env))
    return path


class Server:
    """A depathd process on 127.0.0.1 (a free port unless `port` is given), its state in its own
    data directory (WORKDIR/data unless `data_dir` is given: a restart on the same one)."""

    def __init__(self, workdir, *flags, port=0, data_dir=None):
        self.workdir = Path(workdir)
        self.workdir.mkdir(parents=True, exist_ok=True)
        self.data_dir = Path(data_dir) if data_dir else self.workdir / "data"
        port_file = self.workdir / "port"
        if port_file.exists():
            port_file.unlink()
        self.log_path = self.workdir / "depathd.log"
        self._log = open(self.log_path, "ab")
        self.killed = False
        self.process = subprocess.Popen([binary("DEPATHD", "server/depathd"), "--listen", "127.0.0.1:%d" % port,
                                         "--port-file", str(port_file), "--data-dir", str(self.data_dir),
                                         "--threads", "2", "--log-format", "json", *flags],
                                        stdout=self._log, stderr=subprocess.STDOUT)
        deadline = time.monotonic() + 30 * TIME_SCALE
        while not (port_file.exists() and port_file.read_text().strip()):
            if self.process.poll() is not None or time.monotonic() > deadline:
                self.process.kill()
                raise RuntimeError("depathd did not start: %s" % self.log())
            time.sleep(0.02)
        self.port = int(port_file.read_text())
        self.address = "127.0.0.1:%d" % self.port

    def log(self):
        return self.log_path.read_text(errors="replace")

    def logged(self, event):
        """The JSON log entries of one event name (e.g. "job.checkpointed", logged at debug level)."""
        entries = (json.loads(line) for line in self.log().splitlines() if line.startswith("{"))
        return [e for e in entries if e.get("event") == event]

    def kill(self):
        """SIGKILL (a crash); stop() then reports nothing."""
        self.process.kill()
        self.process.wait()
        self.killed = True

    def stop(self):
        """SIGTERM, then the exit status (0 = a graceful shutdown; 0 too after kill())."""
        if self.killed:
            self._log.close()
            return 0
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
            try:
                self.process.wait(timeout=30 * TIME_SCALE)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
                self._log.close()
                raise AssertionError("depathd did not stop within the shutdown bound:\n" + self.log())
        self._log.close()
        return self.process.returncode


@pytest.fixture(scope="session")
def server(tmp_path_factory):
    s = Server(tmp_path_factory.mktemp("depathd"))
    yield s
    rc = s.stop()
    assert rc == 0, "depathd exit status %s:\n%s" % (rc, s.log())


@pytest.fixture
def start_server(tmp_path):
    """Factory for servers with their own flags; each is stopped (and checked) at teardown."""
    started = []

    def start(*flags, port=0, data_dir=None):
        s = Server(tmp_path / ("depathd%d" % len(started)), *flags, port=port, data_dir=data_dir)
        started.append(s)
        return s

    yield start
    for s in started:
        rc = s.stop()
        assert rc == 0, "depathd exit status %s:\n%s" % (rc, s.log())


@pytest.fixture
def client(server):
    with depath.Client(server.address, timeout=30 * TIME_SCALE) as c:
        yield c


@pytest.fixture(scope="session")
def cli():
    """Runs `depath ARGS...` and returns its stdout (fails the test with stderr on error)."""
    path = binary("DEPATH_CLI", "client/depath")

    def run(*args):
        p = subprocess.run([path, *map(str, args)], capture_output=True, text=True, timeout=600 * TIME_SCALE)
        assert p.returncode == 0, "depath %s failed (%d): %s" % (" ".join(map(str, args)), p.returncode, p.stderr)
        return p.stdout

    return run


def read_off(path):
    """(V, F) arrays of an OFF file of triangles, parsed independently of the project."""
    tok = Path(path).read_text().split()
    assert tok[0] == "OFF"
    nv, nf = int(tok[1]), int(tok[2])
    V = np.array(tok[4:4 + 3 * nv], dtype=np.float64).reshape(nv, 3)
    F = np.array(tok[4 + 3 * nv:4 + 3 * nv + 4 * nf], dtype=np.int64).reshape(nf, 4)
    assert (F[:, 0] == 3).all()
    return V, F[:, 1:]


def grid(n, height=None):
    """An n x n grid over [0, 1]^2 split along the (i, j) -> (i + 1, j + 1) diagonals; z = height(x, y) or 0.
    Vertex id = j * n + i."""
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    z = np.zeros_like(x) if height is None else height(x, y)
    V = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    a = (np.arange(n - 1)[None, :] + n * np.arange(n - 1)[:, None]).ravel()
    F = np.concatenate([np.column_stack([a, a + 1, a + n + 1]), np.column_stack([a, a + n + 1, a + n])])
    return V, F


@pytest.fixture(scope="session")
def kitten():
    return KITTEN


@pytest.fixture(scope="session")
def kitten_arrays():
    return read_off(KITTEN)
