"""A lobe on a narrow neck: one outline, not two rings.

Where a lobe meets the body through a neck a few radii long and about a radius wide or less
(a silhouette's head on a thin throat, a blob joined to the next by a bridge of pixels), the
march can close the lobe on itself across the neck and run the body's outline past its mouth,
each covering the neck's walls with a bump or a spike: two rings where the truth is one
outline pinched at the neck. Cutting an edge of each ring where they face and linking the cut
ends (a 2-opt move between the rings) gives the one outline. The move is kept where the points
about it lie much nearer the joined ring than the two rings: its links run along the neck's
walls, and the edges it cut ran across the neck's ends, where no wall runs. Two shapes of their
own that come close face each other along walls of points, which the cut edges carried; the
move would leave those points farther off, and the rings stay apart.

This differs from `mouths`, which joins a ring capped by a sharp turn at its root to a bare
straight pass of the body's outline: a neck's lobe may close round the neck with no cap (a
spike into it), and the body's outline may bulge into the neck's mouth, covering its points.

References
----------
.. [1] G. A. Croes, "A method for solving traveling-salesman problems", Operations Research
   6(6), 1958, pp. 791-812 (the 2-opt move).
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.spatial import cKDTree

from ..geometry import along_and_across, curve_line, polyline_distance, polyline_length
from ..types import FloatArray, OrderedContour
from .gaps import keeps_members, meets_others

#: Two rings this many radii apart or nearer may be a lobe and the body on a neck: the march
#: closes a lobe across a neck up to a couple of radii long.
NECK_REACH = 2.5
#: Edges of each ring tried for the move: those nearest the other ring...
NECK_EDGES = 6
#: ... each the first of a cut of up to this many edges: the lobe's ring may close round the
#: neck in a spike, and the body's bulge into its mouth, whose nodes the move drops.
CUT_EDGES = 3
#: Each link runs along one of the neck's walls: at least this many radii long (two shapes
#: a fraction of a radius apart, touching at a pixel's corner, are split at their waist,
#: `waists`)...
MIN_LINK = 0.75
#: ... and the two within this many degrees of parallel...
NECK_PARALLEL = 30.0
#: ... and each at least this many degrees off the chord of one of the cuts: the neck runs
#: from the body's mouth across to the lobe's, where a link along the walls of two rings side
#: by side (closer than the radius) runs beside the edges it replaces.
ACROSS_MOUTH = 45.0
#: The points about a move: those within this many radii of its cut edges or its links.
NECK_BAND = 1.0
#: A move is kept where the points about it lie, on average, at most this share as far from
#: the joined ring as from the two rings.
NECK_GAIN = 0.85
#: Each link runs along a wall: every sample along it (every `LINK_STEP` radii) has a point
#: within this many radii.
LINK_SUPPORT = 0.5
LINK_STEP = 0.25
#: Each link runs along one of the neck's walls: along its middle half, the points within
#: this many radii of it (a wall's scatter of a quarter radius, and the link's own slant)...
WALL_BAND = 0.35
#: ... are at least this share of what a wall as long holds at the two rings' points per
#: length. A link across the gap between two shapes finds their walls only near its ends.
WALL_SHARE = 0.5
#: Joins made per call; each leaves one ring fewer.
MAX_JOINS = 8


def join_through_necks(contours: list[OrderedContour], points: FloatArray, radius: float
                       ) -> list[OrderedContour]:
    """Join two rings side by side that a neck's walls link into one outline.

    Parameters
    ----------
    contours : the ordered contours; only closed ones, neither inside the other, are joined.
    points : the input points (the contours' members index them).
    radius : the neighbourhood radius of the ordering.

    Returns
    -------
    The contours, joined rings replaced by the one ring they make: the best move of
    `NECK_EDGES` x `NECK_EDGES` between them whose points lie nearer it (`NECK_GAIN`), whose
    links run along points (`LINK_SUPPORT`), and which is a valid polygon that meets no other
    contour and keeps every member of the two as near as its own ring did (or within a
    radius).
    """
    out = list(contours)
    tree = None
    for _ in range(MAX_JOINS):
        pairs = _near_pairs(out, radius)
        if not pairs:
            break
        tree = tree or cKDTree(points)
        join = next((j for a, b in pairs
                     if (j := _best_move(out, a, b, points, tree, radius)) is not None), None)
        if join is None:
            break
        a, b, ring = join
        out[a] = OrderedContour(ring, True, np.union1d(out[a].members, out[b].members))
        del out[b]
    return out


def _near_pairs(contours: list[OrderedContour], radius: float) -> list[tuple[int, int]]:
    """Pairs of rings (a < b) within `NECK_REACH` radii, neither inside the other, nearest
    first."""
    rings = [k for k, c in enumerate(contours) if c.closed and len(c.points) >= 4]
    if len(rings) < 2:
        return []
    polygons = [shapely.Polygon(contours[k].points) for k in rings]
    near_a, near_b = shapely.STRtree(polygons).query(polygons, predicate="dwithin",
                                                     distance=NECK_REACH * radius)
    pairs = []
    for i, j in zip(near_a, near_b):
        if i < j and not polygons[i].intersects(polygons[j]):
            pairs.append((float(polygons[i].distance(polygons[j])), rings[i], rings[j]))
    return [(a, b) for _, a, b in sorted(pairs)]


def _best_move(contours: list[OrderedContour], a: int, b: int, points: FloatArray,
               tree: cKDTree, radius: float) -> tuple[int, int, FloatArray] | None:
    """The move between rings a and b that brings the points about it nearest (at most
    `NECK_GAIN` as far as before), with its ring, or None."""
    one, two = contours[a].points, contours[b].points
    length = polyline_length(one, True) + polyline_length(two, True)
    density = (len(contours[a].members) + len(contours[b].members)) / max(length, 1e-300)
    lines = None
    best = None
    for cut_one in _facing_cuts(one, two):
        for cut_two in _facing_cuts(two, one):
            mouths = (_chord(one, *cut_one), _chord(two, *cut_two))
            for ring, links in _moves(one, cut_one, two, cut_two):
                if not _along_the_neck(links, mouths, tree, radius):
                    continue
                gain = _gain(ring, one, cut_one, two, cut_two, links, tree, radius)
                if gain > NECK_GAIN or (best is not None and gain >= best[0]):
                    continue
                if not (_walled(ring, len(one) - cut_one[1], tree, radius, density)
                        and shapely.Polygon(ring).is_valid):
                    continue
                if lines is None:
                    lines = shapely.STRtree([curve_line(c.points, c.closed) for c in contours])
                if (not meets_others(ring, (a, b), lines)
                        and all(keeps_members(ring, contours[k], points, radius)
                                for k in (a, b))):
                    best = (gain, ring)
    return None if best is None else (min(a, b), max(a, b), best[1])


def _facing_cuts(xy: FloatArray, other: FloatArray) -> list[tuple[int, int]]:
    """Cuts (i, k) of ring ``xy``: the k edges from xy[i] to xy[i + k], k up to `CUT_EDGES`,
    starting at one of its `NECK_EDGES` edges nearest the ring ``other``."""
    edges = shapely.linestrings(np.stack([xy, np.roll(xy, -1, axis=0)], axis=1))
    gap = shapely.distance(edges, shapely.LinearRing(other))
    first = np.argsort(gap, kind="stable")[:NECK_EDGES]
    return [(int(i), k) for i in first for k in range(1, min(CUT_EDGES, len(xy) - 3) + 1)]


def _moves(one: FloatArray, cut_one: tuple[int, int], two: FloatArray,
           cut_two: tuple[int, int]
           ) -> list[tuple[FloatArray, tuple[tuple[FloatArray, FloatArray], ...]]]:
    """The rings through ``one`` and ``two`` without their cuts, either way round ``two``,
    each with its two links."""
    p, q = _without(one, *cut_one), _without(two, *cut_two)
    return [(np.vstack([p, path]), ((p[-1], path[0]), (path[-1], p[0])))
            for path in (q, q[::-1])]


def _chord(xy: FloatArray, i: int, k: int) -> FloatArray:
    """The chord of ring ``xy``'s cut of k edges from xy[i]."""
    return xy[(i + k) % len(xy)] - xy[i]


def _sine(u: FloatArray, v: FloatArray) -> float:
    """The sine of the angle between two directions (0 where either is a point)."""
    norms = float(np.linalg.norm(u) * np.linalg.norm(v))
    return abs(float(u[0] * v[1] - u[1] * v[0])) / norms if norms > 0 else 0.0


def _without(xy: FloatArray, i: int, k: int) -> FloatArray:
    """Ring ``xy`` without its k edges from xy[i]: the path from xy[i + k] round to xy[i]."""
    return np.roll(xy, -(i + k), axis=0)[:len(xy) - k + 1]


def _along_the_neck(links: tuple[tuple[FloatArray, FloatArray], ...],
                    mouths: tuple[FloatArray, FloatArray], tree: cKDTree, radius: float
                    ) -> bool:
    """Do both links run along the neck: at least `MIN_LINK` radii long, within
    `NECK_PARALLEL` degrees of parallel, across a cut's chord (``mouths``, `ACROSS_MOUTH`)
    and along points (`_along_points`)?"""
    (a0, a1), (b0, b1) = links
    u, v = a1 - a0, b1 - b0
    lu, lv = float(np.linalg.norm(u)), float(np.linalg.norm(v))
    if min(lu, lv) < MIN_LINK * radius:
        return False
    if abs(float(u @ v)) < np.cos(np.radians(NECK_PARALLEL)) * lu * lv:
        return False
    if not all(max(_sine(w, m) for m in mouths) >= np.sin(np.radians(ACROSS_MOUTH))
               for w in (u, v)):
        return False
    return _along_points(a0, a1, tree, radius) and _along_points(b0, b1, tree, radius)


def _along_points(a: FloatArray, b: FloatArray, tree: cKDTree, radius: float) -> bool:
    """Does every sample along a-b (every `LINK_STEP` radii) lie within `LINK_SUPPORT`
    radii of a point?"""
    steps = max(int(np.ceil(np.linalg.norm(b - a) / (LINK_STEP * radius))), 1)
    t = np.linspace(0.0, 1.0, steps + 1)[:, None]
    near, _ = tree.query(a + t * (b - a), distance_upper_bound=LINK_SUPPORT * radius)
    return bool(np.all(np.isfinite(near)))


def _walled(ring: FloatArray, first_link: int, tree: cKDTree, radius: float,
            density: float) -> bool:
    """Does each link of the joined ring (segments ``first_link`` and the last) run along a
    wall: in its middle half, within `WALL_BAND` radii of it, at least `WALL_SHARE` of the
    points a wall that long holds at ``density`` points per length, and one at least?"""
    for k in (first_link, len(ring) - 1):
        a, b = ring[k], ring[(k + 1) % len(ring)]
        length = float(np.linalg.norm(b - a))
        near = tree.data[tree.query_ball_point((a + b) / 2, length / 2 + WALL_BAND * radius)]
        along, across = along_and_across(near, a, b)
        middle = (np.abs(along - length / 2) <= length / 4) & (across <= WALL_BAND * radius)
        if middle.sum() < max(WALL_SHARE * density * length / 2, 1.0):
            return False
    return True


def _gain(ring: FloatArray, one: FloatArray, cut_one: tuple[int, int], two: FloatArray,
          cut_two: tuple[int, int],
          links: tuple[tuple[FloatArray, FloatArray], ...], tree: cKDTree, radius: float
          ) -> float:
    """Mean distance of the points about the move (`NECK_BAND`) to the joined ring, over
    their mean distance to the two rings."""
    segments = [*_cut_edges(one, *cut_one), *_cut_edges(two, *cut_two),
                *(np.vstack(link) for link in links)]
    near = np.unique(np.concatenate([
        tree.query_ball_point(s.mean(axis=0), np.linalg.norm(s[1] - s[0]) / 2
                              + NECK_BAND * radius) for s in segments]).astype(np.intp))
    pts = tree.data[near]
    band = np.min([polyline_distance(pts, s, False) for s in segments], axis=0)
    pts = pts[band <= NECK_BAND * radius]
    if len(pts) == 0:
        return np.inf
    before = np.minimum(polyline_distance(pts, one, True), polyline_distance(pts, two, True))
    after = polyline_distance(pts, ring, True)
    return float(after.mean() / max(before.mean(), 1e-12 * radius))


def _cut_edges(xy: FloatArray, i: int, k: int) -> list[FloatArray]:
    """The k edges of ring ``xy`` from xy[i], each as a (2, 2) array."""
    n = len(xy)
    return [xy[[(i + m) % n, (i + m + 1) % n]] for m in range(k)]
