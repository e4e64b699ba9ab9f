"""Reconstruction, coarse to fine (paper §4, eq. 8-11): verified, with the fewest vertices.

Starting at the coarsest level of a `Pyramid`, runs of storable coefficients (eq. 8-9) become
multi-storable coefficients (MSCs) kept in a global dynamic list (GDL); the data points they
approximate are deleted from the working set (eq. 10). The next level is synthesized (eq. 11);
coefficients inside an MSC found at a coarser level (the "updated MSC") are not searched again,
the rest go through the same extraction, until no data point is left or the finest level is done.

Every coefficient sits at a curve parameter (its Greville abscissa, `wavelets.greville`), and
every data point gets the parameter of its projection on the finest control polygon, so "inside
an MSC", "between two MSCs" and "the edge that stands for a point" are comparisons of numbers.

The polygon is then made honest: every data point of the contour is measured against the edge
that stands for it (which bounds its distance to the polygon), and wherever the tolerance
breaks, the finest-level point (or, failing that, the data point itself) that restores it is
inserted. Finally the fewest of those vertices that keep every point within the tolerance are
chosen (a shortest path over feasible chords, `select_vertices`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import maximum_filter1d
from scipy.spatial import cKDTree

from . import wavelets
from .geometry import hull_candidates, nearest_segment, polyline_distance, segment_distance
from .levels import Pyramid
from .types import FloatArray, IntArray

#: Relative slack on the tolerance for floating-point round-off in distance computations.
SLACK = 1e-9


@dataclass(frozen=True)
class Msc:
    """A multi-storable coefficient run: inner coefficients ``first..last`` of ``level``.

    start / span: parameter interval covered (span may wrap past 1 on a closed contour).
    """

    level: int
    first: int
    last: int
    start: float
    span: float
    points: FloatArray
    params: FloatArray


@dataclass(frozen=True)
class Reconstruction:
    """The polygon of one contour and how it was made."""

    vertices: FloatArray
    params: FloatArray
    closed: bool
    mscs: list[Msc]
    start_level: int
    wavelet_vertices: int  # after MSC assembly and repair, before the selection
    max_error: float
    mean_error: float

    @property
    def mscs_per_level(self) -> dict[int, int]:
        out: dict[int, int] = {}
        for m in self.mscs:
            out[m.level] = out.get(m.level, 0) + 1
        return out


def point_parameters(points: FloatArray, pyramid: Pyramid) -> FloatArray:
    """Curve parameter of each data point: its projection on the finest control polygon.

    Points outside a corner all project onto the corner; they are told apart by direction
    (those towards the outgoing edge get a slightly larger parameter), so that an inserted
    vertex can always separate them. On an open contour, the parameters of points beyond an end
    continue along its end segments.
    """
    cp = pyramid.coefficients[pyramid.finest]
    u = wavelets.greville(pyramid.finest, pyramid.closed)
    if pyramid.closed:
        cp, u = np.vstack([cp, cp[:1]]), np.append(u, 1.0)
    length = np.linalg.norm(np.diff(cp, axis=0), axis=1)
    arc = np.concatenate([[0.0], np.cumsum(length)])
    s = _locate(points, cp, arc)
    param = np.interp(s, arc, u)
    delta = 1e-9 * float(np.diff(u).min(initial=1.0))
    at = np.clip(np.searchsorted(arc, s), 0, len(arc) - 1)
    near = np.abs(arc[at] - s) <= 1e-12 * arc[-1]
    m = len(arc) - 1  # segments; on a closed contour vertex m is vertex 0 again
    inner = near if pyramid.closed else near & (at > 0) & (at < m)
    if inner.any():
        i = at[inner] % m if pyramid.closed else at[inner]
        prev, nxt = (i - 1) % m, i + 1
        d_in = _unit(cp[i] - cp[prev])
        d_out = _unit(cp[nxt] - cp[i])
        w = _unit(points[inner] - cp[i])
        key = np.einsum("ij,ij->i", w, d_in + d_out)  # -1 by the incoming edge, +1 by the next
        param[inner] = u[i] + 0.25 * key * delta
    param = _untie(param, 1e-3 * delta)
    if pyramid.closed:
        return np.mod(param, 1.0)
    # beyond an end of an open contour: the parameter continues along the end segment, so that
    # the repair can extend the polyline to such points
    for end, nxt in ((0, 1), (m, m - 1)):
        out = near & (at == end)
        if out.any():
            seg = cp[end] - cp[nxt]
            t = (points[out] - cp[end]) @ seg / max(float(seg @ seg), 1e-300)
            gap = np.linalg.norm(points[out] - cp[end], axis=1) / np.sqrt(max(float(seg @ seg),
                                                                                1e-300))
            # strictly beyond the end vertex, so that an inserted point has its own parameter
            param[out] = u[end] + (np.maximum(t, 0.0) + delta * (1 + gap)) * (u[end] - u[nxt])
    return param


def _locate(points: FloatArray, line: FloatArray, arc: FloatArray) -> FloatArray:
    """Arc length along the open polyline ``line`` of each point's nearest point on it.

    Like shapely's ``line_locate_point``, but O((n + m) log m) (`nearest_segment`); a point
    whose nearest point is a vertex gets exactly that vertex's ``arc`` value.
    """
    seg, _ = nearest_segment(points, line, False)
    a, ab = line[seg], line[seg + 1] - line[seg]
    denom = np.einsum("ij,ij->i", ab, ab)
    t = np.einsum("ij,ij->i", points - a, ab) / np.where(denom > 0, denom, 1.0)
    s = arc[seg] + np.clip(t, 0.0, 1.0) * (arc[seg + 1] - arc[seg])
    s[t >= 1.0] = arc[seg[t >= 1.0] + 1]
    return s


def _untie(param: FloatArray, step: float) -> FloatArray:
    """Equal parameters spread by ``step`` (in input order): with every point's parameter its
    own, a point inserted as a vertex starts the edge that holds it, so the repair ends."""
    order = np.argsort(param, kind="stable")
    p = param[order]
    new_group = np.concatenate([[True], p[1:] != p[:-1]])
    start = np.maximum.accumulate(np.where(new_group, np.arange(len(p)), 0))
    out = param.copy()
    out[order] = p + (np.arange(len(p)) - start) * step
    return out


def _unit(v: FloatArray) -> FloatArray:
    n = np.linalg.norm(v, axis=1, keepdims=True)
    return v / np.where(n > 0, n, 1.0)


# ---------------------------------------------------------------------------------------------
# MSC extraction (§4.1 at the coarsest level, §4.2 at finer levels)


def _neighbour_distances(points: FloatArray, owner: IntArray, coeffs: FloatArray, closed: bool
                         ) -> tuple[FloatArray, FloatArray]:
    """Distance of each point to the segments before and after its coefficient (inf if none)."""
    m = len(coeffs)
    prev = owner - 1
    nxt = owner + 1
    if closed:
        prev, nxt = prev % m, nxt % m
    d_prev = np.full(len(points), np.inf)
    d_next = np.full(len(points), np.inf)
    ok_prev = prev >= 0
    ok_next = nxt < m
    d_prev[ok_prev] = segment_distance(points[ok_prev], coeffs[prev[ok_prev]],
                                       coeffs[owner[ok_prev]])
    d_next[ok_next] = segment_distance(points[ok_next], coeffs[owner[ok_next]],
                                       coeffs[nxt[ok_next]])
    return d_prev, d_next


def storable_mask(points: FloatArray, coeffs: FloatArray, closed: bool, tolerance: float
                  ) -> tuple[np.ndarray, IntArray]:
    """Eq. 8-9: which coefficients are storable, and the nearest coefficient of each point.

    A coefficient is storable when every data point nearest to it (eq. 9) lies within
    ``tolerance`` of the nearer of its two adjacent segments (eq. 8). A coefficient with no
    points is storable.
    """
    if len(points) == 0:
        return np.ones(len(coeffs), dtype=bool), np.empty(0, dtype=np.intp)
    _, owner = cKDTree(coeffs).query(points)
    d_prev, d_next = _neighbour_distances(points, owner, coeffs, closed)
    bad = np.minimum(d_prev, d_next) > tolerance * (1 + SLACK)
    return np.bincount(owner, weights=bad, minlength=len(coeffs)) == 0, owner


def storable_runs(candidate: np.ndarray, closed: bool, min_run: int = 4) -> list[IntArray]:
    """Index runs of at least ``min_run`` consecutive True values (cyclic when ``closed``)."""
    m = len(candidate)
    if closed and candidate.all():
        return [np.arange(m)]
    shift = 0
    if closed:  # start the scan just after a False so that no run wraps
        shift = int(np.flatnonzero(~candidate)[-1]) + 1
    rolled = np.roll(candidate, -shift)
    edges = np.diff(np.concatenate([[0], rolled.astype(np.int8), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    return [(np.arange(s, e) + shift) % m for s, e in zip(starts, ends) if e - s >= min_run]


def _inside(u: FloatArray, mscs: list[Msc], closed: bool) -> np.ndarray:
    """Which parameters fall within some MSC's interval (the updated MSCs, §4.2)."""
    mask = np.zeros(len(u), dtype=bool)
    for msc in mscs:
        if closed:
            mask |= np.mod(u - msc.start, 1.0) <= msc.span + 1e-12
        else:
            mask |= (u >= msc.start - 1e-12) & (u <= msc.start + msc.span + 1e-12)
    return mask


