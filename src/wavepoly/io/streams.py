"""File objects in and out: a reader or writer of paths, given a stream instead.

A stream (standard input, an ``io.BytesIO``, an open file) is copied to a temporary file of
the named format and read as a path; a result is written to a temporary file and copied to the
stream. Messages name the stream (its ``name``, or ``<stream>``), never the temporary file.
"""

from __future__ import annotations

import contextlib
import io
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

from ..errors import DataError, ParameterError


def is_stream(obj: object) -> bool:
    """True for a file object (anything with ``read`` or ``write``), False for a path."""
    return hasattr(obj, "read") or hasattr(obj, "write")


def stream_name(stream: object) -> str:
    name = getattr(stream, "name", None)
    return name if isinstance(name, str) and name else "<stream>"


@contextlib.contextmanager
def stream_as_path(stream, fmt: str | None) -> Iterator[Path]:
    """The content of a readable stream as a temporary file ending in ``.fmt``."""
    if not fmt:
        raise ParameterError(f"{stream_name(stream)}: a file object needs its format "
                             "(format='xy', 'ply', ...; --format on the command line)")
    with tempfile.TemporaryDirectory(prefix="wavepoly-in-") as folder:
        path = Path(folder) / f"stream.{fmt.lower()}"
        with open(path, "wb") as out:
            while chunk := stream.read(1 << 20):
                out.write(chunk.encode("utf-8") if isinstance(chunk, str) else chunk)
        try:
            yield path
        except DataError as exc:
            raise DataError(str(exc).replace(str(path), stream_name(stream))) from None


@contextlib.contextmanager
def path_for_stream(stream, fmt: str | None) -> Iterator[Path]:
    """A temporary path ending in ``.fmt`` whose content, once written, goes to ``stream``
    (text streams get it decoded as UTF-8, binary ones as bytes)."""
    if not fmt:
        raise ParameterError(f"{stream_name(stream)}: a file object needs its format "
                             "(format='geojson', 'svg', ...; --output-format on the command "
                             "line)")
    with tempfile.TemporaryDirectory(prefix="wavepoly-out-") as folder:
        path = Path(folder) / f"stream.{fmt.lower()}"
        try:
            yield path
        except DataError as exc:
            raise DataError(str(exc).replace(str(path), stream_name(stream))) from None
        with open(path, "rb") as src:
            if isinstance(stream, io.TextIOBase):
                stream.write(src.read().decode("utf-8"))
            else:
                shutil.copyfileobj(src, stream)
        if hasattr(stream, "flush"):
            stream.flush()
