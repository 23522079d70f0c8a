"""depath.Client: meshes and jobs on a depathd server, numpy in and out."""
from __future__ import annotations

import uuid
from typing import Any, Iterable, Iterator, List, Optional, Sequence, Tuple

import grpc

from ._channel import PathOrPem, TlsOption, make_channel, resolve_tls, resolve_token
from ._errors import DeadlineExceeded, NotFound, from_rpc_error
from ._job import Job
from ._meshes import MeshBytes, MeshLike, is_mesh_id, mesh_bytes
from ._progress import ProgressOption
from ._results import Result
from ._spec import job_spec
from .v1 import job_pb2, job_pb2_grpc, mesh_pb2, mesh_pb2_grpc

_CHUNK_BYTES = 1 << 20
# Deadline of an upload, and of a mesh lookup once connected: the server may parse the mesh
# for either (a lookup reloads one it stored before a restart). As the CLI's.
_MESH_SECONDS = 600.0


class Client:
    """A connection to depathd.

    address: "host:port" (or any gRPC target). token: sent as `authorization: Bearer TOKEN`
    when the server runs with --auth-token; or token_file (its first line); default: the
    environment's DEPATH_TOKEN or DEPATH_TOKEN_FILE. tls: False for plain TCP, True for TLS with
    the system's roots, depath.TLS(ca=..., cert=..., key=...) for a private CA or mutual TLS;
    or tls_ca / tls_cert / tls_key (file paths or PEM bytes); default (tls=None and none of
    those): DEPATH_TLS_CA / DEPATH_TLS_CERT / DEPATH_TLS_KEY from the environment, else plain TCP.
    timeout: seconds for each unary call (connecting included). reconnect_seconds: how long a
    watch keeps retrying without hearing from the server. interceptors: gRPC client
    interceptors (logging, tracing).

    Use as a context manager, or call close()."""

    def __init__(self, address: str, token: Optional[str] = None, tls: TlsOption = None, *,
                 timeout: float = 30.0, reconnect_seconds: float = 60.0, interceptors: Sequence[Any] = (),
                 token_file: Optional[str] = None, tls_ca: Optional[PathOrPem] = None,
                 tls_cert: Optional[PathOrPem] = None, tls_key: Optional[PathOrPem] = None):
        self.address = address
        self.timeout = timeout
        self.reconnect_seconds = reconnect_seconds
        token = resolve_token(token, token_file)
        self._metadata: Tuple[Tuple[str, str], ...] = (("authorization", "Bearer " + token),) if token else ()
        tls = resolve_tls(tls, tls_ca, tls_cert, tls_key)
        self._tls = tls
        self._channel = make_channel(address, tls, interceptors)
        self._meshes = mesh_pb2_grpc.MeshServiceStub(self._channel)
        self._jobs = job_pb2_grpc.JobServiceStub(self._channel)

    def close(self) -> None:
        self._channel.close()

    def __enter__(self) -> "Client":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __repr__(self) -> str:
        return "Client(%r)" % self.address

    def _call(self, method: Any, request: Any, doing: str, timeout: Optional[float] = None) -> Any:
        """A unary call with the token; waits for the connection up to the timeout."""
        try:
            return method(request, metadata=self._metadata, timeout=timeout or self.timeout, wait_for_ready=True)
        except grpc.RpcError as e:
            raise from_rpc_error(e, doing) from None

    def _wait_connected(self, doing: str) -> None:
        """Waits up to the client's timeout for the server; a call after this may take longer."""
        ready = grpc.channel_ready_future(self._channel)
        try:
            ready.result(timeout=self.timeout)
        except grpc.FutureTimeoutError:
            ready.cancel()  # else it stays subscribed to the channel, which keeps trying to connect
            raise DeadlineExceeded(grpc.StatusCode.DEADLINE_EXCEEDED,
                                   "no answer from the server at %s within %gs (is it running?)"
                                   % (self.address, self.timeout), doing=doing) from None

    def _cancel_on_new_channel(self, job_id: str) -> None:
        """CancelJob over a channel of its own (best effort): for when a KeyboardInterrupt may
        have left this client's channel unusable."""
        channel = make_channel(self.address, self._tls)
        try:
            job_pb2_grpc.JobServiceStub(channel).CancelJob(job_pb2.CancelJobRequest(job_id=job_id),
                                                           metadata=self._metadata, timeout=10)
        except grpc.RpcError:
            pass
        finally:
            channel.close()

    # ---- meshes ----------------------------------------------------------------------------

    def upload(self, mesh: MeshLike, *, name: str = "", force: bool = False) -> str:
        """Makes the server have `mesh` and returns its id (SHA-256 of the bytes sent).

        mesh: a file path (OBJ, OFF, PLY, STL), or a (vertices, faces) pair of arrays
        ((n, 3) floats, (m, 3) 0-based vertex ids; sent as OFF text). The bytes are sent
        only when the server lacks the mesh (or with force=True)."""
        if is_mesh_id(mesh):
            return self.mesh_info(mesh).id
        source = mesh_bytes(mesh, name)
        return self._ensure(source, force=force).id

    def mesh_info(self, mesh: MeshLike) -> mesh_pb2.MeshInfo:
        """The server's MeshInfo (counts, bounding box, warnings) for a mesh id, file or arrays.
        Raises NotFound when the server does not have it."""
        mesh_id = str(mesh) if is_mesh_id(mesh) else mesh_bytes(mesh).id
        doing = "looking up mesh " + mesh_id
        # The timeout bounds the wait for the server, not the lookup (it may parse the mesh).
        self._wait_connected(doing)
        return self._call(self._meshes.GetMesh, mesh_pb2.GetMeshRequest(id=mesh_id), doing, timeout=_MESH_SECONDS)

    def list_meshes(self) -> List[mesh_pb2.MeshInfo]:
        return list(self._call(self._meshes.ListMeshes, mesh_pb2.ListMeshesRequest(), "listing meshes").meshes)

    def delete_mesh(self, mesh_id: str) -> None:
        self._call(self._meshes.DeleteMesh, mesh_pb2.DeleteMeshRequest(id=mesh_id), "deleting mesh " + mesh_id)

    def _ensure(self, source: MeshBytes, force: bool = False) -> mesh_pb2.MeshInfo:
        if not force:
            try:
                return self.mesh_info(source.id)
            except NotFound:
                pass  # never uploaded, evicted or deleted: send it
        return self._send(source)

    def _send(self, source: MeshBytes) -> mesh_pb2.MeshInfo:
        def requests() -> Iterator[mesh_pb2.UploadMeshRequest]:
            yield mesh_pb2.UploadMeshRequest(header=mesh_pb2.UploadMeshHeader(
                file_name=source.file_name, format=source.format, size_bytes=len(source.data)))
            for offset in range(0, len(source.data), _CHUNK_BYTES):
                yield mesh_pb2.UploadMeshRequest(chunk=source.data[offset:offset + _CHUNK_BYTES])

        try:
            return self._meshes.UploadMesh(requests(), metadata=self._metadata, timeout=max(self.timeout, _MESH_SECONDS),
                                           wait_for_ready=True)
        except grpc.RpcError as e:
            raise from_rpc_error(e, "uploading " + source.file_name) from None

    # ---- jobs ------------------------------------------------------------------------------

    def submit(self, mesh: MeshLike, source: int, target: int, *, request_id: Optional[str] = None,
               **options: Any) -> Job:
        """Uploads the mesh if the server lacks it, queues the job and returns it at once.

        mesh: file path, mesh id, or (vertices, faces) arrays. source, target: vertex ids
        (0-based, file order). options (all optional, as `depath solve`'s flags):
          energy="geodesic" | "vector_field" | "constant_slope"
          density=(n,) array (geodesic), field=(n, 3) array (vector_field),
          field_from_height=bool, rotate=degrees, slope=k, up="x"|"y"|"z", smoothness=lambda,
          method="de" | "fmm" | "descent", refine=bool,
          population, generations, stall, F, CR, strategy, seed_with_problem, seed,
          path_every=K (attach the best path to every K-th progress event).
        request_id: idempotency key (default: a fresh one); resubmitting with it returns the
        same job. Errors: InvalidArgument, NotFound, FailedPrecondition, ResourceExhausted, ..."""
        upload = None if is_mesh_id(mesh) else mesh_bytes(mesh)
        mesh_id = upload.id if upload is not None else str(mesh)
        spec = job_spec(mesh_id, source, target, **options)
        request = job_pb2.SubmitJobRequest(spec=spec, client_request_id=request_id or "py-" + uuid.uuid4().hex)
        for attempt in range(2):
            if upload is not None:
                self._ensure(upload)
            try:
                reply = self._jobs.SubmitJob(request, metadata=self._metadata, timeout=self.timeout + 60,
                                             wait_for_ready=True)
                return Job(self, reply.job_id)
            except grpc.RpcError as e:
                # The mesh was evicted between the lookup and the submit: upload again, once.
                if e.code() == grpc.StatusCode.NOT_FOUND and upload is not None and attempt == 0:
                    continue
                raise from_rpc_error(e, "submitting the job") from None
        raise AssertionError("unreachable")

    def job(self, job_id: str) -> Job:
        """The job with this id (no call is made)."""
        return Job(self, job_id)

    def list_jobs(self, states: Iterable[str] = (), mesh_id: str = "") -> List[job_pb2.JobInfo]:
        """The server's jobs, oldest first; optionally only those in `states` ("running", ...)."""
        by_name = {"queued": job_pb2.JOB_STATE_QUEUED, "running": job_pb2.JOB_STATE_RUNNING,
                   "succeeded": job_pb2.JOB_STATE_SUCCEEDED, "failed": job_pb2.JOB_STATE_FAILED,
                   "cancelled": job_pb2.JOB_STATE_CANCELLED}
        request = job_pb2.ListJobsRequest(states=[by_name[s] for s in states], mesh_id=mesh_id)
        return list(self._call(self._jobs.ListJobs, request, "listing jobs").jobs)

    def run(self, mesh: MeshLike, source: int, target: int, *, progress: ProgressOption = None,
            timeout: Optional[float] = None, request_id: Optional[str] = None, **options: Any) -> Result:
        """Upload if needed + submit + wait: the result of the job (see submit for the options,
        Job.wait for progress, errors and Ctrl-C)."""
        return self.submit(mesh, source, target, request_id=request_id, **options).wait(progress, timeout=timeout)
