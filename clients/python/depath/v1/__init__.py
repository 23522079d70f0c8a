"""Protobuf messages and gRPC stubs of the depath.v1 API, generated from proto/depath/v1/*.proto.

Do not edit: regenerate with tools/generate_stubs.py (tests/test_stubs.py checks they match proto/).
"""
