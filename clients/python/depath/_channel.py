"""The gRPC channel to depathd: plain TCP or TLS (server certificate check, optional client
certificate for mutual TLS), keepalive so that a dead connection is noticed during a long watch."""
from __future__ import annotations

import os
from dataclasses import dataclass
from typing import List, Optional, Sequence, Tuple, Union

import grpc

PathOrPem = Union[str, bytes, os.PathLike]


@dataclass(frozen=True)
class TLS:
    """TLS settings for Client(tls=...).

    ca:   the CA certificate that signed the server's certificate (file path or PEM bytes);
          None = the system's trusted roots.
    cert, key: the client's certificate and private key, for servers that require mutual TLS.
    server_name: the name to check the server's certificate against, when it differs from
          the host in the address (e.g. connecting to 127.0.0.1 with a certificate for "depathd")."""

    ca: Optional[PathOrPem] = None
    cert: Optional[PathOrPem] = None
    key: Optional[PathOrPem] = None
    server_name: Optional[str] = None


def _pem(value: Optional[PathOrPem]) -> Optional[bytes]:
    if value is None or isinstance(value, bytes):
        return value
    with open(value, "rb") as f:
        return f.read()


TlsOption = Union[None, bool, TLS, grpc.ChannelCredentials]


def resolve_tls(tls: TlsOption, ca: Optional[PathOrPem] = None, cert: Optional[PathOrPem] = None,
                key: Optional[PathOrPem] = None) -> TlsOption:
    """The TLS settings a Client uses: `tls` when given (not None); else TLS(ca, cert, key) from
    the arguments, each falling back to the environment variable DEPATH_TLS_CA / DEPATH_TLS_CERT /
    DEPATH_TLS_KEY (as the depath CLI does); None (plain TCP) when none is set."""
    if tls is not None:
        if any(v is not None for v in (ca, cert, key)):
            raise ValueError("give either tls=... or tls_ca/tls_cert/tls_key, not both")
        return tls
    ca = ca if ca is not None else os.environ.get("DEPATH_TLS_CA") or None
    cert = cert if cert is not None else os.environ.get("DEPATH_TLS_CERT") or None
    key = key if key is not None else os.environ.get("DEPATH_TLS_KEY") or None
    if (cert is None) != (key is None):
        raise ValueError("tls_cert and tls_key (DEPATH_TLS_CERT / DEPATH_TLS_KEY) go together")
    if ca is None and cert is None:
        return None
    return TLS(ca=ca, cert=cert, key=key)


def resolve_token(token: Optional[str], token_file: Optional[Union[str, os.PathLike]] = None) -> Optional[str]:
    """The bearer token: `token`, else the first line of `token_file`, else the environment's
    DEPATH_TOKEN, else the first line of the file DEPATH_TOKEN_FILE names (as the depath CLI)."""
    if token is not None and token_file is not None:
        raise ValueError("give either token or token_file, not both")
    if token is not None:
        return token or None
    if token_file is None:
        if os.environ.get("DEPATH_TOKEN"):
            return os.environ["DEPATH_TOKEN"]
        token_file = os.environ.get("DEPATH_TOKEN_FILE") or None
    if token_file is None:
        return None
    with open(token_file, encoding="utf-8") as f:
        line = f.readline().strip()
    if not line:
        raise ValueError("token file %s: the first line is empty" % os.fspath(token_file))
    return line


def make_channel(address: str, tls: TlsOption, interceptors: Sequence[object] = ()) -> grpc.Channel:
    """A channel to `address` (host:port or any gRPC target): insecure for tls None/False,
    TLS with the system roots for True, else as the TLS settings or credentials say."""
    options: List[Tuple[str, Union[int, str]]] = [
        ("grpc.max_receive_message_length", -1),
        ("grpc.max_send_message_length", -1),
        ("grpc.keepalive_time_ms", 30000),
        ("grpc.keepalive_timeout_ms", 10000),
    ]
    if tls is None or tls is False:
        channel = grpc.insecure_channel(address, options=options)
    else:
        if tls is True:
            tls = TLS()
        if isinstance(tls, TLS):
            if tls.server_name:
                options.append(("grpc.ssl_target_name_override", tls.server_name))
            credentials = grpc.ssl_channel_credentials(root_certificates=_pem(tls.ca), private_key=_pem(tls.key),
                                                       certificate_chain=_pem(tls.cert))
        elif isinstance(tls, grpc.ChannelCredentials):
            credentials = tls
        else:
            raise TypeError("tls must be None, a bool, depath.TLS or grpc.ChannelCredentials, got %r" % (tls,))
        channel = grpc.secure_channel(address, credentials, options=options)
    if interceptors:
        channel = grpc.intercept_channel(channel, *interceptors)
    return channel
