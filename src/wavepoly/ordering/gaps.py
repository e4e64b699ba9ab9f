"""Closing an outline that the march left open across short gaps its points fill.

On a clean scan a silhouette's outline is one closed curve, but the march can stop a few radii
short of closing it: at a spur of a bitmap's outline one pixel wide (its two walls merge into a
chain whose tip is a dead end), or where the outline's last stretch runs beside a stretch the
march took before. The chain then comes out open, its two ends a few radii apart, and the gap
between them is not empty: the outline's points run across it. Where the march broke the
outline twice or more (at a notch's tip and where a lobe nearly touches the wall beside it),
it comes out as pieces whose ends pair up across such gaps, and they close as one ring. A
stroke of a line drawing whose ends come close (a C) has nothing between its ends, and stays
open.
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.spatial import cKDTree

from ..geometry import polyline_distance, polyline_length
from ..types import FloatArray, IntArray, OrderedContour
from .untangle import untangle

#: An open piece closes across a gap of at most this many radii (the march stops up to some 6
#: radii short where a spur's merged walls end it, 10.5 at the horse's tail in scikit-image,
#: a run of one-pixel spurs each 3 to 4 radii long, and 12.4 at the root of a noisy bitmap
#: silhouette's limb whose walls merged; a gap is closed only where points fill it)...
GAP_REACH = 18.0
#: ... when it is at least this many times as long as the gap: the two ends of a short curved
#: stroke lie near each other too (a 270-degree arc is 3.3 x its gap, and its gap is filled
#: only where the arc is under 2 radii across). A small shape's outline, 4-5 tolerances
#: across, that the march left open at a corner is 4.4 x its gap: at 10 it stayed open.
GAP_LENGTH = 4.0
#: The gap is filled when a point lies within this many radii of every sample along it (the
#: gap may cut a corner of the outline it runs across: 1.03 radii at scikit-image's horse's
#: tail, where the march stopped 12 radii short); a stroke's ends facing across an empty gap
#: leave its middle bare: the march joins ends up to 4 radii apart, so a gap left open is
#: wider than 3 of these.
GAP_SUPPORT = 1.25
#: Samples along the gap this many radii apart.
GAP_STEP = 0.5
#: Ends of other pieces looked at per end, the nearest first.
GAP_CANDIDATES = 6
#: The mean spacing of the points near an end (`chance_gaps`) is taken over the contours'
#: length within this many radii of it.
SPACING_WINDOW = 10.0


def close_gaps(contours: list[OrderedContour], points: FloatArray, radius: float,
               left_out: IntArray | None = None
               ) -> tuple[list[OrderedContour], IntArray]:
    """Close each open piece whose ends lie across a short gap that its points fill, then
    each cycle of open pieces whose ends pair up across such gaps.

    The closed ring keeps the pieces' points, and takes the points left out that lie across
    a gap (`_bridge`: a single return at a limb's round tip beyond a sparse scan's gap);
    where a closing edge crosses a piece near the gap, the crossing is untangled (2-opt).
    Pieces close only when the ring is a valid polygon, crosses no other contour and keeps
    every member as near as the open pieces did (or within a radius). Two ends pair up when
    each is the other's nearest end (of another piece) across a gap of at most `GAP_REACH`
    radii that points fill (`GAP_SUPPORT`) or no wider than the sample leaves by chance
    (`chance_gaps`: on a scan sparser than the radius, the gap a random sampling left).

    Parameters
    ----------
    contours : the ordered contours; only the open ones are read.
    points : the input points (the contours' members index them).
    radius : the neighbourhood radius of the ordering.
    left_out : indices of the points no contour holds (outliers so far), sorted.

    Returns
    -------
    The contours, those that closed now closed, and the points still left out.

    Examples
    --------
    A ring the march left open 4 radii short of its start; its points fill the gap.

    >>> t = np.linspace(0, 2 * np.pi, 600, endpoint=False)
    >>> pts = np.column_stack([np.cos(t), np.sin(t)])
    >>> piece = OrderedContour(pts[:-6:6], False, np.arange(600))
    >>> [c.closed for c in close_gaps([piece], pts, 0.03)[0]]
    [True]
    """
    left_out = np.empty(0, dtype=np.intp) if left_out is None else left_out
    if all(c.closed for c in contours):
        return contours, left_out
    tree = cKDTree(points)
    lines = shapely.union_all([_line(c) for c in contours])
    others = shapely.STRtree([_line(c) for c in contours])
    out = list(contours)
    for k, c in enumerate(contours):
        if c.closed or not _filled_gap(c.points, lines, tree, radius):
            continue
        ring, taken = _bridge([c.points], points, left_out)
        ring = _closed_ring(ring)
        if ring is None or meets_others(ring, (k,), others):
            continue
        if keeps_members(ring, c, points, radius):
            out[k] = OrderedContour(ring, True, np.union1d(c.members, taken))
            left_out = np.setdiff1d(left_out, taken)
    if any(a is not b for a, b in zip(out, contours)):  # rings closed: their lines moved
        lines = shapely.union_all([_line(c) for c in out])
    return _close_cycles(out, points, radius, tree, lines, left_out)


def _close_cycles(contours: list[OrderedContour], points: FloatArray, radius: float,
                  tree: cKDTree, lines: shapely.Geometry, left_out: IntArray
                  ) -> tuple[list[OrderedContour], IntArray]:
    """Join open pieces end to end into one ring where their ends pair up across filled gaps
    (`_partner_ends`) and the pairs close a cycle; under the rules of a single piece's gap.
    ``lines``: the contours' lines (their union), where the spacing near the ends is measured
    (`chance_gaps`)."""
    pieces = [k for k, c in enumerate(contours) if not c.closed and len(c.points) >= 2]
    if len(pieces) < 2:
        return contours, left_out
    ends = np.vstack([contours[k].points[[0, -1]] for k in pieces])
    chance = chance_gaps(ends, lines, tree, radius)
    partner = _partner_ends(ends, chance, tree, radius)
    others = shapely.STRtree([_line(c) for c in contours])
    out, used = list(contours), set()
    for cycle in _cycles(partner):
        own = tuple(pieces[i] for i, _ in cycle)
        walks = [contours[pieces[i]].points[::-1 if flip else 1] for i, flip in cycle]
        exits = [_exit_end(i, flip) for i, flip in cycle]
        widest = np.linalg.norm(ends[exits] - ends[partner[exits]], axis=1).max()
        if polyline_length(np.vstack(walks), True) < GAP_LENGTH * widest:
            continue
        ring, taken = _bridge(walks, points, left_out)
        ring = _closed_ring(ring)
        if ring is None or meets_others(ring, own, others):
            continue
        if all(keeps_members(ring, contours[k], points, radius) for k in own):
            members = np.concatenate([contours[k].members for k in own] + [taken])
            out[own[0]] = OrderedContour(ring, True, np.sort(members))
            used.update(own[1:])
            left_out = np.setdiff1d(left_out, taken)
    return [c for k, c in enumerate(out) if k not in used], left_out


def _bridge(walks: list[FloatArray], points: FloatArray, left_out: IntArray
            ) -> tuple[FloatArray, IntArray]:
    """The ring that walks the pieces in turn, each gap from one's last point to the next's
    first crossed through the points left out within half the gap of its middle (in their
    order along it), and those points' indices."""
    parts, taken = [], []
    for w, nxt in zip(walks, walks[1:] + walks[:1]):
        a, b = w[-1], nxt[0]
        half = 0.5 * float(np.linalg.norm(b - a))
        near = left_out[np.linalg.norm(points[left_out] - 0.5 * (a + b), axis=1) <= half]
        along = (points[near] - a) @ (b - a)
        near = near[np.argsort(along, kind="stable")]
        parts += [w, points[near]]
        taken.append(near)
    return np.vstack(parts), np.concatenate(taken).astype(np.intp)


def _partner_ends(ends: FloatArray, chance: FloatArray, tree: cKDTree, radius: float
                  ) -> np.ndarray:
    """For each end (two per piece), the nearest end of another piece within `GAP_REACH`
    radii across a filled gap or one no wider than the sampling leaves by chance there
    (``chance``: each end's, `chance_gaps`; the two ends' mean), where that end chooses it
    back; else -1."""
    k = min(GAP_CANDIDATES, len(ends))
    dist, near = cKDTree(ends).query(ends, k=k, distance_upper_bound=GAP_REACH * radius)
    choice = np.full(len(ends), -1)
    for e in range(len(ends)):
        for d, j in zip(dist[e], near[e]):
            if not np.isfinite(d):
                break
            if j // 2 != e // 2 and (d <= 0.5 * (chance[e] + chance[j])
                                     or is_supported(ends[e], ends[j], tree, radius)):
                choice[e] = j
                break
    mutual = (choice >= 0) & (choice[np.maximum(choice, 0)] == np.arange(len(ends)))
    return np.where(mutual, choice, -1)


