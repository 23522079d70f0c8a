from depath.v1 import mesh_pb2 as _mesh_pb2
from google.protobuf.internal import containers as _containers
from google.protobuf.internal import enum_type_wrapper as _enum_type_wrapper
from google.protobuf import descriptor as _descriptor
from google.protobuf import message as _message
from typing import ClassVar as _ClassVar, Iterable as _Iterable, Mapping as _Mapping, Optional as _Optional, Union as _Union

AXIS_UNSPECIFIED: Axis
AXIS_X: Axis
AXIS_Y: Axis
AXIS_Z: Axis
DESCRIPTOR: _descriptor.FileDescriptor
ENERGY_KIND_CONSTANT_SLOPE: EnergyKind
ENERGY_KIND_GEODESIC: EnergyKind
ENERGY_KIND_UNSPECIFIED: EnergyKind
ENERGY_KIND_VECTOR_FIELD: EnergyKind
JOB_STATE_CANCELLED: JobState
JOB_STATE_FAILED: JobState
JOB_STATE_QUEUED: JobState
JOB_STATE_RUNNING: JobState
JOB_STATE_SUCCEEDED: JobState
JOB_STATE_UNSPECIFIED: JobState
METHOD_DE: Method
METHOD_DESCENT: Method
METHOD_FMM: Method
METHOD_UNSPECIFIED: Method

class CancelJobRequest(_message.Message):
    __slots__ = ["job_id"]
    JOB_ID_FIELD_NUMBER: _ClassVar[int]
    job_id: str
    def __init__(self, job_id: _Optional[str] = ...) -> None: ...

class Crossing(_message.Message):
    __slots__ = ["t", "v0", "v1"]
    T_FIELD_NUMBER: _ClassVar[int]
    V0_FIELD_NUMBER: _ClassVar[int]
    V1_FIELD_NUMBER: _ClassVar[int]
    t: float
    v0: int
    v1: int
    def __init__(self, v0: _Optional[int] = ..., v1: _Optional[int] = ..., t: _Optional[float] = ...) -> None: ...

class DeOptions(_message.Message):
    __slots__ = ["cr", "f", "generations", "population", "seed_with_problem", "stall", "strategy"]
    CR_FIELD_NUMBER: _ClassVar[int]
    F_FIELD_NUMBER: _ClassVar[int]
    GENERATIONS_FIELD_NUMBER: _ClassVar[int]
    POPULATION_FIELD_NUMBER: _ClassVar[int]
    SEED_WITH_PROBLEM_FIELD_NUMBER: _ClassVar[int]
    STALL_FIELD_NUMBER: _ClassVar[int]
    STRATEGY_FIELD_NUMBER: _ClassVar[int]
    cr: float
    f: float
    generations: int
    population: int
    seed_with_problem: bool
    stall: int
    strategy: str
    def __init__(self, population: _Optional[int] = ..., generations: _Optional[int] = ..., stall: _Optional[int] = ..., f: _Optional[float] = ..., cr: _Optional[float] = ..., strategy: _Optional[str] = ..., seed_with_problem: bool = ...) -> None: ...

class EnergySpec(_message.Message):
    __slots__ = ["density", "field", "field_from_height", "kind", "rotate_degrees", "slope", "smoothness", "up"]
    DENSITY_FIELD_NUMBER: _ClassVar[int]
    FIELD_FIELD_NUMBER: _ClassVar[int]
    FIELD_FROM_HEIGHT_FIELD_NUMBER: _ClassVar[int]
    KIND_FIELD_NUMBER: _ClassVar[int]
    ROTATE_DEGREES_FIELD_NUMBER: _ClassVar[int]
    SLOPE_FIELD_NUMBER: _ClassVar[int]
    SMOOTHNESS_FIELD_NUMBER: _ClassVar[int]
    UP_FIELD_NUMBER: _ClassVar[int]
    density: _containers.RepeatedScalarFieldContainer[float]
    field: _containers.RepeatedCompositeFieldContainer[_mesh_pb2.Vec3]
    field_from_height: bool
    kind: EnergyKind
    rotate_degrees: float
    slope: float
    smoothness: float
    up: Axis
    def __init__(self, kind: _Optional[_Union[EnergyKind, str]] = ..., density: _Optional[_Iterable[float]] = ..., field: _Optional[_Iterable[_Union[_mesh_pb2.Vec3, _Mapping]]] = ..., field_from_height: bool = ..., rotate_degrees: _Optional[float] = ..., slope: _Optional[float] = ..., up: _Optional[_Union[Axis, str]] = ..., smoothness: _Optional[float] = ...) -> None: ...

