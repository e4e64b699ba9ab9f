"""Reconstruction, coarse to fine (paper §4, eq. 8-11): verified, with the fewest vertices.

Starting at the coarsest level of a `Pyramid`, runs of storable coefficients (eq. 8-9) become
multi-storable coefficients (MSCs) kept in a global dynamic list (GDL); the data points they
approximate are deleted from the working set (eq. 10). The next level is synthesized (eq. 11);
coefficients inside an MSC found at a coarser level (the "updated MSC") are not searched again,
the rest go through the same extraction, until no data point is left or the finest level is done.

Every coefficient sits at a curve parameter (its Greville abscissa, `wavelets.greville`), and
every data point gets the parameter of its projection on the finest control polygon
(`wavepoly.parameters`), so "inside an MSC", "between two MSCs" and "the edge that stands for a
point" are comparisons of numbers.

The polygon is then made honest: every data point of the contour is measured against the edge
that stands for it (which bounds its distance to the polygon), and wherever the tolerance
breaks, the finest-level point (or, failing that, the data point itself) that restores it is
inserted. Finally the fewest of those vertices and the ordered points that keep every point within
the tolerance are chosen (`wavepoly.simplify.select_vertices`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from scipy.spatial import cKDTree

from . import wavelets
from .geometry import curve_line, nearest_site, polyline_distance, segment_distance, true_runs
from .kernels import neighbour_distances
from .parameters import (
    hull_groups,
    raw_parameters,
    sorted_by_parameter,
    split_groups,
    vertex_parameters,
)
from .simplify import edge_of, own_edge_distance, select_vertices
from .types import SLACK, FloatArray, IntArray, Msc, Pyramid, Reconstruction
from .validity import obstacle_hits

#: Parameter round-off allowed at an MSC's ends (parameters live in [0, 1]).
MSC_END_SLACK = 1e-12
#: An ordered point this close to a vertex is that vertex (not a new candidate).
SAME_POINT = 1e-12
#: Fewest storable coefficients in a run that makes an MSC (two ends and two inner ones, §4.1).
MIN_RUN = 4
#: Farthest a vertex may lie from the ordered curve, in tolerances: the tolerance then binds
#: both ways (every point near the polygon, and the polygon near the points). A coarse
#: B-spline's control points stand outside the curve where it turns sharply (a blade's
#: trailing edge), and such a point, kept as a vertex, would put a spike beyond the shape.
MAX_VERTEX_OFFSET = 1.0
#: Data points per ordered point from which a contour's points are grouped between parameters
#: and thinned to their hull candidates for the selection (`reconstruct_contour`): below it the
#: groups are too small for that to pay for itself.
DENSE_SAMPLING = 8

# ---------------------------------------------------------------------------------------------
# MSC extraction (§4.1 at the coarsest level, §4.2 at finer levels)


def _neighbour_distances(points: FloatArray, owner: IntArray, coeffs: FloatArray, closed: bool
                         ) -> tuple[FloatArray, FloatArray]:
    """Distance of each point to the segments before and after its coefficient (inf if none):
    the NumPy reference of `wavepoly.kernels.neighbour_distances`, for the tests."""
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
    _, owner = nearest_site(points, coeffs)
    d_prev, d_next = neighbour_distances(np.ascontiguousarray(points), owner,
                                         np.ascontiguousarray(coeffs), closed)
    bad = np.minimum(d_prev, d_next) > tolerance * (1 + SLACK)
    return np.bincount(owner, weights=bad, minlength=len(coeffs)) == 0, owner


def storable_runs(candidate: np.ndarray, closed: bool, min_run: int = MIN_RUN) -> list[IntArray]:
    """Index runs of at least ``min_run`` consecutive True values (cyclic when ``closed``)."""
    return true_runs(candidate, closed, min_run)


def _inside(u: FloatArray, mscs: list[Msc], closed: bool) -> np.ndarray:
    """Which parameters fall within some MSC's interval (the updated MSCs, §4.2)."""
    mask = np.zeros(len(u), dtype=bool)
    for msc in mscs:
        if closed:
            mask |= np.mod(u - msc.start, 1.0) <= msc.span + MSC_END_SLACK
        else:
            mask |= ((u >= msc.start - MSC_END_SLACK)
                     & (u <= msc.start + msc.span + MSC_END_SLACK))
    return mask


