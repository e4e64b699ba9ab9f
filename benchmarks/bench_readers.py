"""Readers (issue "Speed"): a 2M-row text table against ``np.loadtxt``, the peak memory of
``wavepoly info`` on it, and the chunked readers of large 3D files (binary PLY memory-mapped,
LAS/LAZ by laspy's chunk iterator) against reading them whole. The files are made here, in a
temporary folder, from a noisy sampled cylinder; nothing is committed."""

from __future__ import annotations

import subprocess
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path

import numpy as np

from wavepoly.io.readers import read_points
from wavepoly.io.tiles import CHUNK_POINTS, read_chunks

from .common import ROOT, best_time, table

TEXT_ROWS = 2_000_000
CLOUD_POINTS = 4_000_000


def _cylinder(n: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    t, h = rng.uniform(0, 2 * np.pi, n), rng.uniform(0, 20, n)
    pts = np.column_stack([5 * np.cos(t), 5 * np.sin(t), h])
    return pts + rng.normal(scale=0.01, size=pts.shape)


def _info_peak_mb(path: Path) -> float:
    """Peak resident memory (MB) of ``wavepoly info`` run on ``path`` in a process of its own."""
    probe = ("import resource, subprocess, sys; subprocess.run(sys.argv[1:], check=True, "
             "capture_output=True); "
             "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024)")
    wavepoly = Path(sys.executable).with_name("wavepoly")
    out = subprocess.run([sys.executable, "-c", probe, str(wavepoly), "info", str(path)],
                         capture_output=True, text=True, check=True, cwd=ROOT)
    return float(out.stdout.strip())


def _streamed(path: Path) -> tuple[float, float, str]:
    """Seconds to read a file chunk by chunk, the traced peak (MB) while doing so, and the
    chunks' dtype."""
    tracemalloc.start()
    t0 = time.perf_counter()
    count, dtype = 0, "-"
    for chunk in read_chunks(path):
        count += len(chunk)
        dtype = str(chunk.dtype)
    seconds = time.perf_counter() - t0
    peak = tracemalloc.get_traced_memory()[1] / 2**20
    tracemalloc.stop()
    return seconds, peak, dtype


def _whole_peak(path: Path) -> float:
    tracemalloc.start()
    read_points(path)
    peak = tracemalloc.get_traced_memory()[1] / 2**20
    tracemalloc.stop()
    return peak


def _text_rows(folder: Path) -> list[list[object]]:
    path = folder / "cloud.xyz"
    np.savetxt(path, _cylinder(TEXT_ROWS), fmt="%.6f")
    ours, pts = best_time(lambda: read_points(path), repeat=3)
    numpy, ref = best_time(lambda: np.loadtxt(path), repeat=2)
    same = "yes" if np.array_equal(pts, ref) else "no"
    return [[f"text .xyz, {TEXT_ROWS:,} rows", f"{ours:.2f}", f"{numpy:.2f} (np.loadtxt)", same,
             str(pts.dtype), "—", f"{_info_peak_mb(path):.0f}"]]


def _cloud_rows(folder: Path) -> list[list[object]]:
    import laspy
    from plyfile import PlyData, PlyElement

    cloud = _cylinder(CLOUD_POINTS)
    ply = folder / "cloud.ply"
    vertex = np.empty(len(cloud), dtype=[("x", "<f4"), ("y", "<f4"), ("z", "<f4")])
    vertex["x"], vertex["y"], vertex["z"] = cloud.T
    PlyData([PlyElement.describe(vertex, "vertex")]).write(str(ply))
    laz = folder / "cloud.laz"
    header = laspy.LasHeader(point_format=0, version="1.2")
    header.scales, header.offsets = [1e-4] * 3, cloud.min(axis=0)
    las = laspy.LasData(header)
    las.x, las.y, las.z = cloud.T
    las.write(str(laz))
    rows = []
    for name, path, whole in (("binary PLY (float32), memory-mapped", ply,
                               lambda p: PlyData.read(str(p))),
                              ("LAZ, laspy chunk iterator", laz, lambda p: laspy.read(str(p)))):
        seconds, peak, dtype = _streamed(path)
        reference, _ = best_time(lambda whole=whole, path=path: whole(path), repeat=1)
        rows.append([f"{name}, {CLOUD_POINTS:,} points", f"{seconds:.2f}",
                     f"{reference:.3f} (read whole)", "—", dtype,
                     f"{peak:.0f} streamed / {_whole_peak(path):.0f} whole", "—"])
    return rows


def run() -> str:
    with tempfile.TemporaryDirectory(prefix="wavepoly-bench-") as tmp:
        rows = _text_rows(Path(tmp)) + _cloud_rows(Path(tmp))
    return ("## Readers\n\nFiles made by the benchmark from a noisy cylinder. *seconds*: "
            "`read_points` for the text table (best of 3), `read_chunks` (the slicer's reader, "
            f"chunks of {CHUNK_POINTS:,} points) for the 3D files; *reference*: the same file "
            "read by NumPy, plyfile or laspy alone; *same*: bit-identical arrays; *traced MB*: "
            "peak Python allocation while reading, chunk by chunk against the whole file; "
            "*info MB*: peak resident memory of `wavepoly info` on the file (imports included)."
            "\n\n" + table(["file", "seconds", "reference s", "same", "dtype", "traced MB",
                            "info MB"], rows))
