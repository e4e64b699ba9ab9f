"""Reference simplifications to measure wavepoly against (a public module for comparisons).

Researchers comparing curve-reconstruction methods measure vertex counts against the optimal
min-# answer and against Douglas-Peucker, so these live in the package, documented, rather than
in the benchmarks alone; the benchmarks and the tests of the guarantee use them too.

`min_vertices` is the optimal min-# answer: the fewest vertices, chosen among the given ordered
points, such that every point is within the tolerance of the polyline (Imai & Iri 1988, with
Chan & Chin's cone test). `min_vertices_covering` is the same limit for wavepoly's guarantee:
every *input* point within the tolerance. Both use `wavepoly.simplify`, the selection that
wavepoly's own reconstruction uses. `douglas_peucker` is shapely's simplification, as most
users would run it.

>>> t = np.linspace(0, np.pi, 200)
>>> arc = np.column_stack([np.cos(t), np.sin(t)])
>>> idx = min_vertices(arc, 0.01)
>>> bool(chord_errors(arc, idx, closed=False).max() <= 0.01), len(idx) < 20
(True, True)

References
----------
.. [1] H. Imai and M. Iri, "Polygonal approximations of a curve: formulations and
   algorithms", in Computational Morphology, North-Holland, 1988, pp. 71-86.
.. [2] D. H. Douglas and T. K. Peucker, "Algorithms for the reduction of the number of points
   required to represent a digitized line or its caricature", Cartographica 10(2), 1973.
"""

from __future__ import annotations

import numpy as np
import shapely

from .geometry import segment_distance
from .simplify import feasible_chords, select_vertices
from .types import FloatArray, IntArray

#: Refuse dense feasibility matrices of more points than this (memory grows as n^2).
MAX_POINTS = 12000


def _index_params(n: int) -> FloatArray:
    """Each ordered point's own parameter: its index, scaled into [0, 1)."""
    return np.arange(n) / n


def feasible_shortcuts(points: FloatArray, tolerance: float, max_span: int | None = None
                       ) -> np.ndarray:
    """S[i, j - i]: the segment p_i p_j is within the tolerance of every point between them.

    A dense view of `wavepoly.simplify.feasible_chords` over the ordered points themselves.
    """
    pts = np.asarray(points, dtype=float)
    n = len(pts)
    if n > MAX_POINTS:
        raise ValueError(f"feasible_shortcuts is O(n^2) in memory: {n} points > {MAX_POINTS}")
    span = n - 1 if max_span is None else max_span
    u = _index_params(n)
    rows = feasible_chords(pts, u, pts, u, tolerance)
    out = np.zeros((n, span + 1), dtype=bool)
    for i, row in enumerate(rows):
        m = min(len(row), span)
        out[i, 1:m + 1] = row[:m]
    return out


def min_vertices(points: FloatArray, tolerance: float, closed: bool = False) -> IntArray:
    """Indices of the fewest points whose polyline keeps every point within ``tolerance``.

    Open: the end points are kept. Closed: the best start is searched, and the returned
    indices do not repeat the first one.
    """
    pts = np.asarray(points, dtype=float)
    n = len(pts)
    if n <= (3 if closed else 2):
        return np.arange(n)
    u = _index_params(n)
    _, kept = select_vertices(pts, u, pts, u, closed, tolerance, simple=False)
    return np.searchsorted(u, kept)


def min_vertices_covering(ordered: FloatArray, closed: bool, points: FloatArray,
                          tolerance: float) -> IntArray:
    """Fewest ordered points whose polyline keeps every *input* point within ``tolerance``.

    The limit for the guarantee wavepoly gives: `min_vertices` only keeps the ordered points
    within the tolerance, which on noisy scans leaves input points outside it. Each input point
    is tied to the place along the ordered polyline it projects to; where no subset of ordered
    points can cover a point, the polyline of all ordered points is returned as is.
    """
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
        _, kept = select_vertices(ordered, vparams, points, params, closed, tolerance,
                                  simple=False)
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