class GetJobRequest(_message.Message):
    __slots__ = ["job_id"]
    JOB_ID_FIELD_NUMBER: _ClassVar[int]
    job_id: str
    def __init__(self, job_id: _Optional[str] = ...) -> None: ...

class GetResultRequest(_message.Message):
    __slots__ = ["job_id"]
    JOB_ID_FIELD_NUMBER: _ClassVar[int]
    job_id: str
    def __init__(self, job_id: _Optional[str] = ...) -> None: ...

class JobEvent(_message.Message):
    __slots__ = ["job_id", "progress", "result", "sequence", "state", "time_unix"]
    JOB_ID_FIELD_NUMBER: _ClassVar[int]
    PROGRESS_FIELD_NUMBER: _ClassVar[int]
    RESULT_FIELD_NUMBER: _ClassVar[int]
    SEQUENCE_FIELD_NUMBER: _ClassVar[int]
    STATE_FIELD_NUMBER: _ClassVar[int]
    TIME_UNIX_FIELD_NUMBER: _ClassVar[int]
    job_id: str
    progress: Progress
    result: JobResult
    sequence: int
    state: StateChange
    time_unix: float
    def __init__(self, job_id: _Optional[str] = ..., sequence: _Optional[int] = ..., time_unix: _Optional[float] = ..., state: _Optional[_Union[StateChange, _Mapping]] = ..., progress: _Optional[_Union[Progress, _Mapping]] = ..., result: _Optional[_Union[JobResult, _Mapping]] = ...) -> None: ...

class JobInfo(_message.Message):
    __slots__ = ["client_request_id", "created_unix", "error_code", "error_message", "finished_unix", "has_result", "job_id", "last_progress", "last_sequence", "mesh_id", "queue_position", "spec", "started_unix", "state"]
    CLIENT_REQUEST_ID_FIELD_NUMBER: _ClassVar[int]
    CREATED_UNIX_FIELD_NUMBER: _ClassVar[int]
    ERROR_CODE_FIELD_NUMBER: _ClassVar[int]
    ERROR_MESSAGE_FIELD_NUMBER: _ClassVar[int]
    FINISHED_UNIX_FIELD_NUMBER: _ClassVar[int]
    HAS_RESULT_FIELD_NUMBER: _ClassVar[int]
    JOB_ID_FIELD_NUMBER: _ClassVar[int]
    LAST_PROGRESS_FIELD_NUMBER: _ClassVar[int]
    LAST_SEQUENCE_FIELD_NUMBER: _ClassVar[int]
    MESH_ID_FIELD_NUMBER: _ClassVar[int]
    QUEUE_POSITION_FIELD_NUMBER: _ClassVar[int]
    SPEC_FIELD_NUMBER: _ClassVar[int]
    STARTED_UNIX_FIELD_NUMBER: _ClassVar[int]
    STATE_FIELD_NUMBER: _ClassVar[int]
    client_request_id: str
    created_unix: float
    error_code: int
    error_message: str
    finished_unix: float
    has_result: bool
    job_id: str
    last_progress: Progress
    last_sequence: int
    mesh_id: str
    queue_position: int
    spec: JobSpec
    started_unix: float
    state: JobState
    def __init__(self, job_id: _Optional[str] = ..., state: _Optional[_Union[JobState, str]] = ..., mesh_id: _Optional[str] = ..., client_request_id: _Optional[str] = ..., spec: _Optional[_Union[JobSpec, _Mapping]] = ..., created_unix: _Optional[float] = ..., started_unix: _Optional[float] = ..., finished_unix: _Optional[float] = ..., last_progress: _Optional[_Union[Progress, _Mapping]] = ..., error_code: _Optional[int] = ..., error_message: _Optional[str] = ..., last_sequence: _Optional[int] = ..., queue_position: _Optional[int] = ..., has_result: bool = ...) -> None: ...

