"""Live progress: numbered events, per-generation progress, best paths, resume, callbacks and bars."""
import io
import threading

import numpy as np
import pytest

import depath
from conftest import TIME_SCALE, grid

V, F = grid(12, lambda x, y: 0.3 * np.sin(3 * x) * np.cos(2 * y))


def test_watch_streams_numbered_events_ending_with_result_and_state(client):
    job = client.submit((V, F), 0, 143, population=8, generations=12, seed=5, path_every=4)
    events = list(job.watch(timeout=120 * TIME_SCALE))
    seqs = [e.sequence for e in events]
    assert seqs == sorted(set(seqs)) and seqs[0] >= 1
    assert all(e.job_id == job.id for e in events)
    states = [e for e in events if isinstance(e, depath.StateEvent)]
    assert states[-1] is events[-1] and states[-1].state == "succeeded" and states[-1].terminal
    assert "running" in [s.state for s in states]
    results = [e for e in events if isinstance(e, depath.ResultEvent)]
    assert len(results) == 1 and events.index(results[0]) == len(events) - 2
    result = results[0].result

    progress = [e for e in events if isinstance(e, depath.ProgressEvent)]
    gens = [p.generation for p in progress]
    assert gens == sorted(set(gens)) and 1 <= gens[0] and gens[-1] <= 12
    assert all(p.max_generations == 12 for p in progress)
    best = [p.best_energy for p in progress]
    assert all(b2 <= b1 for b1, b2 in zip(best, best[1:]))  # selection never loses the best
    assert all(p.mean_energy >= p.best_energy for p in progress)
    if gens[-1] == result.generations:
        assert progress[-1].best_energy == pytest.approx(result.energy, rel=1e-12)
    for p in progress:  # path_every=4: the best path so far, on generations 4, 8, 12
        if p.generation % 4 == 0:
            assert p.best_path is not None
            assert p.best_path.points.shape[1] == 3
            np.testing.assert_allclose(p.best_path.points[0], V[0], atol=1e-6)
            np.testing.assert_allclose(p.best_path.points[-1], V[143], atol=1e-6)
        else:
            assert p.best_path is None
    assert job.result().energy == result.energy  # GetResult = the streamed result
    assert job.state == "succeeded"


def test_watch_resumes_after_a_sequence(client):
    job = client.submit((V, F), 0, 143, population=8, generations=6, seed=2)
    full = list(job.watch(timeout=120 * TIME_SCALE))
    cut = full[len(full) // 2].sequence
    tail = list(job.watch(after_sequence=cut, timeout=120 * TIME_SCALE))
    assert tail and all(e.sequence > cut for e in tail)
    seqs = [e.sequence for e in tail]
    assert seqs == sorted(set(seqs)) and set(seqs) <= {e.sequence for e in full}
    # Progress may be coalesced on the way; state changes and the result never are.
    assert {e.sequence for e in full if e.sequence > cut and not isinstance(e, depath.ProgressEvent)} <= set(seqs)
    assert tail[-1].state == "succeeded"


def test_several_watchers_see_the_same_end(client):
    job = client.submit((V, F), 0, 143, population=8, generations=30, seed=4)
    ends = []

    def follow():
        events = list(job.watch(timeout=120 * TIME_SCALE))
        ends.append((events[-1].state, [e.result.energy for e in events if isinstance(e, depath.ResultEvent)]))

    threads = [threading.Thread(target=follow) for _ in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(180 * TIME_SCALE)
    assert len(ends) == 3 and len({repr(e) for e in ends}) == 1 and ends[0][0] == "succeeded"


def test_run_calls_the_progress_callback(client):
    seen = []
    res = client.run((V, F), 0, 143, population=8, generations=10, seed=3, progress=seen.append)
    assert seen and all(isinstance(p, depath.ProgressEvent) for p in seen)
    assert [p.generation for p in seen] == sorted({p.generation for p in seen})
    assert seen[-1].generation <= res.generations == 10


def test_run_draws_a_text_bar(client, capsys):
    client.run((V, F), 0, 143, population=8, generations=10, seed=3, progress=True)
    err = capsys.readouterr().err
    assert "gen 10/10" in err and "best " in err and err.endswith("\n")


class Bar:
    """What Client.run needs from a tqdm bar: total, update(n), set_postfix, close."""

    def __init__(self):
        self.total, self.n, self.postfix, self.closed = None, 0, None, False

    def update(self, n):
        self.n += n

    def set_postfix(self, refresh=True, **kw):
        self.postfix = kw

    def close(self):
        self.closed = True


def test_run_drives_a_tqdm_style_bar(client):
    bar = Bar()
    res = client.run((V, F), 0, 143, population=8, generations=10, seed=3, progress=bar)
    assert bar.total == 10 and bar.closed
    assert bar.n <= 10 and bar.n >= 1
    assert float(bar.postfix["best"]) >= res.energy


def test_text_bar_format():
    out = io.StringIO()
    bar = depath.TextBar(out)
    bar(depath.ProgressEvent("j", 3, 0.0, generation=25, max_generations=100, best_energy=1.5, mean_energy=2.0,
                             evaluations=500, improvements=3, elapsed_seconds=5.0, best_path=None))
    bar.close()
    assert out.getvalue() == "\r[######..................] gen 25/100  best 1.5  ETA 15s\033[K\n"
