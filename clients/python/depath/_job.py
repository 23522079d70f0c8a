"""A job on the server: watch its events (resuming after a dropped connection), wait for its
result, cancel it. Ctrl-C while waiting cancels the job on the server (see _interrupt)."""
from __future__ import annotations

import time
from typing import TYPE_CHECKING, Iterator, Optional

import grpc

from ._errors import DeadlineExceeded, DepathError, Interrupted, JobCancelled, Unavailable, error_for, from_rpc_error
from ._interrupt import CancelOnInterrupt
from ._progress import ProgressOption, reporter
from ._results import (STATE_NAMES, JobEvent, ProgressEvent, Result, ResultEvent, StateEvent, event_from_proto,
                       result_from_proto)
from .v1 import job_pb2

if TYPE_CHECKING:
    from ._client import Client

# A dropped watch is resumed on these codes (the server restarting, a network blip).
_RETRYABLE = (grpc.StatusCode.UNAVAILABLE, grpc.StatusCode.DEADLINE_EXCEEDED, grpc.StatusCode.UNKNOWN,
              grpc.StatusCode.INTERNAL)


class Job:
    """A submitted job. Get one from Client.submit or Client.job(job_id)."""

    def __init__(self, client: "Client", job_id: str):
        self._client = client
        self.id = job_id

    def __repr__(self) -> str:
        return "Job(%r)" % self.id

    # ---- queries ---------------------------------------------------------------------------

    def info(self) -> job_pb2.JobInfo:
        """The server's JobInfo: state, spec, times, last progress, queue position."""
        return self._client._call(self._client._jobs.GetJob, job_pb2.GetJobRequest(job_id=self.id),
                                  "looking up job " + self.id)

    @property
    def state(self) -> str:
        """"queued", "running", "succeeded", "failed" or "cancelled" (asks the server)."""
        return STATE_NAMES.get(self.info().state, "unspecified")

    def cancel(self) -> str:
        """Asks the server to stop the job (a running job ends CANCELLED with its best path so
        far). Idempotent. Returns the state right after the request."""
        info = self._client._call(self._client._jobs.CancelJob, job_pb2.CancelJobRequest(job_id=self.id),
                                  "cancelling job " + self.id)
        return STATE_NAMES.get(info.state, "unspecified")

    # ---- events ----------------------------------------------------------------------------

    def watch(self, after_sequence: int = 0, *, timeout: Optional[float] = None) -> Iterator[JobEvent]:
        """Yields the job's events after `after_sequence` until its terminal state (included).

        A dropped connection or a restarting server is retried with backoff and the stream
        resumed after the last sequence seen, so no state change and no result is missed
        (progress may be coalesced). Gives up with Unavailable after the client's
        `reconnect_seconds` without any event; with DeadlineExceeded once `timeout` seconds
        have passed in total."""
        client = self._client
        cursor = after_sequence
        deadline = None if timeout is None else time.monotonic() + timeout
        give_up = time.monotonic() + client.reconnect_seconds
        backoff = 0.2
        while True:
            remaining = None if deadline is None else deadline - time.monotonic()
            if remaining is not None and remaining <= 0:
                raise DeadlineExceeded(grpc.StatusCode.DEADLINE_EXCEEDED,
                                       "no terminal state within %gs" % (timeout or 0),
                                       doing="watching job " + self.id, job_id=self.id)
            stream = client._jobs.WatchJob(job_pb2.WatchJobRequest(job_id=self.id, after_sequence=cursor),
                                           metadata=client._metadata, timeout=remaining)
            failure: Optional[grpc.RpcError] = None
            try:
                for message in stream:
                    cursor = message.sequence
                    backoff = 0.2
                    give_up = time.monotonic() + client.reconnect_seconds
                    event = event_from_proto(message)
                    if event is None:
                        continue
                    yield event
                    if isinstance(event, StateEvent) and event.terminal:
                        return
            except grpc.RpcError as e:
                failure = e
            finally:
                stream.cancel()  # no-op after the end; frees the call when the caller stops early
            if failure is not None and failure.code() not in _RETRYABLE:
                raise from_rpc_error(failure, "watching job " + self.id)
            if deadline is not None and time.monotonic() >= deadline:
                continue  # reported at the top of the loop
            if time.monotonic() > give_up:
                reason = failure.details() if failure is not None else "the stream ended before the job did"
                raise Unavailable(grpc.StatusCode.UNAVAILABLE, "gave up reconnecting after %gs: %s"
                                  % (client.reconnect_seconds, reason), doing="watching job " + self.id,
                                  job_id=self.id)
            time.sleep(backoff)
            backoff = min(2.0, backoff * 2)

    # ---- results ---------------------------------------------------------------------------

    def wait(self, progress: ProgressOption = None, *, timeout: Optional[float] = None) -> Result:
        """Waits for the job to end and returns its result, showing progress (see
        depath._progress: None, True for a text bar, a tqdm bar, or a callable).

        Raises the job's own error for a FAILED job (e.g. FailedPrecondition "no path"),
        JobCancelled (with .result = best path so far) for a CANCELLED one. Ctrl-C cancels the
        job on the server, waits for its end and raises depath.Interrupted (a
        KeyboardInterrupt) with the best path so far; a second Ctrl-C stops waiting at once."""
        show = reporter(progress)
        result: Optional[Result] = None
        terminal: Optional[StateEvent] = None
        with CancelOnInterrupt(self._cancel_quietly) as interrupt:
            try:
                for event in self.watch(timeout=timeout):
                    if isinstance(event, ProgressEvent):
                        show(event)
                    elif isinstance(event, ResultEvent):
                        result = event.result
                    elif event.terminal:
                        terminal = event
            except KeyboardInterrupt:
                # Not turned into a request (second Ctrl-C, a thread, the program's own handler):
                # gRPC's channel may be stuck now, so cancel over a new one.
                show.close()
                self._client._cancel_on_new_channel(self.id)
                raise Interrupted(self.id, result) from None
        show.close()
        if interrupt.requested.is_set():
            raise Interrupted(self.id, result)
        assert terminal is not None  # watch() only returns after the terminal state
        return self._outcome(terminal, result)

    def result(self, timeout: Optional[float] = None) -> Result:
        """The job's result, waiting for it to end if it has not (like wait(), silently)."""
        info = self.info()
        if STATE_NAMES.get(info.state) == "succeeded":
            return self._fetch_result()
        return self.wait(timeout=timeout)

    def _fetch_result(self) -> Result:
        reply = self._client._call(self._client._jobs.GetResult, job_pb2.GetResultRequest(job_id=self.id),
                                   "fetching the result of job " + self.id)
        return result_from_proto(self.id, reply)

    def _outcome(self, terminal: StateEvent, result: Optional[Result]) -> Result:
        if terminal.state == "succeeded":
            return result if result is not None else self._fetch_result()
        if terminal.state == "cancelled":
            raise JobCancelled(terminal.message or "cancelled", job_id=self.id, result=result)
        code = terminal.code if terminal.code != grpc.StatusCode.OK else grpc.StatusCode.INTERNAL
        raise error_for(code, terminal.message, doing="job " + self.id + " failed", job_id=self.id)

    def _cancel_quietly(self) -> None:
        try:
            self.cancel()
        except DepathError:
            pass  # the watch reports what happens to the job