class JobResult(_message.Message):
    __slots__ = ["energy", "evaluations", "fmm_energy", "generations", "length", "method", "metrics", "path", "refined", "seconds", "stop_reason"]
    ENERGY_FIELD_NUMBER: _ClassVar[int]
    EVALUATIONS_FIELD_NUMBER: _ClassVar[int]
    FMM_ENERGY_FIELD_NUMBER: _ClassVar[int]
    GENERATIONS_FIELD_NUMBER: _ClassVar[int]
    LENGTH_FIELD_NUMBER: _ClassVar[int]
    METHOD_FIELD_NUMBER: _ClassVar[int]
    METRICS_FIELD_NUMBER: _ClassVar[int]
    PATH_FIELD_NUMBER: _ClassVar[int]
    REFINED_FIELD_NUMBER: _ClassVar[int]
    SECONDS_FIELD_NUMBER: _ClassVar[int]
    STOP_REASON_FIELD_NUMBER: _ClassVar[int]
    energy: float
    evaluations: int
    fmm_energy: float
    generations: int
    length: float
    method: Method
    metrics: _containers.RepeatedCompositeFieldContainer[Metric]
    path: Path
    refined: bool
    seconds: float
    stop_reason: str
    def __init__(self, path: _Optional[_Union[Path, _Mapping]] = ..., energy: _Optional[float] = ..., length: _Optional[float] = ..., method: _Optional[_Union[Method, str]] = ..., refined: bool = ..., generations: _Optional[int] = ..., evaluations: _Optional[int] = ..., seconds: _Optional[float] = ..., fmm_energy: _Optional[float] = ..., metrics: _Optional[_Iterable[_Union[Metric, _Mapping]]] = ..., stop_reason: _Optional[str] = ...) -> None: ...

class JobSpec(_message.Message):
    __slots__ = ["de", "energy", "mesh_id", "method", "path_every", "refine", "seed", "source", "target"]
    DE_FIELD_NUMBER: _ClassVar[int]
    ENERGY_FIELD_NUMBER: _ClassVar[int]
    MESH_ID_FIELD_NUMBER: _ClassVar[int]
    METHOD_FIELD_NUMBER: _ClassVar[int]
    PATH_EVERY_FIELD_NUMBER: _ClassVar[int]
    REFINE_FIELD_NUMBER: _ClassVar[int]
    SEED_FIELD_NUMBER: _ClassVar[int]
    SOURCE_FIELD_NUMBER: _ClassVar[int]
    TARGET_FIELD_NUMBER: _ClassVar[int]
    de: DeOptions
    energy: EnergySpec
    mesh_id: str
    method: Method
    path_every: int
    refine: bool
    seed: int
    source: int
    target: int
    def __init__(self, mesh_id: _Optional[str] = ..., source: _Optional[int] = ..., target: _Optional[int] = ..., energy: _Optional[_Union[EnergySpec, _Mapping]] = ..., method: _Optional[_Union[Method, str]] = ..., refine: bool = ..., de: _Optional[_Union[DeOptions, _Mapping]] = ..., seed: _Optional[int] = ..., path_every: _Optional[int] = ...) -> None: ...

class ListJobsRequest(_message.Message):
    __slots__ = ["mesh_id", "states"]
    MESH_ID_FIELD_NUMBER: _ClassVar[int]
    STATES_FIELD_NUMBER: _ClassVar[int]
    mesh_id: str
    states: _containers.RepeatedScalarFieldContainer[JobState]
    def __init__(self, states: _Optional[_Iterable[_Union[JobState, str]]] = ..., mesh_id: _Optional[str] = ...) -> None: ...

class ListJobsResponse(_message.Message):
    __slots__ = ["jobs"]
    JOBS_FIELD_NUMBER: _ClassVar[int]
    jobs: _containers.RepeatedCompositeFieldContainer[JobInfo]
    def __init__(self, jobs: _Optional[_Iterable[_Union[JobInfo, _Mapping]]] = ...) -> None: ...

class Metric(_message.Message):
    __slots__ = ["name", "value"]
    NAME_FIELD_NUMBER: _ClassVar[int]
    VALUE_FIELD_NUMBER: _ClassVar[int]
    name: str
    value: float
    def __init__(self, name: _Optional[str] = ..., value: _Optional[float] = ...) -> None: ...

class Path(_message.Message):
    __slots__ = ["crossings", "points", "segment_faces", "vertices"]
    CROSSINGS_FIELD_NUMBER: _ClassVar[int]
    POINTS_FIELD_NUMBER: _ClassVar[int]
    SEGMENT_FACES_FIELD_NUMBER: _ClassVar[int]
    VERTICES_FIELD_NUMBER: _ClassVar[int]
    crossings: _containers.RepeatedCompositeFieldContainer[Crossing]
    points: _containers.RepeatedCompositeFieldContainer[_mesh_pb2.Vec3]
    segment_faces: _containers.RepeatedScalarFieldContainer[int]
    vertices: _containers.RepeatedCompositeFieldContainer[PathVertex]
    def __init__(self, points: _Optional[_Iterable[_Union[_mesh_pb2.Vec3, _Mapping]]] = ..., crossings: _Optional[_Iterable[_Union[Crossing, _Mapping]]] = ..., segment_faces: _Optional[_Iterable[int]] = ..., vertices: _Optional[_Iterable[_Union[PathVertex, _Mapping]]] = ...) -> None: ...

