"""Fewest vertices within the tolerance over feasible chords (Imai & Iri; Chan & Chin).

Given candidate vertices along a contour, each at a curve parameter, and data points, each at
the parameter of the edge that stands for it (the *own-edge rule*: a point with parameter p
belongs to the edge from the last vertex at or before p), `select_vertices` returns the fewest
candidates whose polygon keeps every point within the tolerance of its own edge. That distance
bounds the distance to the polygon, so the result is verified by construction.

A chord (a, b) is feasible when every point between the two candidates is within the tolerance
of it; Chan & Chin's cone test decides that for all chords from a vertex in one sweep over the
points (`feasible_chords`), and the fewest-edge path over feasible chords (`shortest_path`) is
the optimal subset (Imai & Iri). Only the points that can be convex-hull vertices of each gap
between candidates enter the sweep (`geometry.hull_candidates`): the cone's distances are
convex in the point, so they decide the same chords.

Reconstruction (§4) uses it to choose among the wavelet polygon's vertices and the ordered
points; the min-# baselines (`wavepoly.baselines`) use it on the ordered points alone.

References
----------
.. [1] H. Imai and M. Iri, "Polygonal approximations of a curve: formulations and
   algorithms", in Computational Morphology, North-Holland, 1988, pp. 71-86.
.. [2] W. S. Chan and F. Chin, "Approximation of polygonal curves with minimum number of line
   segments or minimum error", Int. J. Comput. Geom. Appl. 6(1), 1996, pp. 59-77.
.. [3] S. G. Akl and G. T. Toussaint, "A fast convex hull algorithm", Inf. Process. Lett. 7(5),
   1978, pp. 219-222.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from scipy.ndimage import maximum_filter1d

from .chord_validity import (
    EXACT_ROUNDS,
    MAX_VALIDITY_ROUNDS,
    allow_backbone,
    fixed_edges_met,
    forbid,
    forbid_across,
    invalid_chords,
)
from .geometry import hull_candidates
from .kernels import edge_distances, fewest_edges, sweep_cones
from .types import SLACK, FloatArray, IntArray

#: Angular round-off (radians) allowed when a chord's direction meets a cone's bound.
ANGLE_SLACK = 1e-12
#: Points swept together per row of the cone test: large enough for NumPy to pay off, small
#: enough that rows whose cones close early stop soon.
SWEEP_WINDOW = 128


@dataclass(frozen=True)
class Frame:
    """Candidate vertices and data points along one contour, both sorted by parameter.

    v, u: candidate vertices and their parameters; pts, prm: data points and theirs.
    """

    v: FloatArray
    u: FloatArray
    pts: FloatArray
    prm: FloatArray

    def mirrored(self) -> Frame:
        """The same contour run backwards (parameters negated, order reversed)."""
        return Frame(self.v[::-1], -self.u[::-1], self.pts[::-1], -self.prm[::-1])


def edge_of(vparams: FloatArray, params: FloatArray, closed: bool) -> IntArray:
    """Index of the polygon edge (vertex i to i+1) whose parameter span holds each point."""
    k = len(vparams)
    key = np.mod(vparams, 1.0) if closed else vparams
    e = np.searchsorted(key, np.mod(params, 1.0) if closed else params, side="right") - 1
    if closed:
        return np.mod(e, k)
    return np.clip(e, 0, k - 2)


def own_edge_distance(vertices: FloatArray, vparams: FloatArray, points: FloatArray,
                      params: FloatArray, closed: bool) -> FloatArray:
    """Distance of each point to the polygon edge whose parameter span holds it.

    This bounds the distance to the polygon; keeping it within the tolerance is the invariant
    that repair establishes and the selection preserves.
    """
    if len(points) == 0:
        return np.zeros(0)
    e = edge_of(vparams, params, closed)
    return edge_distances(np.ascontiguousarray(points, dtype=np.float64), e,
                          np.ascontiguousarray(vertices, dtype=np.float64))


def select_vertices(vertices: FloatArray, vparams: FloatArray, points: FloatArray,
                    params: FloatArray, closed: bool, tolerance: float, *,
                    backbone: IntArray | None = None,
                    obstacles: shapely.STRtree | None = None, simple: bool = True
                    ) -> tuple[FloatArray, FloatArray]:
    """The fewest of the polygon's own vertices that keep every point within ``tolerance``,
    and whose polygon is simple and meets no edge of ``obstacles``.

    A chord from vertex a to vertex b is feasible when every point whose parameter lies between
    theirs is within the tolerance of it (the own-edge invariant of the repair, so the result
    is verified by construction). The shortest path over feasible chords (Imai & Iri) is the
    optimal subset of an open contour. On a closed contour every start in a window that any
    polygon must have a vertex in is tried (`_closed_starts`), and the best is kept.

    Validity is part of feasibility: a chord of the chosen path that meets an obstacle edge
    (the contours already fixed nearby), or meets another chord of the path (a self-crossing
    or a fold), is made infeasible and the path is solved again, until the path is valid
    (`MAX_VALIDITY_ROUNDS`). Chords that meet obstacles are infeasible whatever the rest of the
    path, so the result is the optimum under that constraint; a crossing between two chords
    forbids both, which keeps the result valid at the cost of, rarely, a vertex. The edges of
    the ``backbone`` (the verified polygon) are never forbidden, so a path always exists.
    Where a path still crosses after `EXACT_ROUNDS`, every chord that meets the backbone edges
    its bad chords meet is forbidden at once (`wavepoly.chord_validity.forbid_across`), not
    the next one of the family the following round: still valid, at the cost of a vertex or
    two.
    ``simple=False`` (and no obstacles) gives the classic, unconstrained min-# optimum.
    """
    k = len(vertices)
    if k <= (3 if closed else 2):
        return vertices, vparams
    if not closed:  # points beyond the ends belong to the end edges (as in `edge_of`)
        params = np.clip(params, vparams[0], np.nextafter(vparams[-1], -np.inf))
    order = np.argsort(np.mod(params, 1.0) if closed else params, kind="stable")
    pts, prm = points[order], (np.mod(params, 1.0) if closed else params)[order]
    u = np.mod(vparams, 1.0) if closed else vparams.copy()
    pts, prm = _hull_of_each_gap(pts, prm, u)
    if closed:  # unroll: vertices and points twice round, parameters + 1 the second time
        vertices2, u = np.vstack([vertices, vertices]), np.concatenate([u, u + 1.0])
        pts, prm = np.vstack([pts, pts]), np.concatenate([prm, prm + 1.0])
    else:
        vertices2 = vertices
    feasible = _feasible_chords(Frame(vertices2, u, pts, prm), tolerance * (1 + SLACK),
                                max_span=k if closed else k - 1, periodic=closed)
    fixed: set[tuple[int, int]] = set()
    if backbone is not None and len(backbone) >= 2:
        fixed = allow_backbone(feasible, backbone, k, closed)
    path = _best_path(feasible, k, closed)
    for rounds in range(MAX_VALIDITY_ROUNDS if simple or obstacles is not None else 0):
        bad = invalid_chords(vertices, path, k, closed, obstacles, fixed)
        if not bad:
            break
        for a, b in bad:
            forbid(feasible, a, b, k, closed)
        if rounds >= EXACT_ROUNDS:
            forbid_across(feasible, vertices, fixed_edges_met(vertices, path, bad, k, fixed),
                          k, closed, fixed)
        try:
            path = _best_path(feasible, k, closed)
        except RuntimeError:  # nothing valid through these candidates: the caller's fallback
            break
    keep = np.sort(path[:-1] % k) if closed else path
    return vertices[keep], vparams[keep]


def _best_path(feasible: list[np.ndarray], k: int, closed: bool) -> IntArray:
    """The fewest-edge path over the feasible chords (closed: unrolled, from a start s to
    s + k)."""
    chords = flat_chords(feasible)
    if not closed:
        return shortest_path(feasible, 0, k - 1, chords=chords)
    best = None
    for start in _closed_starts(feasible, k):
        try:
            path = shortest_path(feasible, start, start + k, min_edges=3, chords=chords)
        except RuntimeError:  # no polygon has this vertex; another start in the window does
            continue
        if best is None or len(path) < len(best):
            best = path
    if best is None:
        raise RuntimeError("internal error: no feasible polygon")
    return best


def feasible_chords(vertices: FloatArray, vparams: FloatArray, points: FloatArray,
                    params: FloatArray, tolerance: float) -> list[np.ndarray]:
    """For each vertex a of an open contour, a boolean array over b = a+1 ..: is chord (a, b)
    feasible, i.e. every point with parameter in [vparams[a], vparams[b]) within ``tolerance``
    of it. The arrays stop at the last b that the forward cone reaches.

    Parameters
    ----------
    vertices, vparams : (k, 2) candidate vertices and their increasing parameters.
    points, params : (n, 2) data points and their parameters.
    tolerance : the distance every point between a chord's ends must keep.
    """
    order = np.argsort(params, kind="stable")
    frame = Frame(np.asarray(vertices, float), np.asarray(vparams, float), points[order],
                  params[order])
    return _feasible_chords(frame, tolerance * (1 + SLACK), max_span=len(vertices) - 1)


def _hull_of_each_gap(pts: FloatArray, prm: FloatArray, u: FloatArray
                      ) -> tuple[FloatArray, FloatArray]:
    """The points (sorted by parameter ``prm``) that may be hull vertices of the points between
    two consecutive vertex parameters ``u``: the cone test's distances are convex functions of
    the point, so a chord keeps every point within the tolerance exactly when it keeps these.
    Points at a vertex's own parameter form a gap of their own (both sweep directions see the
    same gaps)."""
    cuts = np.concatenate([[0], np.searchsorted(prm, u, "left"), np.searchsorted(prm, u, "right")])
    starts = np.unique(cuts[cuts < len(prm)])
    keep = hull_candidates(pts, starts)
    return pts[keep], prm[keep]


def _closed_starts(feasible: list[np.ndarray], k: int) -> IntArray:
    """Starts to try on a closed contour of ``k`` vertices (``feasible`` unrolled twice round).

    Every polygon has, for each vertex a, a vertex in [a, M(a)], where M(a) is the farthest
    vertex that a feasible chord starting before a reaches: the polygon's edge over a ends
    there at the latest. The vertex with the narrowest window (a corner) gives the fewest starts.
    """
    last = np.array([a + 1 + int(np.flatnonzero(f)[-1]) if f.any() else a
                     for a, f in enumerate(feasible[:k])])
    last = np.concatenate([last, last + k])  # the second turn's arrays are cut at its end
    # M(a) for a in [k, 2k): the largest ``last`` over the k vertices before a
    before = maximum_filter1d(last, size=k, origin=(k - 1) // 2)[k - 1:2 * k - 1]
    window = np.maximum(before - np.arange(k, 2 * k), 0)
    a = int(np.argmin(window))
    return np.arange(a, a + window[a] + 1) % k


def _feasible_chords(frame: Frame, limit: float, max_span: int, periodic: bool = False
                     ) -> list[np.ndarray]:
    """For each vertex a, a boolean array over b = a+1 .. : is chord (a, b) feasible.

    Chan & Chin's cone test, swept over the points in parameter order: chord (a, b) keeps every
    point between them within ``limit`` exactly when b lies in the cone of directions from a
    that pass within ``limit`` of each of those points, and a in the same cone seen from b.
    The arrays stop at the last b the forward cone reaches (every later chord is infeasible).
    """
    n = len(frame.v)
    k = n // 2 if periodic else n  # the unrolled second turn repeats the first: sweep once
    fwd = _sweep_cones(frame, np.arange(k), limit, max_span, "left")
    # backwards = forwards on the mirrored contour; the own-edge rule u[a] <= p < u[b] becomes
    # u'[b'] < p' <= u'[a'], hence the other searchsorted side
    bwd = _sweep_cones(frame.mirrored(), np.arange(k), limit, max_span, "right")[::-1]
    if periodic:
        fwd, bwd = fwd * 2, bwd * 2
    fwd = [f[: n - 1 - a] for a, f in enumerate(fwd)]
    width = max(1, max(len(f) for f in fwd + bwd))
    ahead, behind = _padded(fwd, width), _padded(bwd, width)
    a, off = np.nonzero(ahead)
    b = a + off + 1  # chord (a, b) needs a in the backward cone of b, at the same offset
    both = np.zeros_like(ahead)
    both[a, off] = behind[b, off]
    return [both[i, : len(f)] for i, f in enumerate(fwd)]


def _padded(rows: list[np.ndarray], width: int) -> np.ndarray:
    out = np.zeros((len(rows), width), dtype=bool)
    lengths = np.array([len(r) for r in rows])
    if lengths.sum():
        out[np.arange(width) < lengths[:, None]] = np.concatenate(rows)
    return out


def _wrap(angle: FloatArray) -> FloatArray:
    return (angle + np.pi) % (2 * np.pi) - np.pi


def _sweep_cones(frame: Frame, rows: IntArray, limit: float, max_span: int, side: str
                 ) -> list[np.ndarray]:
    """ok[a][m]: vertex a+m+1 lies in the cone from vertex a over the points between them
    (the compiled `wavepoly.kernels.sweep_cones`; `_sweep_cones_reference` is its NumPy
    twin, for the tests)."""
    n = len(frame.v)
    last = np.minimum(rows + max_span, n - 1)
    at = np.searchsorted(frame.prm, frame.u, side)  # points before each vertex's parameter
    a, b, ok = sweep_cones(np.ascontiguousarray(frame.v), at, np.ascontiguousarray(frame.pts),
                           np.asarray(rows, dtype=np.intp), last, float(limit), ANGLE_SLACK)
    return _rows_of(rows, a, b, ok)


def _sweep_cones_reference(frame: Frame, rows: IntArray, limit: float, max_span: int,
                           side: str) -> list[np.ndarray]:
    """ok[a][m]: vertex a+m+1 lies in the cone from vertex a over the points between them.

    All starting vertices sweep together, `SWEEP_WINDOW` points at a time: the cone from a is the
    intersection, over the points with parameter in [u[a], u[b]) (``side="left"``), of the
    directions that pass within ``limit`` of each point farther than ``limit``. A row stops at
    the window where its cone closes; the targets after it are infeasible and left out.
    """
    v, u, pts, prm = frame.v, frame.u, frame.pts, frame.prm
    window = SWEEP_WINDOW
    n = len(v)
    last = np.minimum(rows + max_span, n - 1)
    at = np.searchsorted(prm, u, side)  # points before each vertex's parameter
    start, stop = at[rows], at[last]
    lo, hi = np.full(len(rows), -np.inf), np.full(len(rows), np.inf)
    ref = np.full(len(rows), np.nan)
    found_a, found_b, found_ok = [], [], []
    # targets with no point between them and a: always feasible
    first = np.clip(np.searchsorted(at, start, "right"), rows + 1, last + 1)
    _record(found_a, found_b, found_ok, rows, rows + 1, first, None)
    active = np.flatnonzero(last > rows)
    j0 = 0
    while len(active):
        a, s = rows[active], start[active]
        idx = s[:, None] + np.arange(j0, j0 + window)
        valid = idx < stop[active][:, None]
        d = pts[np.minimum(idx, len(pts) - 1)] - v[a][:, None, :]
        r = np.hypot(d[..., 0], d[..., 1])
        far = (r > limit) & valid
        theta = np.arctan2(d[..., 1], d[..., 0])
        new = np.isnan(ref[active]) & far.any(axis=1)
        ref[active[new]] = theta[new, np.argmax(far[new], axis=1)]
        base = np.nan_to_num(ref[active])
        rel = _wrap(theta - base[:, None])
        half = np.arcsin(np.minimum(limit / np.where(far, r, 1.0), 1.0))
        lo_w = np.maximum(np.maximum.accumulate(np.where(far, rel - half, -np.inf), axis=1),
                          lo[active][:, None])
        hi_w = np.minimum(np.minimum.accumulate(np.where(far, rel + half, np.inf), axis=1),
                          hi[active][:, None])
        # targets whose count of points before them falls in this window
        b_from = np.clip(np.searchsorted(at, s + j0, "right"), a + 1, last[active] + 1)
        b_to = np.clip(np.searchsorted(at, s + j0 + window, "right"), a + 1, last[active] + 1)
        row, b = _ranges(b_from, b_to)
        col = at[b] - s[row] - j0 - 1
        cone_lo, cone_hi = lo_w[row, col], hi_w[row, col]
        t_dir = v[b] - v[a[row]]
        rel_t = _wrap(np.arctan2(t_dir[:, 1], t_dir[:, 0]) - base[row])
        ok = ((rel_t >= cone_lo - ANGLE_SLACK) & (rel_t <= cone_hi + ANGLE_SLACK)
              & (cone_lo <= cone_hi))
        _record(found_a, found_b, found_ok, a[row], b, None, ok)
        lo[active], hi[active] = lo_w[:, -1], hi_w[:, -1]
        done = (lo_w[:, -1] > hi_w[:, -1]) | (s + j0 + window >= stop[active])
        active = active[~done]
        j0 += window
    return _rows_of(rows, np.concatenate(found_a), np.concatenate(found_b),
                    np.concatenate(found_ok))


def _ranges(begin: IntArray, end: IntArray) -> tuple[IntArray, IntArray]:
    """(row, value) for every value in [begin[row], end[row])."""
    counts = np.maximum(end - begin, 0)
    row = np.repeat(np.arange(len(begin)), counts)
    offset = np.arange(len(row)) - np.repeat(np.cumsum(counts) - counts, counts)
    return row, begin[row] + offset


def _record(found_a, found_b, found_ok, a, b_or_begin, end, ok) -> None:
    if end is not None:  # a range of targets, all feasible
        row, b = _ranges(b_or_begin, end)
        a, ok = a[row], np.ones(len(row), dtype=bool)
    else:
        b = b_or_begin
    found_a.append(a)
    found_b.append(b)
    found_ok.append(ok)


def _rows_of(rows: IntArray, a: IntArray, b: IntArray, ok: np.ndarray) -> list[np.ndarray]:
    """Per starting vertex, the boolean array over its targets a+1 .. (up to the last found)."""
    length = np.zeros(int(rows.max(initial=-1)) + 1, dtype=np.intp)
    np.maximum.at(length, a, b - a)
    out = [np.zeros(length[r], dtype=bool) for r in rows]
    order = np.argsort(a, kind="stable")
    a, b, ok = a[order], b[order], ok[order]
    bounds = np.searchsorted(a, np.append(rows, rows[-1] + 1) if len(rows) else [0])
    for i, r in enumerate(rows):
        sel = slice(bounds[i], bounds[i + 1])
        out[i][b[sel] - r - 1] = ok[sel]
    return out


def shortest_path(feasible: list[np.ndarray], start: int, end: int, min_edges: int = 1,
                  chords: tuple[np.ndarray, IntArray] | None = None) -> IntArray:
    """Fewest-edge path from ``start`` to ``end`` over the feasible chords (forward only).

    ``min_edges`` forbids shorter paths (a closed polygon needs 3 edges even when the whole
    contour is within the tolerance of one point). ``chords``: ``feasible`` already laid out
    flat (`flat_chords`), when many paths are searched over the same chords. The search is
    the compiled `wavepoly.kernels.fewest_edges`.
    """
    if not 0 <= start <= end < len(feasible):  # the compiled search checks no bounds
        raise ValueError(f"path from {start} to {end} over {len(feasible)} vertices")
    flat, offset = flat_chords(feasible) if chords is None else chords
    path = fewest_edges(flat, offset, start, end, min_edges)
    if not len(path):
        raise RuntimeError("internal error: no feasible path through the polygon")
    return path.astype(np.intp)


def flat_chords(feasible: list[np.ndarray]) -> tuple[np.ndarray, IntArray]:
    """The per-vertex chord arrays as one boolean array and each vertex's offset into it
    (one more offset than vertices)."""
    offset = np.zeros(len(feasible) + 1, dtype=np.int64)
    np.cumsum([len(f) for f in feasible], out=offset[1:])
    flat = np.concatenate(feasible) if feasible else np.zeros(0, dtype=bool)
    return flat.astype(bool, copy=False), offset


def _shortest_path_reference(feasible: list[np.ndarray], start: int, end: int,
                             min_edges: int = 1) -> IntArray:
    """`shortest_path` in NumPy, one vertex at a time: the reference of the compiled
    `wavepoly.kernels.fewest_edges`, for the tests."""
    big = np.iinfo(np.int64).max // 4
    count = np.full(end + 1, big)
    parent = np.full(end + 1, -1)
    layer_parent = []  # vertices reached with exactly j <= min_edges edges, and their parents
    reached = np.array([start])
    for _ in range(min_edges):
        par = np.full(end + 1, -1)
        for a in reached:
            b = a + 1 + np.flatnonzero(feasible[a][: end - a])
            par[b[par[b] < 0]] = a
        layer_parent.append(par)
        reached = np.flatnonzero(par >= 0)
    count[reached] = len(layer_parent)
    for a in range(int(reached.min(initial=end)), end):
        if count[a] >= big:
            continue
        ok = feasible[a]
        b = a + 1 + np.flatnonzero(ok[: end - a])
        better = count[a] + 1 < count[b]
        count[b[better]] = count[a] + 1
        parent[b[better]] = a
    if count[end] >= big:
        raise RuntimeError("internal error: no feasible path through the polygon")
    path = [end]
    while parent[path[-1]] >= 0:
        path.append(int(parent[path[-1]]))
    for par in layer_parent[::-1]:
        path.append(int(par[path[-1]]))
    return np.array(path[::-1], dtype=np.intp)
