"""Point readers: every common scan format in, an (N, 2) or (N, 3) float64 array out.

The format is chosen from the file extension unless ``fmt`` names it. Each reader raises
`DataError` with a one-line message naming the file and the problem.
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from ..errors import DataError
from ..types import FloatArray
from ..validate import validate_points
from .carmen import CARMEN_SUFFIXES, read_carmen
from .pcd import read_pcd
from .streams import is_stream, stream_as_path
from .text import MAX_LINE, bounded_lines, is_number, no_columns, open_text, snippet

TEXT_FORMATS = ("xyz", "xy", "txt", "csv", "pts", "p2d", "gtn", "xym", "asc")
FORMATS = (*TEXT_FORMATS, "npy", "ply", "las", "laz", "pcd", "obj", "off", "carmen", "conf")
#: Extensions whose columns are planar (x, y, then weights or indices that are not coordinates).
_PLANAR = {"xy", "p2d", "gtn", "xym"}
_SPLIT = re.compile(r"[,\s;]+")


def detect_format(path: str | Path) -> str:
    """The format name for ``path`` from its extension (``.log``, ``.clf``, gzipped or not:
    CARMEN logs)."""
    name = Path(path).name.lower()
    if name.endswith(CARMEN_SUFFIXES):
        return "carmen"
    ext = name.rsplit(".", 1)[-1] if "." in name else ""
    if ext in FORMATS:
        return ext
    raise DataError(f"{path}: unknown point format '.{ext}' "
                    f"(known: {', '.join(FORMATS)}, log, clf)")


def read_points(
    path,
    format: str | None = None,
    *,
    fmt: str | None = None,
    columns: Sequence[int] | None = None,
) -> FloatArray:
    """Read the points of a scan file.

    Parameters
    ----------
    path : file to read: a path, or a binary or text file object (then ``format`` is
        required).
    format, fmt : format name overriding the extension, one of `FORMATS` (two spellings).
    columns : 0-based columns to use as coordinates (2 or 3 of them) in text and NumPy files;
        by default the first 3 (the first 2 for planar formats such as ``.xy``, ``.p2d``, ``.gtn``).

    Returns
    -------
    (N, 2) or (N, 3) float64 array of finite coordinates, N >= 2, not all identical.

    Examples
    --------
    >>> pts = read_points("scan.xyz")                      # doctest: +SKIP
    >>> pts = read_points("slice.csv", columns=(1, 2))     # doctest: +SKIP
    >>> pts = read_points(sys.stdin.buffer, format="xy")  # doctest: +SKIP
    """
    fmt = fmt or format
    if is_stream(path):
        with stream_as_path(path, fmt) as tmp:
            return read_points(tmp, fmt=fmt, columns=columns)
    path = Path(path)
    if not path.exists():
        raise DataError(f"{path}: no such file")
    if path.is_dir():
        raise DataError(f"{path}: is a directory, not a point file")
    if not path.is_file():
        raise DataError(f"{path}: is not a regular file (a pipe or a device); "
                        "save the points to a file first")
    fmt = (fmt or detect_format(path)).lower()
    if fmt not in FORMATS:
        raise DataError(f"{path}: unknown format {fmt!r} (known: {', '.join(FORMATS)})")
    if columns is not None:
        columns = tuple(int(c) for c in columns)
        if len(columns) not in (2, 3) or min(columns) < 0:
            raise DataError(f"{path}: --columns needs 2 or 3 non-negative column numbers")
    reader = _READERS.get(fmt, _read_text)
    try:
        points = reader(path, fmt, columns)
    except DataError:
        raise
    except (OSError, ValueError, IndexError, KeyError, EOFError, UnicodeDecodeError) as exc:
        raise DataError(f"{path}: cannot read as {fmt}: {_short(exc)}") from exc
    except Exception as exc:  # third-party readers raise their own types on corrupt files
        raise DataError(f"{path}: cannot read as {fmt}: {_short(exc)}") from exc
    return validate_points(points, source=str(path))


def _short(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    return text[0] if text else type(exc).__name__


def _select_columns(table: np.ndarray, fmt: str, columns: tuple[int, ...] | None,
                    path: Path) -> np.ndarray:
    if columns is not None:
        if max(columns) >= table.shape[1]:
            raise DataError(f"{path}: asked for column {max(columns)} but rows have "
                            f"{table.shape[1]} columns")
        return table[:, list(columns)]
    if table.shape[1] < 2:
        raise DataError(f"{path}: rows have {table.shape[1]} numeric column(s); need 2 or more")
    ncols = 2 if fmt in _PLANAR else min(3, table.shape[1])
    return table[:, :ncols]


def _read_text(path: Path, fmt: str, columns: tuple[int, ...] | None) -> np.ndarray:
    """Whitespace/comma separated columns; '#' comments, one header line, Hoppe and .gtn rows.

    A plain table (the common case) is parsed by NumPy's C reader (`_read_table_fast`); any
    other file, or any table NumPy refuses, goes through the line-by-line parser below, which
    also words the refusals.
    """
    fast = _read_table_fast(path, fmt, columns)
    if fast is not None:
        return fast
    rows: list[list[str]] = []
    header_seen = False
    with open_text(path) as fh:
        for lineno, raw in enumerate(bounded_lines(fh, path), 1):
            line = raw.split("#", 1)[0].strip()
            if not line:
                continue
            tokens = [t for t in _SPLIT.split(line) if t]
            if len(tokens[0]) == 1 and tokens[0].isalpha():  # Hoppe: 'p x y z' is a point
                if tokens[0] == "p":
                    rows.append(tokens[1:])
                continue
            if not is_number(tokens[0]) or not all(is_number(t) for t in tokens):
                if not rows and not header_seen:
                    header_seen = True  # one header line (e.g. 'x,y,z') is allowed
                    continue
                raise DataError(f"{path}: line {lineno} is not numeric: {snippet(line)}")
            rows.append(tokens)
    if not rows:
        raise DataError(f"{path}: contains no numeric rows")
    if fmt == "gtn" or _looks_like_gtn(rows):
        _check_count_header(rows, path)
        rows = [r[1:] for r in rows[1:]]  # 'count dim 0 0' header, then 'index x y' rows
        if not rows:
            raise DataError(f"{path}: contains no points after its count header")
    width = min(len(r) for r in rows)
    table = np.array([r[:width] for r in rows], dtype=np.float64)
    return _select_columns(table, fmt, columns, path)


#: Bytes scanned at a time for the longest line before the fast parse.
_SCAN_CHUNK = 1 << 24


def _read_table_fast(path: Path, fmt: str, columns: tuple[int, ...] | None
                     ) -> np.ndarray | None:
    """A plain numeric table (whitespace or comma separated, '#' comments, at most one header
    line) read with ``np.loadtxt``; None for anything else (gzip, Hoppe 'p' rows, .gtn count
    headers, ragged rows, lines over `MAX_LINE`), which the line parser handles."""
    if path.name.lower().endswith(".gz") or fmt == "gtn" or _longest_line(path) > MAX_LINE:
        return None
    with open(path, "rb") as fh:
        head = fh.read(MAX_LINE).decode("utf-8", errors="replace").splitlines()
    lines = [ln.split("#", 1)[0].strip() for ln in head]
    lines = [ln for ln in lines if ln]
    if len(lines) < 2:
        return None
    skip = 0 if all(is_number(t) for t in _SPLIT.split(lines[0]) if t) else 1
    first = [t for t in _SPLIT.split(lines[skip]) if t]
    if not first or not all(is_number(t) for t in first) or _looks_like_gtn([first] * 2):
        return None
    delimiter = "," if "," in lines[skip] else None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # an empty file warns; the line parser refuses it
            table = np.loadtxt(path, comments="#", delimiter=delimiter, skiprows=skip,
                               ndmin=2, encoding="utf-8")
    except (ValueError, UnicodeDecodeError):
        return None
    if skip and _header_rows(path) != 1:  # more than one non-numeric line: let the parser say
        return None
    if not len(table):
        return None
    return _select_columns(table, fmt, columns, path)


def _header_rows(path: Path) -> int:
    """Non-comment lines before the first numeric one (np.loadtxt skipped exactly one)."""
    count = 0
    with open(path, encoding="utf-8", errors="replace") as fh:
        for raw in fh:
            line = raw.split("#", 1)[0].strip()
            if not line:
                continue
            if all(is_number(t) for t in _SPLIT.split(line) if t):
                return count
            count += 1
    return count


def _longest_line(path: Path) -> int:
    """The longest line of a file in bytes, scanned in chunks (no line is held)."""
    longest, run = 0, 0
    with open(path, "rb") as fh:
        while chunk := fh.read(_SCAN_CHUNK):
            breaks = np.flatnonzero(np.frombuffer(chunk, dtype=np.uint8) == 10)
            if not len(breaks):
                run += len(chunk)
                longest = max(longest, run)
                continue
            longest = max(longest, run + int(breaks[0]), int(np.diff(breaks).max(initial=0)))
            run = len(chunk) - int(breaks[-1]) - 1
    return max(longest, run)


def _check_count_header(rows: list[list[str]], path: Path) -> None:
    """A .gtn's first row says how many points follow: it must say so truthfully."""
    try:
        count = int(float(rows[0][0]))
    except (ValueError, OverflowError, IndexError):
        raise DataError(f"{path}: the count header is not a number") from None
    if count != len(rows) - 1:
        raise DataError(f"{path}: the count header says {rows[0][0]} points but "
                        f"{len(rows) - 1} rows follow")