class PathVertex(_message.Message):
    __slots__ = ["id", "position"]
    ID_FIELD_NUMBER: _ClassVar[int]
    POSITION_FIELD_NUMBER: _ClassVar[int]
    id: int
    position: _mesh_pb2.Vec3
    def __init__(self, id: _Optional[int] = ..., position: _Optional[_Union[_mesh_pb2.Vec3, _Mapping]] = ...) -> None: ...

class Progress(_message.Message):
    __slots__ = ["best_energy", "best_path", "elapsed_seconds", "evaluations", "generation", "improvements", "max_generations", "mean_energy"]
    BEST_ENERGY_FIELD_NUMBER: _ClassVar[int]
    BEST_PATH_FIELD_NUMBER: _ClassVar[int]
    ELAPSED_SECONDS_FIELD_NUMBER: _ClassVar[int]
    EVALUATIONS_FIELD_NUMBER: _ClassVar[int]
    GENERATION_FIELD_NUMBER: _ClassVar[int]
    IMPROVEMENTS_FIELD_NUMBER: _ClassVar[int]
    MAX_GENERATIONS_FIELD_NUMBER: _ClassVar[int]
    MEAN_ENERGY_FIELD_NUMBER: _ClassVar[int]
    best_energy: float
    best_path: Path
    elapsed_seconds: float
    evaluations: int
    generation: int
    improvements: int
    max_generations: int
    mean_energy: float
    def __init__(self, generation: _Optional[int] = ..., max_generations: _Optional[int] = ..., best_energy: _Optional[float] = ..., mean_energy: _Optional[float] = ..., evaluations: _Optional[int] = ..., improvements: _Optional[int] = ..., elapsed_seconds: _Optional[float] = ..., best_path: _Optional[_Union[Path, _Mapping]] = ...) -> None: ...

class StateChange(_message.Message):
    __slots__ = ["error_code", "message", "state"]
    ERROR_CODE_FIELD_NUMBER: _ClassVar[int]
    MESSAGE_FIELD_NUMBER: _ClassVar[int]
    STATE_FIELD_NUMBER: _ClassVar[int]
    error_code: int
    message: str
    state: JobState
    def __init__(self, state: _Optional[_Union[JobState, str]] = ..., error_code: _Optional[int] = ..., message: _Optional[str] = ...) -> None: ...

class SubmitJobRequest(_message.Message):
    __slots__ = ["client_request_id", "spec"]
    CLIENT_REQUEST_ID_FIELD_NUMBER: _ClassVar[int]
    SPEC_FIELD_NUMBER: _ClassVar[int]
    client_request_id: str
    spec: JobSpec
    def __init__(self, spec: _Optional[_Union[JobSpec, _Mapping]] = ..., client_request_id: _Optional[str] = ...) -> None: ...

class SubmitJobResponse(_message.Message):
    __slots__ = ["existing", "job", "job_id"]
    EXISTING_FIELD_NUMBER: _ClassVar[int]
    JOB_FIELD_NUMBER: _ClassVar[int]
    JOB_ID_FIELD_NUMBER: _ClassVar[int]
    existing: bool
    job: JobInfo
    job_id: str
    def __init__(self, job_id: _Optional[str] = ..., job: _Optional[_Union[JobInfo, _Mapping]] = ..., existing: bool = ...) -> None: ...

class WatchJobRequest(_message.Message):
    __slots__ = ["after_sequence", "job_id"]
    AFTER_SEQUENCE_FIELD_NUMBER: _ClassVar[int]
    JOB_ID_FIELD_NUMBER: _ClassVar[int]
    after_sequence: int
    job_id: str
    def __init__(self, job_id: _Optional[str] = ..., after_sequence: _Optional[int] = ...) -> None: ...

class EnergyKind(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = []

class Method(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = []

class Axis(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = []

class JobState(int, metaclass=_enum_type_wrapper.EnumTypeWrapper):
    __slots__ = []
