"""Job options (keyword arguments of Client.submit / Client.run) -> a depath.v1.JobSpec.

Only the shape of the options is checked here (names, array shapes); the server checks the
values (ranges, lengths, finiteness) and answers INVALID_ARGUMENT naming the problem, the
same way for every client.
"""
from __future__ import annotations

import operator
from typing import Any, Dict, Optional

import grpc
import numpy as np
from numpy.typing import ArrayLike

from ._errors import InvalidArgument
from .v1 import job_pb2, mesh_pb2

ENERGIES = {
    "geodesic": job_pb2.ENERGY_KIND_GEODESIC,
    "vector_field": job_pb2.ENERGY_KIND_VECTOR_FIELD,
    "constant_slope": job_pb2.ENERGY_KIND_CONSTANT_SLOPE,
}
METHODS = {"de": job_pb2.METHOD_DE, "fmm": job_pb2.METHOD_FMM, "descent": job_pb2.METHOD_DESCENT}
AXES = {"x": job_pb2.AXIS_X, "y": job_pb2.AXIS_Y, "z": job_pb2.AXIS_Z}


def _invalid(message: str) -> InvalidArgument:
    return InvalidArgument(grpc.StatusCode.INVALID_ARGUMENT, message, doing="building the job")


def _choice(name: str, value: str, table: Dict[str, Any]) -> Any:
    key = str(value).lower()
    if key not in table:
        raise _invalid("%s must be one of %s, got %r" % (name, ", ".join(sorted(table)), value))
    return table[key]


def _int(name: str, value: Any, bits: int = 32, signed: bool = True) -> int:
    """An integer option that fits its protobuf field (else a message naming it, not protobuf's)."""
    i = operator.index(value)
    lo, hi = (-(1 << (bits - 1)), 1 << (bits - 1)) if signed else (0, 1 << bits)
    if not lo <= i < hi:
        raise _invalid("%s = %d is out of range [%d, %d]" % (name, i, lo, hi - 1))
    return i


def _density(values: ArrayLike) -> np.ndarray:
    a = np.asarray(values, dtype=np.float64)
    if a.ndim == 2 and a.shape[1] == 1:
        a = a[:, 0]
    if a.ndim != 1:
        raise _invalid("density must be one value per vertex (shape (n,)), got shape %s" % (a.shape,))
    return a


def _field(values: ArrayLike) -> np.ndarray:
    a = np.asarray(values, dtype=np.float64)
    if a.ndim != 2 or a.shape[1] != 3:
        raise _invalid("field must be one 3D vector per vertex (shape (n, 3)), got shape %s" % (a.shape,))
    return a


def job_spec(mesh_id: str, source: int, target: int, *,
             energy: str = "geodesic",
             density: Optional[ArrayLike] = None,
             field: Optional[ArrayLike] = None,
             field_from_height: bool = False,
             rotate: float = 0.0,
             slope: float = 0.0,
             up: str = "z",
             smoothness: float = 0.0,
             method: str = "de",
             refine: bool = False,
             population: Optional[int] = None,
             generations: Optional[int] = None,
             stall: Optional[int] = None,
             F: Optional[float] = None,
             CR: Optional[float] = None,
             strategy: Optional[str] = None,
             seed_with_problem: bool = False,
             seed: Optional[int] = None,
             path_every: int = 0) -> job_pb2.JobSpec:
    """The JobSpec for these options; None leaves a DE option at the server's default."""
    e = job_pb2.EnergySpec(kind=_choice("energy", energy, ENERGIES), field_from_height=bool(field_from_height),
                           rotate_degrees=float(rotate), slope=float(slope), up=_choice("up", up, AXES),
                           smoothness=float(smoothness))
    if density is not None:
        e.density.extend(_density(density).tolist())
    if field is not None:
        e.field.extend(mesh_pb2.Vec3(x=x, y=y, z=z) for x, y, z in _field(field).tolist())
    de = job_pb2.DeOptions(seed_with_problem=bool(seed_with_problem))
    if population is not None:
        de.population = _int("population", population)
    if generations is not None:
        de.generations = _int("generations", generations)
    if stall is not None:
        de.stall = _int("stall", stall)
    if F is not None:
        de.f = float(F)
    if CR is not None:
        de.cr = float(CR)
    if strategy is not None:
        de.strategy = str(strategy)
    spec = job_pb2.JobSpec(mesh_id=mesh_id, source=_int("source", source), target=_int("target", target), energy=e,
                           method=_choice("method", method, METHODS), refine=bool(refine), de=de,
                           path_every=_int("path_every", path_every))
    if seed is not None:
        spec.seed = _int("seed", seed, bits=64, signed=False)
    return spec
