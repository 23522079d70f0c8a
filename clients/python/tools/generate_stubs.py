#!/usr/bin/env python3
"""Regenerates the checked-in protobuf / gRPC stubs of the `depath` package from proto/.

    python3 clients/python/tools/generate_stubs.py            # rewrites clients/python/depath/v1/
    python3 clients/python/tools/generate_stubs.py --out DIR  # writes DIR/depath/v1/ (the test compares)

Uses Debian's protoc (package protobuf-compiler, 3.21) and grpc_python_plugin (protobuf-compiler-grpc).
Debian's python3-grpc-tools cannot be used: its bundled protoc predates proto3 `optional`.
The stubs are checked in so that installing the package needs neither tool; the test
tests/test_stubs.py fails when they no longer match proto/.
"""
import argparse
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
PACKAGE_ROOT = os.path.dirname(HERE)
PROTO_DIR = os.path.normpath(os.path.join(PACKAGE_ROOT, "..", "..", "proto"))
# Only depath's own services: the health service is not part of the client's API.
PROTOS = ["depath/v1/mesh.proto", "depath/v1/job.proto"]


def generate(out_root, protoc, plugin, proto_dir=PROTO_DIR):
    """Writes OUT_ROOT/depath/v1/{mesh,job}_pb2{.py,.pyi,_grpc.py}."""
    os.makedirs(out_root, exist_ok=True)
    subprocess.run([protoc, "--proto_path=" + proto_dir, "--python_out=" + out_root, "--pyi_out=" + out_root,
                    "--grpc_out=" + out_root, "--plugin=protoc-gen-grpc=" + plugin] + PROTOS, check=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", help="output root (default: this package, in place)")
    ap.add_argument("--protoc", default=shutil.which("protoc") or "protoc")
    ap.add_argument("--grpc-python-plugin", default=shutil.which("grpc_python_plugin") or "grpc_python_plugin")
    ap.add_argument("--proto-dir", default=PROTO_DIR)
    args = ap.parse_args()
    generate(args.out or PACKAGE_ROOT, args.protoc, args.grpc_python_plugin, args.proto_dir)
    return 0


if __name__ == "__main__":
    sys.exit(main())
