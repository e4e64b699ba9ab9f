"""Point Cloud Library's PCD files: ascii, binary and binary_compressed (LZF).

References
----------
.. [1] Point Cloud Library, "The PCD (Point Cloud Data) file format",
   https://pointclouds.org/documentation/tutorials/pcd_file_format.html
"""

from __future__ import annotations

import struct
import warnings
from pathlib import Path

import numpy as np

from ..errors import DataError, ReadNote

_PCD_TYPES = {("F", 4): "<f4", ("F", 8): "<f8", ("I", 1): "<i1", ("I", 2): "<i2",
              ("I", 4): "<i4", ("I", 8): "<i8", ("U", 1): "<u1", ("U", 2): "<u2",
              ("U", 4): "<u4", ("U", 8): "<u8"}


def read_pcd(path: Path, fmt: str, columns: tuple[int, ...] | None) -> np.ndarray:
    """Point Cloud Library's PCD: ascii, binary and binary_compressed (LZF, field by field).
    Points with NaN coordinates (the holes of an organized cloud: no return from a depth
    camera's pixel) are dropped with a `ReadNote`."""
    raw = path.read_bytes()
    header, offset = _pcd_header(raw, path)
    fields = header.get("FIELDS", [])
    counts = [int(c) for c in header.get("COUNT", ["1"] * len(fields))]
    npts = int(header.get("POINTS", ["0"])[0])
    mode = header["DATA"][0].lower()
    wanted = _pcd_wanted(fields, columns, path)
    if mode == "ascii":
        table = np.loadtxt(raw[offset:].decode("ascii").splitlines(), ndmin=2)
        if "POINTS" in header and len(table) != npts:
            raise DataError(f"{path}: the header says {npts} points but {len(table)} rows "
                            "follow")
        starts = np.cumsum([0, *counts[:-1]])
        points = table[:, [starts[fields.index(f)] for f in wanted]]
    elif mode in ("binary", "binary_compressed"):
        types = [np.dtype(_PCD_TYPES[(t, int(s))]) for t, s in zip(header["TYPE"],
                                                                   header["SIZE"])]
        if mode == "binary":
            dtype = np.dtype([(f, t, (c,)) if c > 1 else (f, t)
                              for f, t, c in zip(fields, types, counts)])
            if len(raw) - offset < npts * dtype.itemsize:
                raise DataError(f"{path}: PCD binary data is truncated")
            data = np.frombuffer(raw, dtype=dtype, count=npts, offset=offset)
            points = np.column_stack([data[f].astype(np.float64) for f in wanted])
        else:
            points = _pcd_compressed(raw, offset, fields, types, counts, npts, wanted, path)
    else:
        raise DataError(f"{path}: PCD data mode '{mode}' is not supported "
                        "(ascii, binary and binary_compressed are)")
    holes = np.isnan(points).any(axis=1)
    if holes.any():
        warnings.warn(f"{path}: {int(holes.sum())} of {len(points)} points have no "
                      "coordinates (NaN: the holes of an organized cloud) and were dropped",
                      ReadNote, stacklevel=2)
        points = points[~holes]
    return points


def _pcd_header(raw: bytes, path: Path) -> tuple[dict[str, list[str]], int]:
    header: dict[str, list[str]] = {}
    offset = 0
    for line in raw.split(b"\n"):
        offset += len(line) + 1
        text = line.decode("ascii", errors="replace").strip()
        if not text or text.startswith("#"):
            continue
        key, *values = text.split()
        header[key.upper()] = values
        if key.upper() == "DATA":
            return header, offset
    raise DataError(f"{path}: PCD header has no DATA line")


def _pcd_wanted(fields: list[str], columns: tuple[int, ...] | None, path: Path) -> list[str]:
    """The fields to read: x, y (and z), or those at ``columns`` in the FIELDS line."""
    if columns is not None:
        if max(columns) >= len(fields):
            raise DataError(f"{path}: asked for field {max(columns)} but the PCD has "
                            f"{len(fields)} ({' '.join(fields)})")
        return [fields[c] for c in columns]
    if not {"x", "y"} <= set(fields):
        raise DataError(f"{path}: PCD has no x/y fields (fields: {' '.join(fields)})")
    return [f for f in ("x", "y", "z") if f in fields]


def _pcd_compressed(raw: bytes, offset: int, fields: list[str], types: list[np.dtype],
                    counts: list[int], npts: int, wanted: list[str], path: Path) -> np.ndarray:
    """binary_compressed: two uint32 sizes, then LZF data holding each field's values for
    all points in turn (PCL's layout)."""
    from .lzf import decompress

    if len(raw) < offset + 8:
        raise DataError(f"{path}: PCD compressed data is truncated")
    packed, size = struct.unpack_from("<II", raw, offset)
    if len(raw) < offset + 8 + packed:
        raise DataError(f"{path}: PCD compressed data is truncated")
    expected = npts * sum(t.itemsize * c for t, c in zip(types, counts))
    if size != expected:
        raise DataError(f"{path}: the PCD header's fields need {expected} bytes of data, "
                        f"the compressed block holds {size}")
    data = decompress(raw[offset + 8:offset + 8 + packed], size, str(path))
    columns, start = {}, 0
    for f, t, c in zip(fields, types, counts):
        block = np.frombuffer(data, dtype=t, count=npts * c, offset=start)
        columns[f] = block.reshape(npts, c)[:, 0] if c > 1 else block
        start += npts * c * t.itemsize
    return np.column_stack([columns[f].astype(np.float64) for f in wanted])
