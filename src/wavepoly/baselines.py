"""Reference simplifications to measure wavepoly against.

`min_vertices` is the optimal min-# answer: the fewest vertices, chosen among the given ordered
points, such that every point is within the tolerance of the polyline (Imai & Iri 1988, with the
O(n^2) feasibility test of Chan & Chin 1996). It is the limit the vertex count is measured
against. `douglas_peucker` is shapely's simplification, as most users would run it.

>>> t = np.linspace(0, np.pi, 200)
>>> arc = np.column_stack([np.cos(t), np.sin(t)])
>>> idx = min_vertices(arc, 0.01)
>>> bool(chord_errors(arc, idx, closed=False).max() <= 0.01), len(idx) < 20
(True, True)
"""

from __future__ import annotations

import numpy as np
import shapely

from .geometry import segment_distance
from .types import FloatArray, IntArray

#: Refuse feasibility matrices larger than this many points (memory grows as n^2).
MAX_POINTS = 12000


def _forward_feasible(points: FloatArray, tolerance: float, max_span: int) -> np.ndarray:
    """F[i, j - i]: every point strictly between i and j is within the tolerance of the RAY i->j.

    Chan & Chin's sweep: the directions from p_i that pass within the tolerance of p_k form an
    angular interval; (i, j) is feasible when the direction of p_j lies in the intersection of
    the intervals of i < k < j. Running max/min of the bounds gives that for all j at once.
    """
    n = len(points)
    out = np.zeros((n, max_span + 1), dtype=bool)
    for i in range(n):
        stop = min(n, i + max_span + 1)
        d = points[i + 1:stop] - points[i]
        if not len(d):
            continue
        r = np.hypot(d[:, 0], d[:, 1])
        theta = np.arctan2(d[:, 1], d[:, 0])
        far = r > tolerance
        ref = theta[np.argmax(far)] if far.any() else 0.0
        rel = (theta - ref + np.pi) % (2 * np.pi) - np.pi
        half = np.where(far, np.arcsin(np.minimum(tolerance / np.where(far, r, 1.0), 1.0)),
                        np.inf)
        lo = np.maximum.accumulate(np.where(far, rel - half, -np.inf))
        hi = np.minimum.accumulate(np.where(far, rel + half, np.inf))
        # j = i + 1 + m is feasible if its direction is inside the cone of points i+1 .. j-1
        lo_prev = np.concatenate([[-np.inf], lo[:-1]])
        hi_prev = np.concatenate([[np.inf], hi[:-1]])
        ok = (rel >= lo_prev - 1e-12) & (rel <= hi_prev + 1e-12)
        out[i, 1:len(ok) + 1] = ok
    return out


def feasible_shortcuts(points: FloatArray, tolerance: float, max_span: int | None = None
                       ) -> np.ndarray:
    """S[i, j - i]: the segment p_i p_j is within the tolerance of every point between them."""
    n = len(points)
    span = n - 1 if max_span is None else max_span
    fwd = _forward_feasible(points, tolerance, span)
    bwd = _forward_feasible(points[::-1], tolerance, span)
    out = np.zeros_like(fwd)
    for s in range(1, span + 1):  # (i, i+s) forward and (n-1-i-s, ...) backward
        i = np.arange(n - s)
        out[i, s] = fwd[i, s] & bwd[n - 1 - i - s, s]
    return out


