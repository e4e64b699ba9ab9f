"""Scans read in chunks: one file too large to load at once, or many tiles as one cloud.

A survey or a large part comes as many LAS/LAZ tiles; sliced together they are one cloud. Each
tile is read chunk by chunk (laspy's chunk iterator for LAS/LAZ, a memory map for binary PLY
and ``.npy``; other formats are small and read whole), so that no process holds more than a
chunk of a tile beyond what it keeps: a first pass gathers each tile's count and height range
(`tile_summary`), a second splits each tile's points into the layers they belong to
(`tile_layers`), and a layer's worker is sent only its layers' pieces.
"""

from __future__ import annotations

import glob
import warnings
from collections.abc import Iterator, Sequence
from pathlib import Path

import numpy as np

from ..errors import DataError
from ..geometry import to_plane
from ..types import FloatArray, TileSummary
from .readers import FORMATS, _check_las_header, _short, detect_format, read_points

#: Points per chunk: 24 MB of float64 coordinates, small beside a worker's memory and large
#: enough that the per-chunk overhead of the readers is negligible.
CHUNK_POINTS = 1_000_000
_GLOB = set("*?[")


def expand_sources(sources: Sequence[str | Path]) -> list[Path]:
    """The files of ``sources``: paths, folders (their point files, sorted) and glob
    patterns (sorted), in the order given; a source that names nothing is an error."""
    out: list[Path] = []
    for source in sources:
        text = str(source)
        if _GLOB & set(text) and not Path(text).exists():
            found = sorted(Path(p) for p in glob.glob(text) if Path(p).is_file())
            if not found:
                raise DataError(f"{text}: the pattern matches no file")
            out.extend(found)
        elif Path(text).is_dir():
            found = sorted(p for p in Path(text).iterdir() if p.is_file() and _known(p))
            if not found:
                raise DataError(f"{text}: the folder holds no point file "
                                f"({', '.join(FORMATS)})")
            out.extend(found)
        else:
            out.append(Path(text))
    return out


def _known(path: Path) -> bool:
    try:
        detect_format(path)
    except DataError:
        return False
    return True


def read_chunks(path: str | Path, *, fmt: str | None = None,
                columns: Sequence[int] | None = None,
                size: int = CHUNK_POINTS) -> Iterator[FloatArray]:
    """The (n, 3) points of a 3D scan file, ``size`` points at a time, in file order: float32
    where the file stores float32 (a binary PLY's), else float64.

    Raises `DataError` naming the file for an unreadable file, fewer than 3 coordinates, or
    NaN / infinite coordinates.
    """
    path = Path(path)
    fmt = (fmt or detect_format(path)).lower()
    if fmt in ("las", "laz") and columns is None:
        chunks = _las_chunks(path, size)
    elif fmt == "ply" and columns is None:
        chunks = _ply_chunks(path, size)
    else:
        chunks = _whole_in_chunks(read_points(path, fmt=fmt, columns=columns), size)
    try:
        for chunk in chunks:
            yield _checked(chunk, path)
    except DataError:
        raise
    except Exception as exc:  # third-party readers raise their own types on corrupt files
        raise DataError(f"{path}: cannot read as {fmt}: {_short(exc)}") from exc


def _checked(chunk: np.ndarray, path: Path) -> FloatArray:
    if chunk.ndim != 2 or chunk.shape[1] != 3:
        raise DataError(f"{path}: slicing needs 3 coordinates per point, got "
                        f"{chunk.shape[1] if chunk.ndim == 2 else chunk.shape}")
    bad = ~np.isfinite(chunk).all(axis=1)
    if bad.any():
        raise DataError(f"{path}: {int(bad.sum())} point(s) have NaN or infinite coordinates")
    return chunk


def _las_chunks(path: Path, size: int) -> Iterator[np.ndarray]:
    import laspy

    if not path.is_file():
        raise DataError(f"{path}: no such file")
    _check_las_header(path)
    with laspy.open(str(path)) as reader:
        for points in reader.chunk_iterator(size):
            yield np.column_stack([np.asarray(points.x, dtype=np.float64),
                                   np.asarray(points.y, dtype=np.float64),
                                   np.asarray(points.z, dtype=np.float64)])


