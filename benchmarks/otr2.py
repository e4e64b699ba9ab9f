"""CGAL's Optimal Transportation Curve Reconstruction (OTR2) as a peer, through the small C++
driver in ``benchmarks/peers/otr2.cpp`` (built by ``make bench`` when CGAL is available).

OTR2's own tolerance is a transport cost, not a distance, so it is driven by target vertex
count (``run_until``): one decimation run writes its output at many counts, and the fewest
vertices whose output keeps every input point within ε is reported.
"""

from __future__ import annotations

import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import shapely

BINARY = Path(__file__).resolve().parent / "peers" / "build" / "otr2"
MAX_POINTS = 6500  # about 2.5 ms a point here: larger cases are left out to keep make bench short


@dataclass(frozen=True)
class Snapshot:
    """OTR2's output after ``run_until(target)``: vertices (k, 2), the indices of isolated
    vertices, segments (m, 2) as vertex index pairs, and seconds since the run started."""

    target: int
    vertices: np.ndarray
    isolated: np.ndarray
    segments: np.ndarray
    seconds: float

    @property
    def pieces(self) -> np.ndarray:
        """The output as shapely geometries: one line per segment, one point per isolated
        vertex."""
        lines = shapely.linestrings(self.vertices[self.segments.reshape(-1)].reshape(-1, 2, 2))
        points = shapely.points(self.vertices[self.isolated])
        return np.concatenate([np.atleast_1d(lines), np.atleast_1d(points)])

    def distance(self, points: np.ndarray) -> np.ndarray:
        """Distance of each of ``points`` (n, 2) to the output."""
        tree = shapely.STRtree(self.pieces)
        _, dist = tree.query_nearest(shapely.points(points), return_distance=True,
                                     all_matches=False)
        return dist

    def fragments_and_open_ends(self) -> tuple[int, int]:
        """Connected pieces of the output (isolated vertices count as pieces) and vertices of
        degree 1 (open ends)."""
        from scipy.sparse import coo_matrix
        from scipy.sparse.csgraph import connected_components

        n = len(self.vertices)
        a, b = self.segments.T if len(self.segments) else (np.empty(0, int),) * 2
        graph = coo_matrix((np.ones(len(a)), (a, b)), shape=(n, n))
        pieces, _ = connected_components(graph, directed=False)
        degree = np.bincount(np.concatenate([a, b]), minlength=n)
        return int(pieces), int(np.count_nonzero(degree == 1))


@dataclass(frozen=True)
class OtrResult:
    """The fewest-vertex OTR2 output within ε (or the closest one, if none is)."""

    n_vertices: int
    max_error: float
    seconds: float
    fragments: int
    open_ends: int
    lines: list


def available() -> bool:
    return BINARY.exists()


def parse_output(text: str) -> list[Snapshot]:
    """The snapshots written by the driver (see its header for the format)."""
    lines = text.splitlines()
    out, i = [], 0
    while i < len(lines):
        tag, target, n_v, n_iso, n_seg, seconds = lines[i].split()
        if tag != "T":
            raise ValueError(f"unexpected line from otr2: {lines[i]!r}")
        n_v, n_iso, n_seg = int(n_v), int(n_iso), int(n_seg)
        i += 1
        verts = np.array([r.split() for r in lines[i:i + n_v]], float).reshape(n_v, 2)
        i += n_v
        iso = np.array(lines[i:i + n_iso], int).reshape(n_iso)
        i += n_iso
        segs = np.array([r.split() for r in lines[i:i + n_seg]], int).reshape(n_seg, 2)
        i += n_seg
        out.append(Snapshot(int(target), verts, iso, segs, float(seconds)))
    return out


def targets(n_points: int) -> list[int]:
    """Decreasing vertex counts: every count up to 200, then steps of 5 % up to n/2."""
    top = max(n_points // 2, 4)
    big = np.unique(np.round(np.geomspace(200, top, 120)).astype(int)) if top > 200 else []
    return sorted({*map(int, big), *range(3, min(top, 200) + 1)}, reverse=True)


def fewest_within(snapshots: list[Snapshot], points: np.ndarray, eps: float) -> OtrResult:
    """The snapshot with the fewest vertices that keeps every point within ``eps``; when none
    does, the one with the smallest error."""
    best = None
    for snap in sorted(snapshots, key=lambda s: len(s.vertices)):
        if not len(snap.vertices):
            continue
        err = float(snap.distance(points).max())
        if best is None or err < best[1]:
            best = (snap, err)
        if err <= eps:
            break
    snap, err = best
    pieces, ends = snap.fragments_and_open_ends()
    lines = [(snap.vertices[s], False) for s in snap.segments]
    return OtrResult(len(snap.vertices), err, snap.seconds, pieces, ends, lines)


def reconstruct(points: np.ndarray, eps: float) -> OtrResult:
    """Run OTR2 on ``points`` (n, 2) and pick its fewest vertices within ``eps``."""
    with tempfile.NamedTemporaryFile("w", suffix=".txt") as f:
        np.savetxt(f, points, fmt="%.17g")
        f.flush()
        run = subprocess.run([str(BINARY), f.name, *map(str, targets(len(points)))],
                             capture_output=True, text=True, check=True)
    return fewest_within(parse_output(run.stdout), points, eps)
