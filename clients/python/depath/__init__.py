"""depath: energy-minimizing paths on triangle meshes (DE-Path), from Python.

    import depath, numpy as np
    with depath.Client("localhost:50051") as client:
        result = client.run((V, F), source=0, target=320, density=rho, progress=True)
        result.points        # (n, 3) numpy array, source first
        result.energy, result.length, result.metrics

A client of the depathd gRPC service: meshes go up once (by SHA-256), jobs run on the
server, progress streams back live, and results come back as numpy arrays.
"""
from ._channel import TLS
from ._client import Client
from ._errors import (AlreadyExists, Cancelled, DeadlineExceeded, DepathError, FailedPrecondition, Internal,
                      Interrupted, InvalidArgument, JobCancelled, NotFound, PermissionDenied, ResourceExhausted,
                      Unauthenticated, Unavailable)
from ._job import Job
from ._meshes import arrays_to_off
from ._progress import TextBar
from ._results import (Crossing, Crossings, Event, JobEvent, Path, ProgressEvent, Result, ResultEvent,
                       StateEvent)

__version__ = "0.1.0"

__all__ = [
    "Client", "Job", "TLS", "Result", "Path", "Crossing", "Crossings", "Event", "JobEvent", "ProgressEvent",
    "StateEvent", "ResultEvent", "TextBar", "arrays_to_off",
    "DepathError", "InvalidArgument", "NotFound", "AlreadyExists", "FailedPrecondition", "ResourceExhausted",
    "Unauthenticated", "PermissionDenied", "Unavailable", "DeadlineExceeded", "Internal", "Cancelled",
    "JobCancelled", "Interrupted",
]
