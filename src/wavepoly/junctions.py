"""Junctions: an open contour that ends just short of another runs on to meet it.

A short wall standing on a long one (a T junction on a laser map) is a piece of its own: the
outliers' second reading keeps it half a tolerance clear of the wall, and its chain ends
where its points thin out, so its polygon stops short of the wall, as a stroke of a drawing
may stop short of the one it meets. The issue asks that "where the points truly form a T or X
junction, the pieces meet at the junction". So an open contour whose end lies within
`JUNCTION_GAP` tolerances of another contour, and heads towards it (its last edge within
`JUNCTION_CONE` degrees of the way there), gains one edge, to the nearest point of that
contour, where that edge meets nothing else. The tolerance holds: every point keeps the edges
it was within the tolerance of, and an edge added can only bring the output nearer.
"""

from __future__ import annotations

import numpy as np
import shapely

from .geometry import curve_line
from .types import Contour, FloatArray

#: An open contour's end this many tolerances from another contour, or nearer, meets it: the
#: gap a piece read apart leaves (half a tolerance of clearance, the chain's end short of its
#: last points, a tolerance of polygon).
JUNCTION_GAP = 2.0
#: ... when the way there is within this many degrees of the contour's last edge: a piece
#: heading into a wall, not one running beside it.
JUNCTION_CONE = 45.0
#: Intersections this close (relative to the gap) to the new edge's own ends are its junctions.
END_SLACK = 1e-9


def meet_at_junctions(contours: list[Contour], tolerance: float
                      ) -> tuple[list[Contour], list[int]]:
    """The contours with each open end that stops short of another contour run on to it, and
    the indices of the contours that gained an edge."""
    lines = [curve_line(c.vertices, c.closed) for c in contours]
    if len(lines) < 2:
        return contours, []
    tree = shapely.STRtree(lines)
    added: list[shapely.Geometry] = []
    out = list(contours)
    grown = []
    for k, c in enumerate(contours):
        if c.closed or len(c.vertices) < 2 or np.array_equal(c.vertices[0], c.vertices[-1]):
            continue  # (an open line whose ends meet is a loop already)
        vertices = c.vertices
        for end, inner in ((0, 1), (-1, -2)):
            edge = _edge_to_nearest(vertices[end], vertices[inner], k, lines, tree, tolerance)
            if edge is None or _meets_others(edge, k, lines, tree, added):
                continue
            added.append(edge)
            target = shapely.get_coordinates(edge)[1:]
            vertices = (np.vstack([target, vertices]) if end == 0
                        else np.vstack([vertices, target]))
        if len(vertices) > len(c.vertices):
            out[k] = Contour(vertices, False, c.max_error, c.mean_error)
            grown.append(k)
    return out, grown


def _edge_to_nearest(end: FloatArray, inner: FloatArray, k: int, lines: list,
                     tree: shapely.STRtree, tolerance: float) -> shapely.Geometry | None:
    """The edge from ``end`` to the nearest point of the nearest other contour within
    `JUNCTION_GAP`, if the contour heads there (`JUNCTION_CONE`)."""
    here = shapely.points(end)
    near = [j for j in tree.query(here, predicate="dwithin", distance=JUNCTION_GAP * tolerance)
            if j != k]
    if not near:
        return None
    gaps = shapely.distance(here, tree.geometries[near])
    j = near[int(np.argmin(gaps))]
    if gaps.min() == 0:
        return None  # it meets that contour already
    target = shapely.get_coordinates(shapely.shortest_line(here, lines[j]))[1]
    heading, way = end - inner, target - end
    norm = np.linalg.norm(heading) * np.linalg.norm(way)
    if norm == 0 or heading @ way < np.cos(np.radians(JUNCTION_CONE)) * norm:
        return None
    return shapely.linestrings(np.vstack([end, target]))


def _meets_others(edge: shapely.Geometry, k: int, lines: list, tree: shapely.STRtree,
                  added: list[shapely.Geometry]) -> bool:
    """Whether ``edge`` meets anything but its own contour at its start and the contour it
    runs to at its end: no new edge may cross a contour or another new edge."""
    ends = shapely.get_coordinates(edge)
    slack = END_SLACK * max(float(np.linalg.norm(ends[1] - ends[0])), 1e-300)
    own, target = shapely.buffer(shapely.points(ends[0]), slack), shapely.buffer(
        shapely.points(ends[1]), slack)
    for j in tree.query(edge, predicate="intersects"):
        meet = shapely.intersection(edge, lines[j])
        allowed = own if j == k else target
        if not shapely.is_empty(shapely.difference(meet, allowed)):
            return True
    return any(shapely.intersects(edge, other) for other in added)
