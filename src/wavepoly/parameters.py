"""Curve parameters of data points (paper §4): where each point stands along its contour.

Every coefficient of a `Pyramid` sits at a curve parameter (its Greville abscissa,
`wavelets.greville`); every data point gets the parameter of its projection on the finest
control polygon (`raw_parameters`), so that "inside an MSC", "between two MSCs" and "the edge
that stands for a point" are comparisons of numbers. Equal parameters are spread apart
(`untie`), and on a dense contour the points are grouped by the run between two consecutive
parameters a vertex can take (`hull_groups`), which also sorts them in linear time.
"""

from __future__ import annotations

import numpy as np

from . import wavelets
from .geometry import group_hull_candidates, nearest_segment
from .kernels import nearly_uniform_search, order_within_groups
from .types import FloatArray, IntArray, Pyramid

#: Parameters this close (relative to the finest level's spacing) are ties at one vertex.
PARAM_TIE = 1e-9
#: Arc lengths this close (relative to the polyline's length) put a point at a vertex.
AT_VERTEX = 1e-12


def point_parameters(points: FloatArray, pyramid: Pyramid) -> FloatArray:
    """Curve parameter of each data point (`raw_parameters`), ties spread (`untie`)."""
    raw, step = raw_parameters(points, pyramid)
    order, params = sorted_by_parameter(raw, step, pyramid.closed)
    out = np.empty_like(params)
    out[order] = params
    return out