def _ply_chunks(path: Path, size: int) -> Iterator[np.ndarray]:
    from plyfile import PlyData

    if not path.is_file():
        raise DataError(f"{path}: no such file")
    with warnings.catch_warnings():  # plyfile warns on empty ASCII elements
        warnings.simplefilter("ignore", UserWarning)
        ply = PlyData.read(str(path), mmap="r")  # binary PLY stays on disk until read
    if "vertex" not in ply:
        raise DataError(f"{path}: PLY file has no 'vertex' element")
    vertex = ply["vertex"].data
    names = [n for n in ("x", "y", "z") if n in (vertex.dtype.names or ())]
    if len(names) < 3:
        raise DataError(f"{path}: PLY vertices have no x/y/z properties")
    single = all(vertex.dtype[n].kind == "f" and vertex.dtype[n].itemsize == 4 for n in names)
    dtype = np.float32 if single else np.float64  # float32 kept: half the memory of a cloud
    for start in range(0, len(vertex), size):
        part = vertex[start:start + size]
        yield np.column_stack([np.asarray(part[n], dtype=dtype) for n in names])


def _whole_in_chunks(points: FloatArray, size: int) -> Iterator[np.ndarray]:
    for start in range(0, len(points), size):
        yield points[start:start + size]


def read_cloud(paths: Sequence[str | Path], *, fmt: str | None = None,
               columns: Sequence[int] | None = None) -> FloatArray:
    """The union of 3D scan files as one (N, 3) cloud, in file then point order."""
    parts = [c for p in paths for c in read_chunks(p, fmt=fmt, columns=columns)]
    if not parts:
        raise DataError(f"{', '.join(map(str, paths))}: contains no points")
    return np.concatenate(parts)


def tile_summary(path: str | Path, basis: FloatArray, *, fmt: str | None = None,
                 columns: Sequence[int] | None = None) -> TileSummary:
    """A tile's point count and height range along ``basis[2]``, read chunk by chunk."""
    count, low, high = 0, np.inf, -np.inf
    for chunk in read_chunks(path, fmt=fmt, columns=columns):
        h = to_plane(chunk, basis)[:, 2]
        count += len(chunk)
        if len(h):
            low, high = min(low, float(h.min())), max(high, float(h.max()))
    return TileSummary(str(path), count, low, high)


def tile_layers(path: str | Path, basis: FloatArray, bottoms: FloatArray, *,
                fmt: str | None = None, columns: Sequence[int] | None = None
                ) -> list[FloatArray]:
    """A tile's points in plane coordinates (u, v, height), split by layer: item ``k`` holds
    those with heights in [bottoms[k], bottoms[k + 1]) (the last layer: from its bottom up),
    in file order."""
    pieces: list[list[FloatArray]] = [[] for _ in bottoms]
    for chunk in read_chunks(path, fmt=fmt, columns=columns):
        uvh = to_plane(chunk, basis)
        layer = np.clip(np.searchsorted(bottoms, uvh[:, 2], side="right") - 1, 0,
                        len(bottoms) - 1)
        order = np.argsort(layer, kind="stable")
        cuts = np.searchsorted(layer[order], np.arange(1, len(bottoms)))
        for k, part in enumerate(np.split(uvh[order], cuts)):
            if len(part):
                pieces[k].append(part)
    return [np.concatenate(p) if p else np.empty((0, 3)) for p in pieces]


def merge_layer(*pieces: FloatArray) -> FloatArray:
    """One layer's points from its pieces in the tiles (in tile order), sorted by height with
    ties in file order: the very rows of that layer in the whole cloud sorted by height."""
    points = np.concatenate(pieces) if pieces else np.empty((0, 3))
    return points[np.argsort(points[:, 2], kind="stable")]
