"""Text-file helpers shared by the readers: bounded lines, gzip-aware opening, short quotes."""

from __future__ import annotations

import gzip
from pathlib import Path

from ..errors import DataError

#: Longest text line read (bytes): a point row is a few dozen; a longer "line" is not a table
#: (a binary file, or a file of one endless line) and would otherwise be held whole.
MAX_LINE = 65536


def bounded_lines(fh, path: Path):
    """The lines of a text file, refusing any longer than `MAX_LINE`."""
    while True:
        line = fh.readline(MAX_LINE + 1)
        if not line:
            return
        if len(line) > MAX_LINE and not line.endswith("\n"):
            raise DataError(f"{path}: a line is longer than {MAX_LINE} characters; "
                            "not a table of points")
        yield line


def open_text(path: Path):
    """``path`` opened as UTF-8 text, through gzip when its name ends in ``.gz``."""
    if path.name.lower().endswith(".gz"):
        return gzip.open(path, "rt", encoding="utf-8", errors="strict")
    return open(path, encoding="utf-8", errors="strict")


def snippet(text: str, size: int = 24) -> str:
    """A short, escaped quote of offending input, never more of a file than that."""
    short = text if len(text) <= size else text[:size] + "..."
    return repr(short)


def no_columns(path: Path, fmt: str, columns: tuple[int, ...] | None, what: str) -> None:
    """Formats without columns to choose: say so rather than ignore ``--columns``."""
    if columns is not None:
        raise DataError(f"{path}: --columns does not apply to .{fmt} files ({what})")


def is_number(token: str) -> bool:
    """Whether ``token`` reads as a float."""
    try:
        float(token)
    except ValueError:
        return False
    return True