def extract_mscs(points: FloatArray, alive: np.ndarray, coeffs: FloatArray, level: int,
                 closed: bool, tolerance: float, gdl: list[Msc]) -> list[Msc]:
    """One level of §4: new MSCs between the updated ones, and eq. 10 deletions in ``alive``."""
    u = wavelets.greville(level, closed)
    searchable = ~_inside(u, gdl, closed)
    idx_alive = np.flatnonzero(alive)
    storable, owner = storable_mask(points[idx_alive], coeffs, closed, tolerance)
    new: list[Msc] = []
    run_id = np.full(len(coeffs), -1)
    for run in storable_runs(storable & searchable, closed):
        inner = run if len(run) == len(coeffs) else run[1:-1]  # a whole ring keeps all
        run_id[inner] = len(new)
        span = 1.0 if len(inner) == len(coeffs) else (
            np.mod(u[inner[-1]] - u[inner[0]], 1.0) if closed else u[inner[-1]] - u[inner[0]])
        new.append(Msc(level, int(inner[0]), int(inner[-1]), float(u[inner[0]]), float(span),
                       coeffs[inner], u[inner]))
    if new and len(idx_alive):
        _delete_covered(points, idx_alive, owner, coeffs, run_id, closed, tolerance, alive)
    return new


def _delete_covered(points, idx_alive, owner, coeffs, run_id, closed, tolerance, alive):
    """Eq. 10: delete the points of an MSC's coefficients within tolerance of its segments."""
    m = len(coeffs)
    in_run = run_id[owner] >= 0
    pts, own = points[idx_alive[in_run]], owner[in_run]
    d_prev, d_next = _neighbour_distances(pts, own, coeffs, closed)
    prev = (own - 1) % m if closed else np.maximum(own - 1, 0)
    nxt = (own + 1) % m if closed else np.minimum(own + 1, m - 1)
    same_prev = (run_id[prev] == run_id[own]) & (prev != own)
    same_next = (run_id[nxt] == run_id[own]) & (nxt != own)
    d = np.minimum(np.where(same_prev, d_prev, np.inf), np.where(same_next, d_next, np.inf))
    alive[idx_alive[in_run][d <= tolerance * (1 + SLACK)]] = False


