"""A server started with --auth-token: calls need Client(token=...)."""
import grpc
import pytest

import depath
from conftest import TIME_SCALE, grid

V, F = grid(6)


def test_token_required(start_server):
    server = start_server("--auth-token", "s3cret-token")
    for token in (None, "wrong-token", "s3cret-token-longer"):
        with depath.Client(server.address, token=token, timeout=30 * TIME_SCALE) as c:
            for call in (c.list_jobs, lambda: c.upload((V, F)), lambda: c.job("x").info()):
                with pytest.raises(depath.Unauthenticated) as caught:
                    call()
                assert caught.value.code == grpc.StatusCode.UNAUTHENTICATED
    with depath.Client(server.address, token="s3cret-token", timeout=30 * TIME_SCALE) as c:
        job = c.submit((V, F), 0, 35, population=6, generations=5, seed=1)
        events = list(job.watch(timeout=60 * TIME_SCALE))
        assert events[-1].state == "succeeded"
        assert job.result().points.shape[1] == 3
        assert [j.job_id for j in c.list_jobs()] == [job.id]


def test_several_tokens_token_file_and_environment(start_server, tmp_path, monkeypatch):
    """depathd accepts each of several tokens; the client takes token_file, DEPATH_TOKEN, DEPATH_TOKEN_FILE."""
    (tmp_path / "server-tokens").write_text("# one per line\nfrom-file\n")
    server = start_server("--auth-token", "first", "--auth-token", "second", "--auth-token-file",
                          tmp_path / "server-tokens")
    for token in ("first", "second", "from-file"):
        with depath.Client(server.address, token=token, timeout=30 * TIME_SCALE) as c:
            assert c.list_jobs() == []
    (tmp_path / "client-token").write_text("second\n")
    with depath.Client(server.address, token_file=tmp_path / "client-token", timeout=30 * TIME_SCALE) as c:
        assert c.list_jobs() == []
    monkeypatch.setenv("DEPATH_TOKEN", "from-file")
    with depath.Client(server.address, timeout=30 * TIME_SCALE) as c:
        assert c.list_jobs() == []
    monkeypatch.delenv("DEPATH_TOKEN")
    monkeypatch.setenv("DEPATH_TOKEN_FILE", str(tmp_path / "client-token"))
    with depath.Client(server.address, timeout=30 * TIME_SCALE) as c:
        assert c.list_jobs() == []
    with depath.Client(server.address, token="third", timeout=30 * TIME_SCALE) as c:
        with pytest.raises(depath.Unauthenticated):
            c.list_jobs()