def _looks_like_gtn(rows: list[list[str]]) -> bool:
    """A .gtn table: first row 'count dim 0 0' with count == number of rows after it."""
    first = rows[0]
    if len(first) != 4 or len(rows) < 2 or not first[0].isdigit():
        return False
    return int(first[0]) == len(rows) - 1 and all(r[0].isdigit() for r in rows[1:3])


def _read_npy(path: Path, fmt: str, columns: tuple[int, ...] | None) -> np.ndarray:
    arr = np.load(path, allow_pickle=False)
    if arr.ndim != 2:
        raise DataError(f"{path}: expected a 2D array, got shape {arr.shape}")
    return _select_columns(arr.astype(np.float64), fmt, columns, path)


def _read_ply(path: Path, fmt: str, columns: tuple[int, ...] | None) -> np.ndarray:
    from plyfile import PlyData

    with warnings.catch_warnings():  # plyfile warns on empty ASCII elements
        warnings.simplefilter("ignore", UserWarning)
        ply = PlyData.read(str(path))
    if "vertex" not in ply:
        raise DataError(f"{path}: PLY file has no 'vertex' element")
    vertex = ply["vertex"].data
    names = [n for n in ("x", "y", "z") if n in vertex.dtype.names]
    if columns is not None:  # the vertex properties in the header's order
        names = _named_columns(list(vertex.dtype.names), columns, path, "vertex properties")
    if len(names) < 2:
        raise DataError(f"{path}: PLY vertices have no x/y properties")
    return np.column_stack([np.asarray(vertex[n], dtype=np.float64) for n in names])


