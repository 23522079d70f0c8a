"""Progress display for Job.wait / Client.run(progress=...).

progress may be:
  None            nothing is shown;
  True / "bar"    a one-line bar on stderr (generation, best energy, ETA), no dependency;
  a tqdm bar      (anything with `update(n)` and a `total` attribute, e.g. tqdm.tqdm()): it
                  advances by generations and shows the best energy as its postfix;
  a callable      called with every depath.ProgressEvent.
"""
from __future__ import annotations

import sys
from typing import Any, Callable, Optional, TextIO

from ._results import ProgressEvent

ProgressOption = Any  # None | bool | "bar" | tqdm-like | Callable[[ProgressEvent], Any]


class _Silent:
    def __call__(self, event: ProgressEvent) -> None:
        pass

    def close(self) -> None:
        pass


class _Callback(_Silent):
    def __init__(self, fn: Callable[[ProgressEvent], Any]):
        self._fn = fn

    def __call__(self, event: ProgressEvent) -> None:
        self._fn(event)


class _Tqdm(_Silent):
    def __init__(self, bar: Any):
        self._bar = bar
        self._done = 0

    def __call__(self, event: ProgressEvent) -> None:
        if event.max_generations and self._bar.total != event.max_generations:
            self._bar.total = event.max_generations
            if hasattr(self._bar, "refresh"):
                self._bar.refresh()
        if event.generation > self._done:
            self._bar.update(event.generation - self._done)
            self._done = event.generation
        if hasattr(self._bar, "set_postfix"):
            self._bar.set_postfix(best="%.10g" % event.best_energy, refresh=False)

    def close(self) -> None:
        if hasattr(self._bar, "close"):
            self._bar.close()


class TextBar(_Silent):
    """`[#######.............] gen 35/100  best 59.1234567  ETA 4s` rewritten in place."""

    WIDTH = 24

    def __init__(self, stream: Optional[TextIO] = None):
        self._stream = stream if stream is not None else sys.stderr
        self._shown = False

    def __call__(self, event: ProgressEvent) -> None:
        total = max(event.max_generations, 1)
        done = min(max(event.generation, 0), total)
        filled = self.WIDTH * done // total
        eta = ""
        if 0 < done < total and event.elapsed_seconds > 0:
            eta = "  ETA %.0fs" % (event.elapsed_seconds * (total - done) / done)
        self._stream.write("\r[%s%s] gen %d/%d  best %.10g%s\033[K" % (
            "#" * filled, "." * (self.WIDTH - filled), event.generation, event.max_generations,
            event.best_energy, eta))
        self._stream.flush()
        self._shown = True

    def close(self) -> None:
        if self._shown:
            self._stream.write("\n")
            self._stream.flush()


def reporter(progress: ProgressOption) -> _Silent:
    """The reporter for a `progress=` option (see the module's doc)."""
    if progress is None or progress is False:
        return _Silent()
    if progress is True or progress == "bar":
        return TextBar()
    if hasattr(progress, "update") and hasattr(progress, "total"):
        return _Tqdm(progress)
    if callable(progress):
        return _Callback(progress)
    raise TypeError("progress must be None, True, 'bar', a tqdm-like bar or a callable, got %r" % (progress,))
