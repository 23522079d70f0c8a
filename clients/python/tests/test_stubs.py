"""The checked-in stubs under depath/v1 are what proto/ generates (else: run tools/generate_stubs.py)."""
import importlib.util
import os
import shutil
import subprocess
from pathlib import Path

from google.protobuf import descriptor_pb2

from conftest import REPO

PACKAGE = Path(__file__).resolve().parents[1]
PROTO_DIR = Path(os.environ.get("DEPATH_PROTO_DIR") or REPO / "proto")  # ctest passes the build's


def tool(env, name):
    path = os.environ.get(env) or shutil.which(name)
    assert path, "%s not found (Debian packages protobuf-compiler / protobuf-compiler-grpc); or set %s" % (name, env)
    return path


def test_checked_in_stubs_are_generated_from_proto(tmp_path):
    spec = importlib.util.spec_from_file_location("generate_stubs", PACKAGE / "tools" / "generate_stubs.py")
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    gen.generate(str(tmp_path), tool("DEPATH_PROTOC", "protoc"),
                 tool("DEPATH_GRPC_PYTHON_PLUGIN", "grpc_python_plugin"), proto_dir=str(PROTO_DIR))
    fresh = {p.name: p.read_bytes() for p in (tmp_path / "depath" / "v1").iterdir()}
    checked_in = {p.name: p.read_bytes() for p in (PACKAGE / "depath" / "v1").iterdir()
                  if p.is_file() and p.name != "__init__.py"}
    assert sorted(fresh) == sorted(checked_in)
    stale = [name for name in fresh if fresh[name] != checked_in[name]]
    assert not stale, "stale stubs %s: run python3 clients/python/tools/generate_stubs.py" % stale


def without_json_names(file):
    """protoc fills json_name (derived from the field name) in descriptor sets, not in stubs."""
    def strip(messages):
        for m in messages:
            for f in m.field:
                f.ClearField("json_name")
            strip(m.nested_type)
    strip(file.message_type)
    return file


def test_imported_stubs_describe_the_protos(tmp_path):
    """The package in use (installed or not) carries the same descriptors as proto/."""
    from depath.v1 import job_pb2, mesh_pb2

    out = tmp_path / "set.pb"
    subprocess.run([tool("DEPATH_PROTOC", "protoc"), "--proto_path=" + str(PROTO_DIR),
                    "--descriptor_set_out=" + str(out), "depath/v1/mesh.proto", "depath/v1/job.proto"], check=True)
    files = {f.name: f for f in descriptor_pb2.FileDescriptorSet.FromString(out.read_bytes()).file}
    for module in (mesh_pb2, job_pb2):
        embedded = descriptor_pb2.FileDescriptorProto.FromString(module.DESCRIPTOR.serialized_pb)
        assert embedded == without_json_names(files[embedded.name]), embedded.name