def extract_mscs(points: FloatArray, coeffs: FloatArray, level: int, closed: bool,
                 tolerance: float, gdl: list[Msc]) -> tuple[list[Msc], np.ndarray]:
    """One level of §4: new MSCs between the updated ones (those of ``gdl``), and which of the
    live data ``points`` they cover (eq. 10: to be deleted from the working set)."""
    u = wavelets.greville(level, closed)
    searchable = ~_inside(u, gdl, closed)
    storable, owner = storable_mask(points, coeffs, closed, tolerance)
    new: list[Msc] = []
    run_id = np.full(len(coeffs), -1)
    for run in storable_runs(storable & searchable, closed):
        inner = run if len(run) == len(coeffs) else run[1:-1]  # a whole ring keeps all
        run_id[inner] = len(new)
        span = 1.0 if len(inner) == len(coeffs) else (
            np.mod(u[inner[-1]] - u[inner[0]], 1.0) if closed else u[inner[-1]] - u[inner[0]])
        new.append(Msc(level, int(inner[0]), int(inner[-1]), float(u[inner[0]]), float(span),
                       coeffs[inner], u[inner]))
    covered = np.zeros(len(points), dtype=bool)
    if new and len(points):
        covered = _covered(points, owner, coeffs, run_id, closed, tolerance)
    return new, covered


def _covered(points: FloatArray, owner: IntArray, coeffs: FloatArray, run_id: IntArray,
             closed: bool, tolerance: float) -> np.ndarray:
    """Eq. 10: the points of an MSC's coefficients within tolerance of its segments."""
    m = len(coeffs)
    in_run = run_id[owner] >= 0
    pts, own = points[in_run], owner[in_run]
    d_prev, d_next = neighbour_distances(np.ascontiguousarray(pts), own,
                                         np.ascontiguousarray(coeffs), closed)
    prev = (own - 1) % m if closed else np.maximum(own - 1, 0)
    nxt = (own + 1) % m if closed else np.minimum(own + 1, m - 1)
    same_prev = (run_id[prev] == run_id[own]) & (prev != own)
    same_next = (run_id[nxt] == run_id[own]) & (nxt != own)
    d = np.minimum(np.where(same_prev, d_prev, np.inf), np.where(same_next, d_next, np.inf))
    covered = np.zeros(len(points), dtype=bool)
    covered[np.flatnonzero(in_run)[d <= tolerance * (1 + SLACK)]] = True
    return covered


# ---------------------------------------------------------------------------------------------
# assembly, verification and repair, fewest-vertex selection