def _named_columns(names: list[str], columns: tuple[int, ...], path: Path, what: str
                   ) -> list[str]:
    if max(columns) >= len(names):
        raise DataError(f"{path}: asked for column {max(columns)} but the file has "
                        f"{len(names)} {what} ({' '.join(names)})")
    return [names[c] for c in columns]


#: Sizes of the LAS public header's fields that locate the rest, and of a VLR's header.
_LAS_MIN_HEADER = 227
_LAS_VLR_HEADER = 54


def _check_las_header(path: Path) -> None:
    """Refuse a LAS/LAZ header whose sizes and counts the file cannot hold (laspy would loop
    over a claimed VLR count of 2^32 - 1)."""
    import struct

    size = path.stat().st_size
    with open(path, "rb") as fh:
        head = fh.read(_LAS_MIN_HEADER)
    if len(head) < _LAS_MIN_HEADER or head[:4] != b"LASF":
        raise DataError(f"{path}: not a LAS file (no 'LASF' header of {_LAS_MIN_HEADER} bytes)")
    header_size, = struct.unpack_from("<H", head, 94)
    offset, n_vlrs = struct.unpack_from("<II", head, 96)
    if not _LAS_MIN_HEADER <= header_size <= offset <= size:
        raise DataError(f"{path}: the header's sizes (header {header_size}, point data at "
                        f"{offset}) do not fit the file's {size} bytes")
    if n_vlrs * _LAS_VLR_HEADER > offset - header_size:
        raise DataError(f"{path}: the header claims {n_vlrs} variable-length records, more "
                        f"than the {offset - header_size} bytes before the points can hold")


def _read_las(path: Path, fmt: str, columns: tuple[int, ...] | None) -> np.ndarray:
    import laspy

    _check_las_header(path)
    las = laspy.read(str(path))
    if columns is None:
        return np.column_stack([np.asarray(las.x), np.asarray(las.y), np.asarray(las.z)])
    # x, y, z scaled to coordinates, then the point format's other dimensions as stored
    names = ["x", "y", "z", *[d for d in las.point_format.dimension_names
                              if d not in ("X", "Y", "Z")]]
    return np.column_stack([np.asarray(las[n], dtype=np.float64)
                            for n in _named_columns(names, columns, path, "dimensions")])


