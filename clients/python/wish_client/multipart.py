"""A minimal ``multipart/form-data`` encoder (RFC 7578) — the standard library has a parser but no encoder."""

from __future__ import annotations

import uuid
from collections.abc import Iterable


def _quote(value: str) -> str:
    """Quotes a form-data parameter value (RFC 7578 §4.2: escape quotes, no raw CR/LF)."""
    return value.replace("\\", "\\\\").replace('"', "%22").replace("\r", "%0D").replace("\n", "%0A")


def encode_multipart(files: Iterable[tuple[str, str, bytes]],
                     fields: Iterable[tuple[str, str]] = ()) -> tuple[bytes, str]:
    """Encodes form fields and file parts.

    Args:
        files: ``(field_name, filename, content)`` per file part, sent as ``application/octet-stream``.
        fields: ``(field_name, value)`` per plain text field.

    Returns:
        ``(body, content_type)`` where ``content_type`` carries the boundary.
    """
    boundary = f"wish-{uuid.uuid4().hex}"
    chunks: list[bytes] = []
    for name, value in fields:
        chunks.append(f'--{boundary}\r\nContent-Disposition: form-data; name="{_quote(name)}"\r\n\r\n'.encode())
        chunks.append(value.encode() + b"\r\n")
    for name, filename, content in files:
        chunks.append((f'--{boundary}\r\nContent-Disposition: form-data; name="{_quote(name)}"; '
                       f'filename="{_quote(filename)}"\r\nContent-Type: application/octet-stream\r\n\r\n').encode())
        chunks.append(content)
        chunks.append(b"\r\n")
    chunks.append(f"--{boundary}--\r\n".encode())
    return b"".join(chunks), f"multipart/form-data; boundary={boundary}"