def reconstruct_contour(pyramid: Pyramid, ordered: FloatArray, points: FloatArray,
                        tolerance: float, start_level: int | None = None,
                        obstacles: shapely.STRtree | None = None, simple_backbone: bool = False
                        ) -> Reconstruction:
    """The concise polygon of one contour (§4), verified against its data ``points``.

    Parameters
    ----------
    pyramid : the wavelet levels of the contour (`wavepoly.levels.decompose_contour`).
    ordered : (k, 2) ordered points of the contour (the finest level's own points).
    points : (n, 2) original data points of the contour.
    tolerance : shape tolerance; every point ends within it of the polygon.
    start_level : level to start extracting from (default: the pyramid's coarsest).
    obstacles : edges of the contours already fixed nearby, which the polygon must not meet
        (`wavepoly.simplify.select_vertices`). On a clean scan, where the repaired wavelet
        polygon meets them and the ordered points do not, the repaired ordered points are the
        backbone.
    simple_backbone : keep the polygon simple where the ordered points are (a clean scan's):
        the selection never forbids its backbone's edges, so where the repaired wavelet polygon
        crosses itself (the walls of a slit closer than the tolerance) the repaired ordered
        points are the backbone, and where the selection still ends on a crossing, the
        backbone is the result. On a noisy scan the ordered points zigzag through the band
        (the Freiburg map's teeth rose from 227 to 321); there a crossing is split instead
        (`wavepoly.fit`).

    Notes
    -----
    On a dense contour (`DENSE_SAMPLING`) the points are labelled once by the run between two
    consecutive parameters of any level's coefficients or ordered points that holds them, and
    only those that may be convex-hull vertices of their run (`geometry.group_hull_candidates`)
    go to the fewest-vertex selection, with the whole runs that a candidate splits. The cone
    test's distances are convex in the point, so the selection is the same as over all the
    points, for a fraction of the work; the labels also sort the points (`untie`).
    """
    closed = pyramid.closed
    level = pyramid.coarsest if start_level is None else start_level
    raw, step = raw_parameters(points, pyramid)
    fine_u = wavelets.greville(pyramid.finest, closed)[pyramid.fine_index]
    dense = len(points) >= DENSE_SAMPLING * len(ordered)
    # in parameter order from here on (the result holds no per-point arrays): the sorts and
    # searches of the selection then run over sorted data
    if dense:
        cuts = np.unique(vertex_parameters(pyramid, fine_u))
        group, keep = hull_groups(points, raw, pyramid, cuts)
        by_param, params = sorted_by_parameter(raw, step, closed, group)
        group, keep = group[by_param], keep[by_param]
    else:
        by_param, params = sorted_by_parameter(raw, step, closed)
    points = points[by_param]
    live = np.arange(len(points))  # the working set of data points (eq. 10 deletes from it)
    gdl: list[Msc] = []
    coeffs = pyramid.coefficients[level]
    while True:
        new, covered = extract_mscs(points[live], coeffs, level, closed, tolerance, gdl)
        gdl, live = gdl + new, live[~covered]
        if not len(live) or level == pyramid.finest:
            break
        coeffs = wavelets.synthesize(coeffs, pyramid.details[level], closed)  # eq. 11
        level += 1
    contour = _ContourData(points, params, ordered, fine_u, closed, tolerance)
    vertices, vparams = _assemble(gdl, ordered, fine_u, params[live], closed)
    vertices, vparams = _near_curve(vertices, vparams, contour)
    vertices, vparams = _repair(contour, vertices, vparams)
    n_wavelet = len(vertices)
    vertices, vparams = _valid_backbone(contour, vertices, vparams, obstacles, simple_backbone)
    simple = simple_backbone and _simple(vertices, closed)
    # the ordered points join the candidates, so the choice is never worse than the best
    # subset of ordered points; the wavelet coefficients add smoothed candidates to it
    # (an ordered point at a vertex's parameter is still new unless it is that very vertex)
    gap, _ = cKDTree(vertices).query(ordered, distance_upper_bound=SAME_POINT)
    extra = ~(np.isfinite(gap) & np.isin(fine_u, vparams))
    cand = np.vstack([vertices, ordered[extra]])
    cand_u = np.concatenate([vparams, fine_u[extra]])
    order = np.argsort(np.mod(cand_u, 1.0) if closed else cand_u, kind="stable")
    backbone = np.flatnonzero(order < len(vertices))  # the repaired, verified polygon
    hull = points, params
    if dense:  # with the groups that a candidate splits, whole
        sel = keep | split_groups(cuts, cand_u, closed)[group]
        hull = points[sel], params[sel]
    chosen, chosen_u = select_vertices(cand[order], cand_u[order], *hull, closed, tolerance,
                                       backbone=backbone, obstacles=obstacles)
    # the cone test is exact up to rounding; the repaired polygon stays the fallback (and, for
    # a simple backbone, where the selection's rounds ended on a crossing)
    crossing = simple and not _simple(chosen, closed)
    if own_edge_distance(chosen, chosen_u, points, params, closed).max(initial=0.0) <= (
            tolerance * (1 + SLACK)) and not crossing:
        vertices, vparams = chosen, chosen_u
    dist = polyline_distance(points, vertices, closed and len(vertices) >= 3)
    return Reconstruction(vertices, vparams, closed, gdl,
                          pyramid.coarsest if start_level is None else start_level, n_wavelet,
                          float(dist.max(initial=0.0)), float(dist.mean()) if len(dist) else 0.0)


def _valid_backbone(c: _ContourData, vertices: FloatArray, vparams: FloatArray,
                    obstacles: shapely.STRtree | None, simple_backbone: bool
                    ) -> tuple[FloatArray, FloatArray]:
    """The repaired polygon the selection may always fall back on: the wavelet one, or, with
    ``simple_backbone`` (a clean scan), the repaired ordered points where those are more
    valid. Simplicity (the walls of a slit closer than the tolerance make the wavelet polygon
    cross itself) comes first, then being clear of the ``obstacles`` (where two rings nearly
    touch, the wavelet polygon may cut a corner across the other's edges). On a noisy scan
    the ordered points zigzag through the band, and a crossing is split instead."""
    def problems(xy: FloatArray) -> tuple[bool, bool]:
        return (not _simple(xy, c.closed),
                obstacles is not None and bool(obstacle_hits(xy, c.closed, obstacles).any()))

    if not simple_backbone:
        return vertices, vparams
    now = problems(vertices)
    if not any(now) or problems(c.ordered) >= now:
        return vertices, vparams
    again, again_u = _repair(c, c.ordered, c.fine_u)
    return (again, again_u) if problems(again) < now else (vertices, vparams)


def _simple(xy: FloatArray, closed: bool) -> bool:
    return bool(curve_line(xy, closed).is_simple)


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