# ---------------------------------------------------------------------------------------------
# assembly, verification and repair, fewest-vertex selection


def reconstruct_contour(pyramid: Pyramid, ordered: FloatArray, points: FloatArray,
                        tolerance: float, start_level: int | None = None) -> Reconstruction:
    """The concise polygon of one contour (§4), verified against its data ``points``.

    Parameters
    ----------
    pyramid : the wavelet levels of the contour (`wavepoly.levels.decompose_contour`).
    ordered : (k, 2) ordered points of the contour (the finest level's own points).
    points : (n, 2) original data points of the contour.
    tolerance : shape tolerance; every point ends within it of the polygon.
    start_level : level to start extracting from (default: the pyramid's coarsest).
    """
    closed = pyramid.closed
    level = pyramid.coarsest if start_level is None else start_level
    params = point_parameters(points, pyramid)
    alive = np.ones(len(points), dtype=bool)
    gdl: list[Msc] = []
    coeffs = pyramid.coefficients[level]
    while True:
        gdl += extract_mscs(points, alive, coeffs, level, closed, tolerance, gdl)
        if not alive.any() or level == pyramid.finest:
            break
        coeffs = wavelets.synthesize(coeffs, pyramid.details[level], closed)  # eq. 11
        level += 1
    fine_u = wavelets.greville(pyramid.finest, closed)[pyramid.fine_index]
    vertices, vparams = _assemble(gdl, ordered, fine_u, params[alive], closed)
    vertices, vparams = _repair(vertices, vparams, ordered, fine_u, points, params, closed,
                                tolerance)
    n_wavelet = len(vertices)
    # the ordered points join the candidates, so the choice is never worse than the best
    # subset of ordered points; the wavelet coefficients add smoothed candidates to it
    # (an ordered point at a vertex's parameter is still new unless it is that very vertex)
    gap, _ = cKDTree(vertices).query(ordered, distance_upper_bound=1e-12)
    extra = ~(np.isfinite(gap) & np.isin(fine_u, vparams))
    cand = np.vstack([vertices, ordered[extra]])
    cand_u = np.concatenate([vparams, fine_u[extra]])
    order = np.argsort(np.mod(cand_u, 1.0) if closed else cand_u, kind="stable")
    backbone = np.flatnonzero(order < len(vertices))  # the repaired, verified polygon
    chosen, chosen_u = select_vertices(cand[order], cand_u[order], points, params, closed,
                                       tolerance, backbone=backbone)
    # the cone test is exact up to rounding; the repaired polygon stays the fallback
    if own_edge_distance(chosen, chosen_u, points, params, closed).max(initial=0.0) <= (
            tolerance * (1 + SLACK)):
        vertices, vparams = chosen, chosen_u
    dist = polyline_distance(points, vertices, closed and len(vertices) >= 3)
    return Reconstruction(vertices, vparams, closed, gdl,
                          pyramid.coarsest if start_level is None else start_level, n_wavelet,
                          float(dist.max(initial=0.0)), float(dist.mean()) if len(dist) else 0.0)


