"""What the client hands back: paths as numpy arrays, results, and the events of a job.

Built in one place from the protobuf messages (`*_from_proto`), immutable afterwards.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Dict, Iterator, NamedTuple, Optional, Union

import grpc
import numpy as np

from ._errors import code_from_number
from .v1 import job_pb2

STATE_NAMES = {
    job_pb2.JOB_STATE_UNSPECIFIED: "unspecified",
    job_pb2.JOB_STATE_QUEUED: "queued",
    job_pb2.JOB_STATE_RUNNING: "running",
    job_pb2.JOB_STATE_SUCCEEDED: "succeeded",
    job_pb2.JOB_STATE_FAILED: "failed",
    job_pb2.JOB_STATE_CANCELLED: "cancelled",
}
TERMINAL_STATES = ("succeeded", "failed", "cancelled")
METHOD_NAMES = {
    job_pb2.METHOD_UNSPECIFIED: "de",
    job_pb2.METHOD_DE: "de",
    job_pb2.METHOD_FMM: "fmm",
    job_pb2.METHOD_DESCENT: "descent",
}


class Crossing(NamedTuple):
    """Where one path point lies: vertex v0 (v1 == -1, t == 0), or (1 - t) * v0 + t * v1 on edge (v0, v1)."""

    v0: int
    v1: int
    t: float


@dataclass(frozen=True, eq=False)  # numpy fields: compare by identity
class Crossings:
    """Per path point: v0, v1 (-1 at a vertex) as int32 arrays and t as a float64 array."""

    v0: np.ndarray
    v1: np.ndarray
    t: np.ndarray

    def __len__(self) -> int:
        return len(self.v0)

    def __getitem__(self, i: int) -> Crossing:
        return Crossing(int(self.v0[i]), int(self.v1[i]), float(self.t[i]))

    def __iter__(self) -> Iterator[Crossing]:
        return (self[i] for i in range(len(self)))

    @property
    def is_vertex(self) -> np.ndarray:
        """Boolean mask: the point is a mesh vertex (not inside an edge)."""
        return self.v1 < 0


@dataclass(frozen=True, eq=False)  # numpy fields: compare by identity
class Path:
    """A polyline on the mesh from source to target.

    points: (n, 3) float64, source first; crossings: where each point lies; segment_faces:
    (n - 1,) int32, the face holding each segment."""

    points: np.ndarray
    crossings: Crossings
    segment_faces: np.ndarray


@dataclass(frozen=True, eq=False)  # numpy fields: compare by identity
class Result:
    """A job's final result (the fields of `depath solve`'s JSON result)."""

    job_id: str
    path: Path
    energy: float          # energy of the path, in the chosen energy's units
    length: float          # Euclidean length of the path
    method: str            # "de", "fmm" or "descent"
    refined: bool
    generations: int       # generations run (0 for fmm / descent)
    evaluations: int       # energy evaluations
    seconds: float         # server-side wall-clock time of the solve
    fmm_energy: float      # energy of the fmm baseline path on the same problem
    metrics: Dict[str, float] = field(default_factory=dict)  # "normalized_energy", "mean_slope_error", ...
    stop_reason: str = ""  # "converged", "max_generations", "stalled" or "cancelled"

    @property
    def points(self) -> np.ndarray:
        """(n, 3) float64 array of the path's points, source first."""
        return self.path.points

    @property
    def crossings(self) -> Crossings:
        return self.path.crossings


@dataclass(frozen=True)
class Event:
    """One numbered event of a job (sequence 1, 2, 3, ...; time_unix is the server's clock)."""

    job_id: str
    sequence: int
    time_unix: float


@dataclass(frozen=True, eq=False)  # numpy fields: compare by identity
class ProgressEvent(Event):
    """Per-generation progress (methods without generations report once, as generation 0)."""

    generation: int
    max_generations: int
    best_energy: float
    mean_energy: float
    evaluations: int
    improvements: int
    elapsed_seconds: float
    best_path: Optional[Path]  # set every `path_every` generations, else None


@dataclass(frozen=True)
class StateEvent(Event):
    """A state change: "queued", "running", "succeeded", "failed" or "cancelled".

    code / message: for a failed or cancelled job, the gRPC status and reason."""

    state: str
    code: grpc.StatusCode
    message: str

    @property
    def terminal(self) -> bool:
        return self.state in TERMINAL_STATES


@dataclass(frozen=True, eq=False)  # numpy fields: compare by identity
class ResultEvent(Event):
    """The final result, sent once just before the terminal state."""

    result: Result


JobEvent = Union[ProgressEvent, StateEvent, ResultEvent]


def path_from_proto(p: job_pb2.Path) -> Path:
    points = np.array([(q.x, q.y, q.z) for q in p.points], dtype=np.float64).reshape(-1, 3)
    crossings = Crossings(v0=np.array([c.v0 for c in p.crossings], dtype=np.int32),
                          v1=np.array([c.v1 for c in p.crossings], dtype=np.int32),
                          t=np.array([c.t for c in p.crossings], dtype=np.float64))
    return Path(points=points, crossings=crossings, segment_faces=np.array(p.segment_faces, dtype=np.int32))


def result_from_proto(job_id: str, r: job_pb2.JobResult) -> Result:
    return Result(job_id=job_id, path=path_from_proto(r.path), energy=r.energy, length=r.length,
                  method=METHOD_NAMES.get(r.method, str(r.method)), refined=r.refined, generations=r.generations,
                  evaluations=r.evaluations, seconds=r.seconds, fmm_energy=r.fmm_energy,
                  metrics={m.name: m.value for m in r.metrics}, stop_reason=r.stop_reason)


def event_from_proto(e: job_pb2.JobEvent) -> Optional[JobEvent]:
    """The event, or None for a kind this client does not know (a newer server)."""
    job_id, sequence, time_unix = e.job_id, e.sequence, e.time_unix
    kind = e.WhichOneof("kind")
    if kind == "progress":
        p = e.progress
        return ProgressEvent(job_id, sequence, time_unix, generation=p.generation, max_generations=p.max_generations,
                             best_energy=p.best_energy, mean_energy=p.mean_energy, evaluations=p.evaluations,
                             improvements=p.improvements, elapsed_seconds=p.elapsed_seconds,
                             best_path=path_from_proto(p.best_path) if p.HasField("best_path") else None)
    if kind == "state":
        s = e.state
        return StateEvent(job_id, sequence, time_unix, state=STATE_NAMES.get(s.state, str(s.state)),
                          code=code_from_number(s.error_code), message=s.message)
    if kind == "result":
        return ResultEvent(job_id, sequence, time_unix, result=result_from_proto(e.job_id, e.result))
    return None
