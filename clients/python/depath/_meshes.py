"""Meshes as the client sends them: a file's bytes, or (V, F) numpy arrays written as OFF text.

The mesh id is the SHA-256 of the bytes sent (as on the server), so the same file or the same
arrays always get the same id and are uploaded once.
"""
from __future__ import annotations

import hashlib
import io
import os
import re
from dataclasses import dataclass
from typing import Tuple, Union

import grpc
import numpy as np
from numpy.typing import ArrayLike

from ._errors import InvalidArgument

MeshLike = Union[str, "os.PathLike[str]", Tuple[ArrayLike, ArrayLike]]

_MESH_ID = re.compile(r"[0-9a-f]{64}")


@dataclass(frozen=True)
class MeshBytes:
    """A mesh ready to upload: its bytes, a file name for messages and its format."""

    data: bytes
    file_name: str
    format: str  # "" = from file_name's extension (the server decides)

    @property
    def id(self) -> str:
        return hashlib.sha256(self.data).hexdigest()


def _invalid(message: str) -> InvalidArgument:
    return InvalidArgument(grpc.StatusCode.INVALID_ARGUMENT, message, doing="reading the mesh")


def arrays_to_off(vertices: ArrayLike, faces: ArrayLike) -> bytes:
    """OFF text for vertices (n, 3) and faces (m, k >= 3) of 0-based vertex ids.

    Coordinates are written with 17 significant digits, which identify a float64 exactly:
    the server reads the same numbers as from the file the arrays came from. Any float or
    integer dtype gives the same bytes for the same values."""
    V = np.asarray(vertices)
    F = np.asarray(faces)
    if V.ndim != 2 or V.shape[1] != 3 or V.shape[0] == 0:
        raise _invalid("vertices must be an (n, 3) array with n >= 1, got shape %s" % (V.shape,))
    if F.ndim != 2 or F.shape[1] < 3 or F.shape[0] == 0:
        raise _invalid("faces must be an (m, 3) array (or (m, k) polygons, k >= 3) with m >= 1, got shape %s"
                       % (F.shape,))
    if not (np.issubdtype(V.dtype, np.floating) or np.issubdtype(V.dtype, np.integer)):
        raise _invalid("vertices must be numbers, got dtype %s" % V.dtype)
    V = V.astype(np.float64)
    bad = np.flatnonzero(~np.isfinite(V).all(axis=1))
    if bad.size:
        raise _invalid("vertex %d has non-finite coordinates %s (%d such vertices)" % (bad[0], V[bad[0]], bad.size))
    if not np.issubdtype(F.dtype, np.integer):
        if not np.issubdtype(F.dtype, np.floating) or not np.array_equal(F, np.round(F)):
            raise _invalid("faces must hold integer vertex ids, got dtype %s" % F.dtype)
    F = F.astype(np.int64)
    out = io.BytesIO()
    out.write(b"OFF\n%d %d 0\n" % (V.shape[0], F.shape[0]))
    np.savetxt(out, V, fmt="%.17g")
    np.savetxt(out, np.column_stack([np.full(F.shape[0], F.shape[1], dtype=np.int64), F]), fmt="%d")
    return out.getvalue()


def is_mesh_id(mesh: object) -> bool:
    """True for a 64-hex-digit string that is not an existing file: the id of a server's mesh."""
    return isinstance(mesh, str) and _MESH_ID.fullmatch(mesh) is not None and not os.path.exists(mesh)


def mesh_bytes(mesh: MeshLike, name: str = "") -> MeshBytes:
    """The bytes to upload for a file path or a (vertices, faces) pair."""
    if isinstance(mesh, (tuple, list)):
        if len(mesh) != 2:
            raise _invalid("a mesh given as arrays must be a (vertices, faces) pair, got %d items" % len(mesh))
        return MeshBytes(arrays_to_off(mesh[0], mesh[1]), name or "arrays.off", "off")
    if isinstance(mesh, (str, os.PathLike)):
        path = os.fspath(mesh)
        try:
            with open(path, "rb") as f:
                data = f.read()
        except OSError as e:
            raise _invalid("mesh '%s' is neither a readable file nor a mesh id (%s)" % (path, e.strerror)) from None
        return MeshBytes(data, name or os.path.basename(path), "")
    raise TypeError("mesh must be a file path, a mesh id or a (vertices, faces) pair of arrays, got %r"
                    % type(mesh).__name__)