def _assemble(gdl: list[Msc], ordered: FloatArray, fine_u: FloatArray, alive_u: FloatArray,
              closed: bool) -> tuple[FloatArray, FloatArray]:
    """MSC coefficients in parameter order; finest-level points fill gaps that still hold data."""
    if not gdl:
        return ordered.copy(), fine_u.copy()
    pts = [m.points for m in gdl]
    us = [m.params for m in gdl]
    fill = ~_inside(fine_u, gdl, closed)
    if closed:
        fill &= _gap_has_data(fine_u, alive_u, gdl)
    else:
        fill &= _gap_has_data(fine_u, alive_u, gdl) | (fine_u <= 0.0) | (fine_u >= 1.0)
    pts.append(ordered[fill])
    us.append(fine_u[fill])
    v, u = np.concatenate(pts), np.concatenate(us)
    order = np.argsort(np.mod(u, 1.0) if closed else u, kind="stable")
    return v[order], u[order]


def _gap_has_data(u: FloatArray, alive_u: FloatArray, gdl: list[Msc]) -> np.ndarray:
    """For each parameter in ``u``: does the gap between MSCs that holds it hold live points?"""
    bounds = np.sort(np.concatenate([[m.start for m in gdl],
                                     [np.mod(m.start + m.span, 1.0) for m in gdl]]))
    gap_of_u = np.searchsorted(bounds, np.mod(u, 1.0))
    gap_of_p = np.searchsorted(bounds, np.mod(alive_u, 1.0))
    live = np.zeros(len(bounds) + 1, dtype=bool)
    live[gap_of_p] = True
    live[0] = live[-1] = live[0] | live[-1]  # the two ends are one gap on a closed contour
    return live[gap_of_u]


