"""TLS and mutual TLS with real certificates (made here with openssl), when depathd has them
(SPEC §3: --tls-cert / --tls-key / --tls-client-ca). Skipped for a depathd built without them."""
import shutil
import subprocess

import pytest

import depath
from conftest import TIME_SCALE, binary, grid

V, F = grid(6)


def depathd_has_tls():
    help_text = subprocess.run([binary("DEPATHD", "server/depathd"), "--help"], capture_output=True, text=True)
    return "--tls-cert" in help_text.stdout + help_text.stderr


pytestmark = pytest.mark.skipif(not depathd_has_tls(), reason="this depathd has no --tls-cert yet")


def openssl(*args, cwd):
    tool = shutil.which("openssl")
    assert tool, "openssl (Debian package openssl) is needed to make test certificates"
    subprocess.run([tool, *map(str, args)], cwd=cwd, check=True, capture_output=True)


@pytest.fixture
def certs(tmp_path):
    """A CA, a server certificate for DNS:depathd / IP:127.0.0.1 and a client certificate, all signed by it."""
    openssl("req", "-x509", "-newkey", "rsa:2048", "-nodes", "-keyout", "ca.key", "-out", "ca.crt", "-days", "2",
            "-subj", "/CN=depath test CA", cwd=tmp_path)
    (tmp_path / "san.ext").write_text("subjectAltName=DNS:depathd,IP:127.0.0.1\n")
    for name in ("server", "client"):
        openssl("req", "-newkey", "rsa:2048", "-nodes", "-keyout", name + ".key", "-out", name + ".csr", "-subj",
                "/CN=" + ("depathd" if name == "server" else "depath client"), cwd=tmp_path)
        openssl("x509", "-req", "-in", name + ".csr", "-CA", "ca.crt", "-CAkey", "ca.key", "-CAcreateserial",
                "-out", name + ".crt", "-days", "2", "-extfile", "san.ext", cwd=tmp_path)
    return tmp_path


def refused(client):
    with pytest.raises((depath.Unavailable, depath.DeadlineExceeded)):
        client.list_jobs()


def test_tls(start_server, certs):
    server = start_server("--tls-cert", certs / "server.crt", "--tls-key", certs / "server.key")
    with depath.Client(server.address, tls=depath.TLS(ca=certs / "ca.crt"), timeout=30 * TIME_SCALE) as c:
        assert c.run((V, F), 0, 35, method="fmm").points.shape[1] == 3
    with depath.Client(server.address, tls=depath.TLS(ca=(certs / "ca.crt").read_bytes(), server_name="depathd"),
                       timeout=30 * TIME_SCALE) as c:
        assert c.list_jobs()
    with depath.Client(server.address, timeout=2 * TIME_SCALE) as plain:
        refused(plain)
    with depath.Client(server.address, tls=True, timeout=2 * TIME_SCALE) as untrusted:  # system roots
        refused(untrusted)


def test_mutual_tls(start_server, certs):
    server = start_server("--tls-cert", certs / "server.crt", "--tls-key", certs / "server.key",
                          "--tls-client-ca", certs / "ca.crt")
    with depath.Client(server.address, tls=depath.TLS(ca=certs / "ca.crt"), timeout=2 * TIME_SCALE) as anonymous:
        refused(anonymous)
    tls = depath.TLS(ca=certs / "ca.crt", cert=certs / "client.crt", key=certs / "client.key")
    with depath.Client(server.address, tls=tls, timeout=30 * TIME_SCALE) as c:
        assert c.run((V, F), 0, 35, method="fmm").points.shape[1] == 3


def test_tls_arguments_and_environment(start_server, certs, monkeypatch):
    """tls_ca / tls_cert / tls_key, and DEPATH_TLS_CA / _CERT / _KEY as the CLI reads them."""
    server = start_server("--tls-cert", certs / "server.crt", "--tls-key", certs / "server.key",
                          "--tls-client-ca", certs / "ca.crt")
    with depath.Client(server.address, tls_ca=certs / "ca.crt", tls_cert=certs / "client.crt",
                       tls_key=certs / "client.key", timeout=30 * TIME_SCALE) as c:
        assert c.list_jobs() == []
    with depath.Client(server.address, tls_ca=certs / "ca.crt", timeout=2 * TIME_SCALE) as anonymous:
        refused(anonymous)
    monkeypatch.setenv("DEPATH_TLS_CA", str(certs / "ca.crt"))
    monkeypatch.setenv("DEPATH_TLS_CERT", str(certs / "client.crt"))
    monkeypatch.setenv("DEPATH_TLS_KEY", str(certs / "client.key"))
    with depath.Client(server.address, timeout=30 * TIME_SCALE) as c:
        assert c.list_jobs() == []
    with depath.Client(server.address, tls=False, timeout=2 * TIME_SCALE) as plain:  # explicit: no TLS
        refused(plain)
    monkeypatch.delenv("DEPATH_TLS_KEY")
    with pytest.raises(ValueError, match="go together"):
        depath.Client(server.address)