def _read_obj(path: Path, fmt: str, columns: tuple[int, ...] | None) -> np.ndarray:
    """Every 'v' line of a Wavefront OBJ: a scan's points are vertices that no face uses, and
    trimesh's OBJ loader (which `read_mesh` uses for the faces) drops those."""
    no_columns(path, fmt, columns, "its vertices are x y z")
    rows = []
    with open_text(path) as fh:
        for line in fh:
            if line.startswith("v "):
                rows.append(line.split()[1:4])
    if not rows:
        raise DataError(f"{path}: OBJ file has no 'v' vertex lines")
    return np.array(rows, dtype=np.float64)


def _read_off(path: Path, fmt: str, columns: tuple[int, ...] | None) -> np.ndarray:
    no_columns(path, fmt, columns, "its vertices are x y z")
    with open_text(path) as fh:
        lines = [ln.split("#", 1)[0].split() for ln in fh]
    lines = [ln for ln in lines if ln]
    if not lines or not lines[0][0].endswith("OFF"):
        raise DataError(f"{path}: not an OFF file (no 'OFF' header)")
    head = lines[0][1:] if len(lines[0]) > 1 else lines[1]
    start = 1 if len(lines[0]) > 1 else 2
    nverts = int(head[0])
    rows = [ln[:3] for ln in lines[start:start + nverts]]
    if len(rows) < nverts:
        raise DataError(f"{path}: OFF file is truncated ({len(rows)} of {nverts} vertices)")
    return np.array(rows, dtype=np.float64)


def _read_conf(path: Path, fmt: str, columns: tuple[int, ...] | None) -> np.ndarray:
    """Aligned range scans (Stanford ``.conf``): every ``bmesh FILE tx ty tz qx qy qz qw`` line.

    Each scan's points p go to R(q)^-1 p + t, q scalar-last (on the bunny's scans this puts
    91 % of bun045's points within 1 mm of bun000's, against 0.3 % for R(q) p + t). Scans named
    in the file but absent are skipped with a warning; none present is an error.
    """
    no_columns(path, fmt, columns, "range scans of x y z, placed by their poses")
    from scipy.spatial.transform import Rotation

    out, missing = [], []
    with open_text(path) as fh:
        lines = list(bounded_lines(fh, path))
    folder = path.parent.resolve()
    for line in lines:
        tokens = line.split()
        if len(tokens) != 9 or tokens[0] != "bmesh":
            continue
        scan = (path.parent / tokens[1]).resolve()
        if folder not in scan.parents:
            raise DataError(f"{path}: scan {snippet(tokens[1])} is not in the .conf's folder "
                            "(scans must lie in it or below it)")
        if scan.suffix.lower() == ".conf":
            raise DataError(f"{path}: a .conf may not name another .conf "
                            f"({snippet(tokens[1])})")
        if not scan.exists():
            missing.append(tokens[1])
            continue
        t, q = np.array(tokens[2:5], float), np.array(tokens[5:9], float)
        pts = read_points(scan)
        if pts.shape[1] != 3:
            raise DataError(f"{scan}: a range scan must have 3 coordinates")
        out.append(Rotation.from_quat(q).inv().apply(pts) + t)
    if not out:
        raise DataError(f"{path}: no 'bmesh FILE tx ty tz qx qy qz qw' line names a scan here")
    if missing:
        warnings.warn(f"{path.name}: {len(missing)} scan(s) not found, skipped: "
                      f"{', '.join(missing)}", stacklevel=3)
    return np.concatenate(out)


_READERS: dict[str, Callable[[Path, str, tuple[int, ...] | None], np.ndarray]] = {
    "npy": _read_npy, "ply": _read_ply, "las": _read_las, "laz": _read_las, "pcd": read_pcd,
    "obj": _read_obj, "off": _read_off, "carmen": read_carmen, "conf": _read_conf,
}


def read_mesh(path: str | Path):
    """A triangle mesh (PLY, OBJ, OFF, STL) as a trimesh.Trimesh, faces required."""
    import trimesh

    path = Path(path)
    if not path.is_file():
        raise DataError(f"{path}: no such file")
    try:
        mesh = trimesh.load(path, process=False, force="mesh")
    except Exception as exc:  # trimesh raises many types on corrupt files
        raise DataError(f"{path}: cannot read a mesh: {_short(exc)}") from exc
    if not hasattr(mesh, "faces") or not len(mesh.faces):
        raise DataError(f"{path}: has no faces; slice its points without --from-mesh")
    if not np.isfinite(np.asarray(mesh.vertices)).all():
        raise DataError(f"{path}: vertices with NaN or infinite coordinates")
    return mesh