def raw_parameters(points: FloatArray, pyramid: Pyramid) -> tuple[FloatArray, float]:
    """Curve parameter of each data point: its projection on the finest control polygon; and
    the step by which `untie` spreads equal ones.

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
    seg, t = _locate(points, cp)
    param = u[seg] + t * (u[seg + 1] - u[seg])
    delta = PARAM_TIE * float(np.diff(u).min(initial=1.0))
    at = np.where(t > 0, seg + 1, seg)  # the first vertex at or after the point's foot
    near = (t <= 0) | ((1 - t) * length[seg] <= AT_VERTEX * length.sum())
    m = len(cp) - 1  # segments; on a closed contour vertex m is vertex 0 again
    inner = near if pyramid.closed else near & (at > 0) & (at < m)
    if inner.any():
        i = at[inner] % m if pyramid.closed else at[inner]
        prev, nxt = (i - 1) % m, i + 1
        d_in = _unit(cp[i] - cp[prev])
        d_out = _unit(cp[nxt] - cp[i])
        w = _unit(points[inner] - cp[i])
        key = np.einsum("ij,ij->i", w, d_in + d_out)  # -1 by the incoming edge, +1 by the next
        param[inner] = u[i] + 0.25 * key * delta
    if pyramid.closed:
        return np.mod(param, 1.0), 1e-3 * delta
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
    return param, 1e-3 * delta


def _locate(points: FloatArray, line: FloatArray) -> tuple[IntArray, FloatArray]:
    """Each point's nearest segment of the open polyline ``line`` and where its foot lies on
    it, as a fraction in [0, 1] of the segment.

    Like shapely's ``line_locate_point``, but O((n + m) log m) (`nearest_segment`); a point
    whose nearest point is a vertex lies exactly at 0 or 1.
    """
    seg, _ = nearest_segment(points, line, False)
    a, ab = line[seg], line[seg + 1] - line[seg]
    denom = np.einsum("ij,ij->i", ab, ab)
    t = np.einsum("ij,ij->i", points - a, ab) / np.where(denom > 0, denom, 1.0)
    return seg, np.clip(t, 0.0, 1.0)


def untie(sorted_param: FloatArray, step: float) -> FloatArray:
    """Sorted parameters with equal ones spread by ``step`` (in their order), still sorted:
    with every point's parameter its own, a point inserted as a vertex starts the edge that
    holds it, so the repair ends.

    Each parameter becomes at least ``step`` above the one before: a run of k ties spreads
    over (k - 1) ``step`` s and pushes on the parameters it reaches (many duplicate points
    at a corner of a laser map: spread past the next parameter, the run had left the
    parameters unsorted, and the repair's edge search found no point in an edge).

    >>> untie(np.array([0.0, 0.0, 0.0, 1.5e-3, 1.0]), 1e-3)
    array([0.   , 0.001, 0.002, 0.003, 1.   ])
    """
    shift = np.arange(len(sorted_param)) * step
    lowered = sorted_param - shift
    floor = np.maximum.accumulate(lowered)
    return np.where(floor > lowered, floor + shift, sorted_param)  # the others exactly as given


def sorted_by_parameter(raw: FloatArray, step: float, closed: bool,
                        group: IntArray | None = None) -> tuple[IntArray, FloatArray]:
    """The (stable) order that sorts the parameters ``raw`` and the sorted parameters, ties
    spread (`untie`); in [0, 1) when ``closed``. With the points' ``group`` of `hull_groups`
    (which never decreases along the parameter), sorted group by group, in linear time."""
    if group is None:
        order = np.argsort(raw, kind="stable")
    else:
        order = order_within_groups(raw, group, int(group.max()) + 1)
    params = untie(raw[order], step)
    if closed and len(params) and params[-1] >= 1.0:  # a tie spread over the seam: wrap it
        params = np.mod(params, 1.0)
        resort = np.argsort(params, kind="stable")
        order, params = order[resort], params[resort]
    return order, params


def _unit(v: FloatArray) -> FloatArray:
    n = np.linalg.norm(v, axis=1, keepdims=True)
    return v / np.where(n > 0, n, 1.0)


def vertex_parameters(pyramid: Pyramid, fine_u: FloatArray) -> FloatArray:
    """Every parameter a vertex can take but a data point's own: the coefficients' of every
    level and the ordered points'."""
    levels = range(pyramid.coarsest, pyramid.finest + 1)
    return np.concatenate([fine_u] + [wavelets.greville(j, pyramid.closed) for j in levels])


def hull_groups(points: FloatArray, params: FloatArray, pyramid: Pyramid, cuts: FloatArray
                ) -> tuple[IntArray, np.ndarray]:
    """Group of each point and whether it may be a hull vertex of its group.

    Group 2i holds the parameters strictly between ``cuts[i-1]`` and ``cuts[i]``, group 2i+1
    those at ``cuts[i]`` (as in `simplify.select_vertices`' gaps); each group is seen along the
    chord of the finest control polygon between its cuts.
    """
    group = np.add(*nearly_uniform_search(cuts, params))
    cp = pyramid.coefficients[pyramid.finest]
    u = wavelets.greville(pyramid.finest, pyramid.closed)
    if pyramid.closed:
        cp, u = np.vstack([cp, cp[:1]]), np.append(u, 1.0)
    at = np.column_stack([np.interp(cuts, u, cp[:, 0]), np.interp(cuts, u, cp[:, 1])])
    axes = np.tile([1.0, 0.0], (2 * len(cuts) + 1, 1))
    if len(cuts) >= 2:
        chords = np.diff(at, axis=0)
        axes[2:-1:2] = chords
        axes[0], axes[-1] = chords[0], chords[-1]
    return group, group_hull_candidates(points, group, axes)


def split_groups(cuts: FloatArray, cand_u: FloatArray, closed: bool) -> np.ndarray:
    """Mask over the groups of `hull_groups`: those that a candidate's parameter, not itself a
    cut, splits (the hull of a part of a group is not among the group's hull candidates)."""
    key = np.mod(cand_u, 1.0) if closed else cand_u
    key = key[~np.isin(key, cuts)]
    split = np.zeros(2 * len(cuts) + 1, dtype=bool)
    split[np.searchsorted(cuts, key, "left") + np.searchsorted(cuts, key, "right")] = True
    return split