def _edge_of(vparams: FloatArray, params: FloatArray, closed: bool) -> IntArray:
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
    e = _edge_of(vparams, params, closed)
    return segment_distance(points, vertices[e], vertices[(e + 1) % len(vertices)])


def _repair(vertices, vparams, ordered, fine_u, points, params, closed, tolerance):
    """Insert finest-level points (or the data points themselves) until all are within tolerance.

    Each round inserts, into every edge that one of its points is farther than the tolerance
    from, the ordered point between the edge's ends that is farthest from it; an edge with no
    ordered point inside gets its worst data point. Points inserted as vertices are at distance
    0, so this ends.
    """
    limit = tolerance * (1 + SLACK)
    for _ in range(len(points) + len(ordered) + 1):
        dist = own_edge_distance(vertices, vparams, points, params, closed)
        bad = dist > limit
        if not bad.any():
            break
        edges = np.unique(_edge_of(vparams, params[bad], closed))
        new_v, new_u = [], []
        for e in edges:
            v, u = _split_point(e, vertices, vparams, ordered, fine_u, points, params, dist,
                                bad, closed)
            new_v.append(v)
            new_u.append(u)
        vertices = np.vstack([vertices, new_v])
        vparams = np.concatenate([vparams, new_u])
        order = np.argsort(np.mod(vparams, 1.0) if closed else vparams, kind="stable")
        vertices, vparams = vertices[order], vparams[order]
    return vertices, vparams


def _split_point(e, vertices, vparams, ordered, fine_u, points, params, dist, bad, closed):
    k = len(vertices)
    a, b = vparams[e], vparams[(e + 1) % k]
    if closed:
        span = np.mod(b - a, 1.0) or 1.0
        inside = (np.mod(fine_u - a, 1.0) > 0) & (np.mod(fine_u - a, 1.0) < span)
    else:
        inside = (fine_u > a) & (fine_u < b)
    cand = np.flatnonzero(inside)
    if len(cand):
        d = segment_distance(ordered[cand], vertices[e], vertices[(e + 1) % k])
        if d.max() > 0:
            j = cand[np.argmax(d)]
            return ordered[j], fine_u[j]
    in_edge = np.flatnonzero(bad & (_edge_of(vparams, params, closed) == e))
    j = in_edge[np.argmax(dist[in_edge])]
    return points[j], params[j]


