from google.protobuf.internal import containers as _containers
from google.protobuf import descriptor as _descriptor
from google.protobuf import message as _message
from typing import ClassVar as _ClassVar, Iterable as _Iterable, Mapping as _Mapping, Optional as _Optional, Union as _Union

DESCRIPTOR: _descriptor.FileDescriptor

class BoundingBox(_message.Message):
    __slots__ = ["max", "min"]
    MAX_FIELD_NUMBER: _ClassVar[int]
    MIN_FIELD_NUMBER: _ClassVar[int]
    max: Vec3
    min: Vec3
    def __init__(self, min: _Optional[_Union[Vec3, _Mapping]] = ..., max: _Optional[_Union[Vec3, _Mapping]] = ...) -> None: ...

class DeleteMeshRequest(_message.Message):
    __slots__ = ["id"]
    ID_FIELD_NUMBER: _ClassVar[int]
    id: str
    def __init__(self, id: _Optional[str] = ...) -> None: ...

class DeleteMeshResponse(_message.Message):
    __slots__ = []
    def __init__(self) -> None: ...

class GetMeshRequest(_message.Message):
    __slots__ = ["id"]
    ID_FIELD_NUMBER: _ClassVar[int]
    id: str
    def __init__(self, id: _Optional[str] = ...) -> None: ...

class ListMeshesRequest(_message.Message):
    __slots__ = []
    def __init__(self) -> None: ...

class ListMeshesResponse(_message.Message):
    __slots__ = ["cache_budget_bytes", "cache_bytes", "meshes"]
    CACHE_BUDGET_BYTES_FIELD_NUMBER: _ClassVar[int]
    CACHE_BYTES_FIELD_NUMBER: _ClassVar[int]
    MESHES_FIELD_NUMBER: _ClassVar[int]
    cache_budget_bytes: int
    cache_bytes: int
    meshes: _containers.RepeatedCompositeFieldContainer[MeshInfo]
    def __init__(self, meshes: _Optional[_Iterable[_Union[MeshInfo, _Mapping]]] = ..., cache_bytes: _Optional[int] = ..., cache_budget_bytes: _Optional[int] = ...) -> None: ...

class MeshInfo(_message.Message):
    __slots__ = ["already_present", "bounding_box", "cached", "format", "id", "jobs_using", "memory_bytes", "name", "num_boundary_edges", "num_components", "num_faces", "num_vertices", "size_bytes", "warnings"]
    ALREADY_PRESENT_FIELD_NUMBER: _ClassVar[int]
    BOUNDING_BOX_FIELD_NUMBER: _ClassVar[int]
    CACHED_FIELD_NUMBER: _ClassVar[int]
    FORMAT_FIELD_NUMBER: _ClassVar[int]
    ID_FIELD_NUMBER: _ClassVar[int]
    JOBS_USING_FIELD_NUMBER: _ClassVar[int]
    MEMORY_BYTES_FIELD_NUMBER: _ClassVar[int]
    NAME_FIELD_NUMBER: _ClassVar[int]
    NUM_BOUNDARY_EDGES_FIELD_NUMBER: _ClassVar[int]
    NUM_COMPONENTS_FIELD_NUMBER: _ClassVar[int]
    NUM_FACES_FIELD_NUMBER: _ClassVar[int]
    NUM_VERTICES_FIELD_NUMBER: _ClassVar[int]
    SIZE_BYTES_FIELD_NUMBER: _ClassVar[int]
    WARNINGS_FIELD_NUMBER: _ClassVar[int]
    already_present: bool
    bounding_box: BoundingBox
    cached: bool
    format: str
    id: str
    jobs_using: int
    memory_bytes: int
    name: str
    num_boundary_edges: int
    num_components: int
    num_faces: int
    num_vertices: int
    size_bytes: int
    warnings: _containers.RepeatedScalarFieldContainer[str]
    def __init__(self, id: _Optional[str] = ..., name: _Optional[str] = ..., format: _Optional[str] = ..., size_bytes: _Optional[int] = ..., num_vertices: _Optional[int] = ..., num_faces: _Optional[int] = ..., num_boundary_edges: _Optional[int] = ..., num_components: _Optional[int] = ..., bounding_box: _Optional[_Union[BoundingBox, _Mapping]] = ..., warnings: _Optional[_Iterable[str]] = ..., memory_bytes: _Optional[int] = ..., already_present: bool = ..., jobs_using: _Optional[int] = ..., cached: bool = ...) -> None: ...

class UploadMeshHeader(_message.Message):
    __slots__ = ["file_name", "format", "size_bytes"]
    FILE_NAME_FIELD_NUMBER: _ClassVar[int]
    FORMAT_FIELD_NUMBER: _ClassVar[int]
    SIZE_BYTES_FIELD_NUMBER: _ClassVar[int]
    file_name: str
    format: str
    size_bytes: int
    def __init__(self, file_name: _Optional[str] = ..., format: _Optional[str] = ..., size_bytes: _Optional[int] = ...) -> None: ...

class UploadMeshRequest(_message.Message):
    __slots__ = ["chunk", "header"]
    CHUNK_FIELD_NUMBER: _ClassVar[int]
    HEADER_FIELD_NUMBER: _ClassVar[int]
    chunk: bytes
    header: UploadMeshHeader
    def __init__(self, header: _Optional[_Union[UploadMeshHeader, _Mapping]] = ..., chunk: _Optional[bytes] = ...) -> None: ...

class Vec3(_message.Message):
    __slots__ = ["x", "y", "z"]
    X_FIELD_NUMBER: _ClassVar[int]
    Y_FIELD_NUMBER: _ClassVar[int]
    Z_FIELD_NUMBER: _ClassVar[int]
    x: float
    y: float
    z: float
    def __init__(self, x: _Optional[float] = ..., y: _Optional[float] = ..., z: _Optional[float] = ...) -> None: ...