def _fewest_edges(shortcuts: np.ndarray, start: int, end: int) -> IntArray:
    """Fewest-edge path start -> end in the DAG of feasible shortcuts (indices of its vertices)."""
    span = shortcuts.shape[1] - 1
    count = np.full(end + 1, np.iinfo(np.int64).max // 2)
    parent = np.full(end + 1, -1)
    count[start] = 0
    for j in range(start + 1, end + 1):
        lo = max(start, j - span)
        i = np.arange(lo, j)
        ok = shortcuts[i, j - i]
        cand = np.where(ok, count[lo:j], np.iinfo(np.int64).max // 2)
        k = int(np.argmin(cand))
        count[j], parent[j] = cand[k] + 1, lo + k
    path = [end]
    while path[-1] != start:
        path.append(int(parent[path[-1]]))
    return np.array(path[::-1], dtype=np.intp)


def min_vertices(points: FloatArray, tolerance: float, closed: bool = False) -> IntArray:
    """Indices of the fewest points whose polyline keeps every point within ``tolerance``.

    Open: the end points are kept. Closed: the best start is searched (an optimal polygon has a
    vertex within the first edge of the polygon that starts at point 0), and the returned
    indices do not repeat the first one.
    """
    pts = np.asarray(points, dtype=float)
    n = len(pts)
    if n > MAX_POINTS:
        raise ValueError(f"min_vertices is O(n^2) in memory: {n} points > {MAX_POINTS}")
    if not closed:
        if n <= 2:
            return np.arange(n)
        return _fewest_edges(feasible_shortcuts(pts, tolerance), 0, n - 1)
    doubled = np.vstack([pts, pts])
    shortcuts = feasible_shortcuts(doubled, tolerance, max_span=n)
    first = _fewest_edges(shortcuts, 0, n)
    best = first
    for s in range(1, int(first[1]) + 1 if len(first) > 1 else 1):
        path = _fewest_edges(shortcuts, s, s + n)
        if len(path) < len(best):
            best = path
    return np.sort(best[:-1] % n)


def min_vertices_covering(ordered: FloatArray, closed: bool, points: FloatArray,
                          tolerance: float) -> IntArray:
    """Fewest ordered points whose polyline keeps every *input* point within ``tolerance``.

    The limit for the guarantee wavepoly gives: `min_vertices` only keeps the ordered points
    within the tolerance, which on noisy scans leaves input points outside it. Each input point
    is tied to the place along the ordered polyline it projects to; where no subset of ordered
    points can cover a point, the polyline of all ordered points is returned as is.
    """
    from .reconstruction import select_vertices

    line = shapely.linearrings(ordered) if closed else shapely.linestrings(ordered)
    seg = np.linalg.norm(np.diff(np.vstack([ordered, ordered[:1]]) if closed else ordered,
                                 axis=0), axis=1)
    arc = np.concatenate([[0.0], np.cumsum(seg)])
    total = arc[-1]
    vparams = arc[:len(ordered)] / total
    params = shapely.line_locate_point(line, shapely.points(points)) / total
    if closed:
        params = np.mod(params, 1.0)
    try:
        _, kept = select_vertices(ordered, vparams, points, params, closed, tolerance)
    except RuntimeError:  # some point is out of reach of every chord: no covering subset
        return np.arange(len(ordered))
    return np.searchsorted(vparams, kept)


def chord_errors(points: FloatArray, vertices: IntArray, closed: bool) -> FloatArray:
    """Distance of every point to the polyline through ``points[vertices]`` (segment by segment).

    Each point is measured against the chord of the vertices on either side of it in order,
    which is the criterion `min_vertices` optimizes.
    """
    n = len(points)
    v = np.asarray(vertices)
    idx = np.arange(n)
    if closed:
        ext = np.append(v, v[0] + n)
        seg = np.searchsorted(ext, np.where(idx < v[0], idx + n, idx), side="right") - 1
        a, b = points[ext[seg] % n], points[ext[seg + 1] % n]
    else:
        seg = np.clip(np.searchsorted(v, idx, side="right") - 1, 0, len(v) - 2)
        a, b = points[v[seg]], points[v[seg + 1]]
    return segment_distance(points, a, b)


def douglas_peucker(points: FloatArray, tolerance: float, closed: bool = False) -> FloatArray:
    """shapely's Douglas-Peucker simplification of the ordered points (vertices, not indices)."""
    geom = shapely.linearrings(points) if closed else shapely.linestrings(points)
    simple = shapely.simplify(geom, tolerance, preserve_topology=False)
    coords = shapely.get_coordinates(simple)
    return coords[:-1] if closed else coords
