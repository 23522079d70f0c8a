"""Exceptions of the depath client: one class per gRPC status code the service documents.

Every exception carries `code` (a grpc.StatusCode) and `message` (the server's words), and
`job_id` when it describes a job's outcome. The classes also derive from the matching
built-in exception where one exists (InvalidArgument is a ValueError, NotFound a LookupError,
Unavailable a ConnectionError, DeadlineExceeded a TimeoutError), so generic handlers work.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Dict, Optional, Type

import grpc

if TYPE_CHECKING:  # only for annotations: _results imports nothing from here
    from ._results import Result


class DepathError(Exception):
    """A failed call or a failed job: gRPC status `code`, the server's `message`."""

    def __init__(self, code: grpc.StatusCode, message: str, *, doing: str = "", job_id: Optional[str] = None):
        self.code = code
        self.message = message
        self.doing = doing
        self.job_id = job_id
        text = "%s: %s" % (code.name, message)
        super().__init__("%s: %s" % (doing, text) if doing else text)


class InvalidArgument(DepathError, ValueError):
    """Bad input: a mesh that does not parse, a vertex out of range, a bad density, ..."""


class NotFound(DepathError, LookupError):
    """Unknown (or evicted) mesh id, unknown job id."""


class AlreadyExists(DepathError):
    """A request id reused for a different job."""


class FailedPrecondition(DepathError):
    """E.g. no path between source and target, or a result asked for before the job ended."""


class ResourceExhausted(DepathError):
    """A server limit: queue full, upload too large, population x vertices over the limit."""


class Unauthenticated(DepathError):
    """The server requires a token (Client(token=...)) and got none or another one."""


class PermissionDenied(DepathError):
    """The server refused the caller."""


class Unavailable(DepathError, ConnectionError):
    """The server cannot be reached or is shutting down."""


class DeadlineExceeded(DepathError, TimeoutError):
    """No answer in time (a call's timeout, or wait(timeout=...))."""


class Internal(DepathError):
    """A server-side failure that is not the caller's fault."""


class Cancelled(DepathError):
    """A cancelled call or job."""


class JobCancelled(Cancelled):
    """The job ended CANCELLED; `result` is its best path so far (None if it had none)."""

    def __init__(self, message: str, *, job_id: str, result: Optional["Result"] = None):
        super().__init__(grpc.StatusCode.CANCELLED, message, doing="job " + job_id, job_id=job_id)
        self.result = result


class Interrupted(KeyboardInterrupt):
    """Ctrl-C while waiting for a job: the job was cancelled on the server, and this carries its
    id and best path so far (`result`, None if it had none). `except KeyboardInterrupt` catches it."""

    def __init__(self, job_id: str, result: Optional["Result"] = None):
        super().__init__("interrupted: job %s cancelled" % job_id)
        self.job_id = job_id
        self.result = result


_BY_CODE: Dict[grpc.StatusCode, Type[DepathError]] = {
    grpc.StatusCode.INVALID_ARGUMENT: InvalidArgument,
    grpc.StatusCode.OUT_OF_RANGE: InvalidArgument,
    grpc.StatusCode.NOT_FOUND: NotFound,
    grpc.StatusCode.ALREADY_EXISTS: AlreadyExists,
    grpc.StatusCode.FAILED_PRECONDITION: FailedPrecondition,
    grpc.StatusCode.RESOURCE_EXHAUSTED: ResourceExhausted,
    grpc.StatusCode.UNAUTHENTICATED: Unauthenticated,
    grpc.StatusCode.PERMISSION_DENIED: PermissionDenied,
    grpc.StatusCode.UNAVAILABLE: Unavailable,
    grpc.StatusCode.DEADLINE_EXCEEDED: DeadlineExceeded,
    grpc.StatusCode.CANCELLED: Cancelled,
}


def error_for(code: grpc.StatusCode, message: str, *, doing: str = "", job_id: Optional[str] = None) -> DepathError:
    """The exception for a status code (Internal for codes without their own class)."""
    return _BY_CODE.get(code, Internal)(code, message, doing=doing, job_id=job_id)


def code_from_number(number: int) -> grpc.StatusCode:
    """grpc.StatusCode for a numeric code as carried in job events (unknown numbers: UNKNOWN)."""
    for code in grpc.StatusCode:
        if code.value[0] == number:
            return code
    return grpc.StatusCode.UNKNOWN


def from_rpc_error(error: grpc.RpcError, doing: str) -> DepathError:
    """The exception for a failed gRPC call; `doing` says what was being done."""
    code = error.code() if hasattr(error, "code") else grpc.StatusCode.UNKNOWN
    details = error.details() if hasattr(error, "details") else str(error)
    return error_for(code or grpc.StatusCode.UNKNOWN, details or "", doing=doing)
