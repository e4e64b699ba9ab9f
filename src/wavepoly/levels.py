"""How deep to decompose (paper §3, eq. 6-7), and an ordered contour as level-J control points.

The ordered points are taken as the control points of a cubic B-spline (eq. 1-2). The wavelets
need ``2**J + 3`` (open) or ``2**J`` (closed) of them, so `to_control_points` inserts extra
points on the longest segments of the ordered polyline until the count fits. Every ordered point
stays a control point and the control polygon stays the same polyline, so the finest level loses
nothing; arc-length resampling would cut corners by up to half a sample spacing and a
least-squares fit would smooth them (see the wavelets note for the measured errors of each).
"""

from __future__ import annotations

import numpy as np

from . import wavelets
from .errors import ParameterError
from .geometry import nearest_segment, polyline_segments
from .types import DEFAULT_RELATIVE_TOLERANCE, FloatArray, IntArray, LevelErrors, Pyramid


def finest_level(n_points: int, closed: bool) -> int:
    """Smallest level J whose coefficient count holds ``n_points`` ordered points."""
    base = n_points if closed else max(n_points - 3, 1)
    level = max(int(np.ceil(np.log2(base))), wavelets.MIN_LEVEL[closed] + 1)
    return level


def to_control_points(points: FloatArray, closed: bool, level: int | None = None
                      ) -> tuple[FloatArray, IntArray]:
    """Control points at level J holding every ordered point, and where each one went.

    Extra points are spread over the segments in proportion to their length (largest
    remainder), evenly inside each segment.

    >>> cp, where = to_control_points(np.array([[0., 0.], [1., 0.], [1., 3.]]), closed=False)
    >>> len(cp), where.tolist()
    (5, [0, 2, 4])
    """
    n = len(points)
    level = finest_level(n, closed) if level is None else level
    m = wavelets.n_coefficients(level, closed)
    if m < n:
        raise ParameterError(f"level {level} holds {m} coefficients, fewer than {n} points")
    a, b = polyline_segments(points, closed)
    length = np.linalg.norm(b - a, axis=1)
    extra = _largest_remainder(length, m - n)
    per_seg = extra + 1  # the segment's start point and its inserted points
    seg = np.repeat(np.arange(len(a)), per_seg)
    first = np.repeat(np.cumsum(per_seg) - per_seg, per_seg)
    frac = (np.arange(len(seg)) - first) / per_seg[seg]
    cp = a[seg] + frac[:, None] * (b - a)[seg]
    index = np.cumsum(per_seg) - per_seg
    if not closed:
        cp = np.vstack([cp, points[-1:]])
        index = np.append(index, len(cp) - 1)
    return cp, index.astype(np.intp)


def _largest_remainder(weights: FloatArray, total: int) -> IntArray:
    if total == 0:
        return np.zeros(len(weights), dtype=np.intp)
    w = weights if weights.sum() > 0 else np.ones_like(weights)
    quota = w / w.sum() * total
    count = np.floor(quota).astype(np.intp)
    short = total - count.sum()
    count[np.argsort(count - quota, kind="stable")[:short]] += 1
    return count


def level_errors(ordered: FloatArray, coarse: FloatArray, closed: bool, level: int
                 ) -> LevelErrors:
    """Eq. 6-7 for every segment of the coarse control polygon.

    E_i(s) is the largest distance to segment i of the ordered points nearer to it than to any
    other segment (eq. 6); E_i(r) = E_i(s) / length(segment i) (eq. 7). Segments with no points
    have E = 0.
    """
    seg, dist = nearest_segment(ordered, coarse, closed)
    n_seg = len(coarse) if closed else len(coarse) - 1
    shape = np.zeros(n_seg)
    np.maximum.at(shape, seg, dist)
    a, b = polyline_segments(coarse, closed)
    length = np.linalg.norm(b - a, axis=1)
    relative = np.where(length > 0, shape / np.where(length > 0, length, 1.0), np.inf)
    return LevelErrors(level, shape, relative)


def decompose_contour(ordered: FloatArray, closed: bool, tolerance: float,
                      relative_tolerance: float | None = DEFAULT_RELATIVE_TOLERANCE) -> Pyramid:
    """Decompose an ordered contour level by level and choose the coarsest level (paper §3).

    At each level the eq. 6-7 errors of the coarse control polygon are measured against the
    ordered points; the decomposition stops at the first level where a segment violates both
    ``tolerance`` and ``relative_tolerance``, and the level above it is the coarsest. With
    ``relative_tolerance=None`` it goes down to the coarsest level the wavelets allow, and the
    fit picks the starting level (`wavepoly.fit.auto_start_levels`).

    Every level's coefficients and details are kept for the reconstruction stage.
    """
    cp, index = to_control_points(ordered, closed)
    top = wavelets.level_of(len(cp), closed)
    coefficients, details, errors = {top: cp}, {}, {}
    level, c = top, cp
    while level > wavelets.MIN_LEVEL[closed]:
        coarse, d = wavelets.analyze(c, closed)
        errs = level_errors(ordered, coarse, closed, level - 1)
        if relative_tolerance is not None and errs.violates(tolerance, relative_tolerance):
            break
        level, c = level - 1, coarse
        coefficients[level], details[level], errors[level] = coarse, d, errs
    return Pyramid(closed, top, level, coefficients, details, index, errors)
