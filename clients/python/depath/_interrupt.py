"""Ctrl-C while waiting for a job, turned into a cancellation on the server.

A KeyboardInterrupt raised in the middle of gRPC's Python code can leave one of its locks
held, after which every call on the channel hangs (seen here about once in 40 tries). So,
while a wait runs in the main thread with Python's default SIGINT handler, the first Ctrl-C
only sets a flag; a helper thread then sends CancelJob, and the wait goes on until the
server reports the job cancelled (with its best path so far), exactly like the C++ CLI. A
second Ctrl-C raises KeyboardInterrupt at once.
"""
from __future__ import annotations

import signal
import threading
from types import FrameType, TracebackType
from typing import Any, Callable, Optional, Type


class CancelOnInterrupt:
    """Context manager: `requested` is set by the first Ctrl-C, which also calls `cancel()`
    from a helper thread. Does nothing outside the main thread or when the program has its own
    SIGINT handler."""

    def __init__(self, cancel: Callable[[], None]):
        self.requested = threading.Event()
        self._cancel = cancel
        self._done = threading.Event()
        self._wake = threading.Event()  # set by the first Ctrl-C or at the end: no polling delay
        self._previous: Any = None
        self._thread: Optional[threading.Thread] = None

    def __enter__(self) -> "CancelOnInterrupt":
        if (threading.current_thread() is threading.main_thread()
                and signal.getsignal(signal.SIGINT) is signal.default_int_handler):
            self._previous = signal.signal(signal.SIGINT, self._on_interrupt)
            self._thread = threading.Thread(target=self._cancel_when_requested, name="depath-cancel", daemon=True)
            self._thread.start()
        return self

    def __exit__(self, kind: Optional[Type[BaseException]], value: Optional[BaseException],
                 tb: Optional[TracebackType]) -> None:
        if self._thread is not None:
            signal.signal(signal.SIGINT, self._previous)
            self._done.set()
            self._wake.set()
            self._thread.join()

    def _on_interrupt(self, signum: int, frame: Optional[FrameType]) -> None:
        if self.requested.is_set():
            raise KeyboardInterrupt
        self.requested.set()
        self._wake.set()

    def _cancel_when_requested(self) -> None:
        self._wake.wait()
        if self.requested.is_set() and not self._done.is_set():
            self._cancel()