def _cycles(partner: np.ndarray) -> list[list[tuple[int, bool]]]:
    """The cycles of pieces that the paired ends close, each a list of (piece, reversed):
    piece i has ends 2i (its start) and 2i + 1, and is walked from the end where the walk
    arrives to its other end."""
    cycles, seen = [], set()
    for start in range(len(partner) // 2):
        if start in seen:
            continue
        cycle, piece, flip = [], start, False
        while piece not in seen:
            seen.add(piece)
            cycle.append((piece, flip))
            arrive = partner[_exit_end(piece, flip)]
            if arrive < 0:
                break
            piece, flip = arrive // 2, arrive % 2 == 1
        if piece == start and not flip and len(cycle) > 1:
            cycles.append(cycle)
    return cycles


def _exit_end(piece: int, flip: bool) -> int:
    """The end a piece's walk leaves it by: its last point, or its first where reversed."""
    return 2 * piece + (0 if flip else 1)


def keeps_members(ring: FloatArray, contour: OrderedContour, points: FloatArray,
                  radius: float) -> bool:
    """Does ``ring`` keep every member of ``contour`` as near as the contour did (or within
    ``radius``)?"""
    members = points[contour.members]
    before = polyline_distance(members, contour.points, contour.closed).max(initial=0.0)
    after = polyline_distance(members, ring, True).max(initial=0.0)
    return bool(after <= max(before, radius))


def meets_others(ring: FloatArray, own: tuple[int, ...], others: shapely.STRtree) -> bool:
    """Does the ring meet a contour of ``others`` (their lines) other than its ``own``?"""
    hit = others.query(shapely.LinearRing(ring), predicate="intersects")
    return bool(np.any(~np.isin(hit, own)))


def _filled_gap(xy: FloatArray, lines: shapely.Geometry, tree: cKDTree, radius: float
                ) -> bool:
    """Are the piece's ends within `GAP_REACH` radii, the piece `GAP_LENGTH` times as long as
    the gap, and points along the gap (`is_supported`) or the gap no wider than the sampling
    leaves by chance there (`chance_gaps`)?"""
    a, b = xy[0], xy[-1]
    gap = float(np.linalg.norm(b - a))
    if len(xy) < 4 or gap > GAP_REACH * radius or polyline_length(xy, False) < GAP_LENGTH * gap:
        return False
    return (gap <= float(chance_gaps(xy[[0, -1]], lines, tree, radius).mean())
            or is_supported(a, b, tree, radius))


def chance_gaps(ends: FloatArray, lines: shapely.Geometry, tree: cKDTree, radius: float
                ) -> FloatArray:
    """The widest gap a uniform random sampling leaves near each end: ln n times the mean
    spacing there (n the number of points; the gaps between n uniform random samples are
    exponential, and the widest is about ln n times their mean). The mean spacing is the
    length of the contours' ``lines`` within `SPACING_WINDOW` radii of the end over the
    points there (two walls side by side have twice the points along twice the length).

    On a clean scan the spacing is a fraction of the radius, and this is less than the gaps
    the march joins; on one sparser than the radius (a scan thinned across a part) it closes
    an outline across an empty stretch a few times its spacing wide.
    """
    reach = SPACING_WINDOW * radius
    length = shapely.length(shapely.intersection(lines, shapely.buffer(shapely.points(ends),
                                                                       reach)))
    count = np.array([len(n) for n in tree.query_ball_point(ends, reach)])
    return np.log(max(tree.n, 2)) * length / np.maximum(count, 1)


def is_supported(a: FloatArray, b: FloatArray, tree: cKDTree, radius: float) -> bool:
    """Does a point lie within `GAP_SUPPORT` radii of every sample along the gap from a to b?"""
    steps = max(int(np.ceil(np.linalg.norm(b - a) / (GAP_STEP * radius))), 1)
    t = np.linspace(0.0, 1.0, steps + 1)[:, None]
    near, _ = tree.query(a + t * (b - a), distance_upper_bound=GAP_SUPPORT * radius)
    return bool(np.all(np.isfinite(near)))


def _closed_ring(xy: FloatArray) -> FloatArray | None:
    """The piece as a ring, untangled where the closing edge crosses it; None unless valid."""
    ring = xy
    if not shapely.Polygon(ring).is_valid:
        ring = untangle(xy, True)
    return ring if shapely.Polygon(ring).is_valid else None


def _line(c: OrderedContour) -> shapely.Geometry:
    xy = np.vstack([c.points, c.points[:1]]) if c.closed else c.points
    return shapely.LineString(xy)