def _near_curve(vertices: FloatArray, vparams: FloatArray, c: _ContourData
                ) -> tuple[FloatArray, FloatArray]:
    """The vertices within `MAX_VERTEX_OFFSET` tolerances of the ordered curve (the repair
    then restores the tolerance where one was dropped); the ordered points when too few are
    left for a polygon."""
    if len(c.ordered) < 2:
        return vertices, vparams
    near = polyline_distance(vertices, c.ordered, c.closed) <= (
        MAX_VERTEX_OFFSET * c.tolerance * (1 + SLACK))
    if near.all():
        return vertices, vparams
    if not c.closed:  # the ends interpolate the curve's ends
        near[[0, -1]] = True
    if near.sum() < (3 if c.closed else 2):
        return c.ordered.copy(), c.fine_u.copy()
    return vertices[near], vparams[near]


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


@dataclass(frozen=True)
class _ContourData:
    """What the repair measures against: the data points and the ordered points of one
    contour, each with its curve parameter, and the tolerance."""

    points: FloatArray
    params: FloatArray
    ordered: FloatArray
    fine_u: FloatArray
    closed: bool
    tolerance: float


def _repair(c: _ContourData, vertices: FloatArray, vparams: FloatArray
            ) -> tuple[FloatArray, FloatArray]:
    """Insert finest-level points (or the data points themselves) until all are within tolerance.

    Each round inserts, into every edge that one of its points is farther than the tolerance
    from, the ordered point between the edge's ends that is farthest from it; an edge with no
    ordered point inside gets its worst data point. Points inserted as vertices are at distance
    0, so this ends.
    """
    limit = c.tolerance * (1 + SLACK)
    dist = own_edge_distance(vertices, vparams, c.points, c.params, c.closed)
    for _ in range(len(c.points) + len(c.ordered) + 1):
        bad = dist > limit
        if not bad.any():
            break
        edges = np.unique(edge_of(vparams, c.params[bad], c.closed))
        key = np.mod(vparams, 1.0) if c.closed else vparams
        held = [_edge_points(c.params, key, e, c.closed) for e in edges]
        new_v, new_u = [], []
        for e, idx in zip(edges, held):
            v, u = _split_point(c, e, vertices, vparams, dist, bad, idx)
            new_v.append(v)
            new_u.append(u)
        vertices = np.vstack([vertices, new_v])
        vparams = np.concatenate([vparams, new_u])
        order = np.argsort(np.mod(vparams, 1.0) if c.closed else vparams, kind="stable")
        vertices, vparams = vertices[order], vparams[order]
        # only the points of the split edges have new edges; the others keep their distances
        idx = np.concatenate(held)
        dist[idx] = own_edge_distance(vertices, vparams, c.points[idx], c.params[idx], c.closed)
    return vertices, vparams


def _edge_points(params: FloatArray, key: FloatArray, e: int, closed: bool) -> IntArray:
    """Indices (increasing) of the points whose own edge is ``e`` (as `simplify.edge_of`
    assigns them), for ``params`` sorted (in [0, 1) on a closed contour) and the vertices'
    sorted parameters ``key`` (taken modulo 1 on a closed contour)."""
    k = len(key)
    n = len(params)
    if closed and e == k - 1:  # the edge over the seam
        head = np.arange(np.searchsorted(params, key[0], "left"))
        return np.concatenate([head, np.arange(np.searchsorted(params, key[-1], "left"), n)])
    lo = 0 if e == 0 and not closed else np.searchsorted(params, key[e], "left")
    hi = n if e == k - 2 and not closed else np.searchsorted(params, key[e + 1], "left")
    return np.arange(lo, hi)


def _split_point(c: _ContourData, e: int, vertices: FloatArray, vparams: FloatArray,
                 dist: FloatArray, bad: np.ndarray, held: IntArray) -> tuple[FloatArray, float]:
    """The point to insert into edge ``e``: the farthest ordered point inside it, else its
    farthest data point beyond the tolerance (of those it ``held``)."""
    k = len(vertices)
    a, b = vparams[e], vparams[(e + 1) % k]
    if c.closed:
        span = np.mod(b - a, 1.0) or 1.0
        inside = (np.mod(c.fine_u - a, 1.0) > 0) & (np.mod(c.fine_u - a, 1.0) < span)
    else:
        inside = (c.fine_u > a) & (c.fine_u < b)
    cand = np.flatnonzero(inside)
    if len(cand):
        d = segment_distance(c.ordered[cand], vertices[e], vertices[(e + 1) % k])
        if d.max() > 0:
            j = cand[np.argmax(d)]
            return c.ordered[j], c.fine_u[j]
    in_edge = held[bad[held]]
    j = in_edge[np.argmax(dist[in_edge])]
    return c.points[j], c.params[j]