def select_vertices(vertices: FloatArray, vparams: FloatArray, points: FloatArray,
                    params: FloatArray, closed: bool, tolerance: float,
                    backbone: IntArray | None = None) -> tuple[FloatArray, FloatArray]:
    """The fewest of the polygon's own vertices that keep every point within ``tolerance``.

    A chord from vertex a to vertex b is feasible when every point whose parameter lies between
    theirs is within the tolerance of it (the own-edge invariant of the repair, so the result
    is verified by construction). The shortest path over feasible chords (Imai & Iri) is the
    optimal subset of an open contour. On a closed contour every start in a window that any
    polygon must have a vertex in is tried (`_closed_starts`), and the best is kept.
    """
    k = len(vertices)
    if k <= (3 if closed else 2):
        return vertices, vparams
    if not closed:  # points beyond the ends belong to the end edges (as in `_edge_of`)
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
    feasible = _feasible_chords(vertices2, u, pts, prm, tolerance * (1 + SLACK),
                                max_span=k if closed else k - 1, periodic=closed)
    if backbone is not None and len(backbone) >= 2:
        _allow_backbone(feasible, backbone, k, closed)
    if not closed:
        path = _shortest(feasible, 0, k - 1)
        return vertices[path], vparams[path]
    best = None
    for start in _closed_starts(feasible, k):
        try:
            path = _shortest(feasible, start, start + k, min_edges=3)
        except RuntimeError:  # no polygon has this vertex; another start in the window does
            continue
        if best is None or len(path) < len(best):
            best = path
    if best is None:
        raise RuntimeError("internal error: no feasible polygon")
    keep = np.sort(best[:-1] % k)
    return vertices[keep], vparams[keep]


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


def _allow_backbone(feasible: list[np.ndarray], backbone: IntArray, k: int, closed: bool
                    ) -> None:
    """Mark the edges of an already verified polygon (vertex indices ``backbone``) feasible,
    so that a path always exists; the caller verifies the choice again."""
    a = backbone if not closed else np.concatenate([backbone, backbone + k])
    b = np.roll(a, -1)[:-1]
    a = a[:-1]
    if closed:
        b = np.where(b <= a, b + k, b)
    for x, y in zip(a, b):
        if 0 < y - x < len(feasible) - x:
            if y - x > len(feasible[x]):  # beyond where the cone test stopped
                feasible[x] = np.pad(feasible[x], (0, y - x - len(feasible[x])))
            feasible[x][y - x - 1] = True


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


def _feasible_chords(v: FloatArray, u: FloatArray, pts: FloatArray, prm: FloatArray,
                     limit: float, max_span: int, periodic: bool = False) -> list[np.ndarray]:
    """For each vertex a, a boolean array over b = a+1 .. : is chord (a, b) feasible.

    Chan & Chin's cone test, swept over the points in parameter order: chord (a, b) keeps every
    point between them within ``limit`` exactly when b lies in the cone of directions from a
    that pass within ``limit`` of each of those points, and a in the same cone seen from b.
    The arrays stop at the last b the forward cone reaches (every later chord is infeasible).
    """
    n = len(v)
    k = n // 2 if periodic else n  # the unrolled second turn repeats the first: sweep once
    fwd = _sweep_cones(v, u, pts, prm, np.arange(k), limit, max_span, "left")
    # backwards = forwards on the mirrored contour; the own-edge rule u[a] <= p < u[b] becomes
    # u'[b'] < p' <= u'[a'], hence the other searchsorted side
    bwd = _sweep_cones(v[::-1], -u[::-1], pts[::-1], -prm[::-1], np.arange(k), limit,
                       max_span, "right")[::-1]
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


def _sweep_cones(v: FloatArray, u: FloatArray, pts: FloatArray, prm: FloatArray,
                 rows: IntArray, limit: float, max_span: int, side: str,
                 window: int = 128) -> list[np.ndarray]:
    """ok[a][m]: vertex a+m+1 lies in the cone from vertex a over the points between them.

    All starting vertices sweep together, ``window`` points at a time: the cone from a is the
    intersection, over the points with parameter in [u[a], u[b]) (``side="left"``), of the
    directions that pass within ``limit`` of each point farther than ``limit``. A row stops at
    the window where its cone closes; the targets after it are infeasible and left out.
    """
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
        ok = ((rel_t >= cone_lo - 1e-12) & (rel_t <= cone_hi + 1e-12) & (cone_lo <= cone_hi))
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


def _shortest(feasible: list[np.ndarray], start: int, end: int, min_edges: int = 1) -> IntArray:
    """Fewest-edge path from ``start`` to ``end`` over the feasible chords (forward only).

    ``min_edges`` forbids shorter paths (a closed polygon needs 3 edges even when the whole
    contour is within the tolerance of one point).
    """
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
