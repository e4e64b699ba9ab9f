"""Strokes among the outliers: the points the first reading left, read again.

On a dense noisy scan the march follows each wall's main band. A second, fainter band beside
it (a ghost wall from a pass whose registration drifted, a reflection) or the foot of a short
wall meeting it lies farther than the radius from the chain, and its points were outliers;
the corner insertion used to reach them with a spike from every other vertex (a zigzag the
length of the wall), which it no longer does along a straight stretch (`contours`). Such a
compact group is a contour, not outliers (the issue: "a compact group of points that forms a
loop or a stroke of at least 4 tolerances is a contour"). So the outliers are read again:

1. Strays go first: a point with fewer than `STROKE_NEIGHBOURS` outliers within the radius
   lies on no stroke (the scattered returns about a wall).
2. Groups of the rest (points within a radius of one another, chained) that span
   `STROKE_EXTENT` tolerances are ordered again as a clean sample, with neighbourhoods of the
   radius: the noise measured over leftovers is the strays', and the reach it would give
   bridges metres of empty floor.
3. Each chain is cut where it leaves its points (a segment whose middle is farther than half a
   radius from all of them) and where it comes within `CLEARANCE` tolerances of a contour of
   the first reading, so that no stroke crosses or touches one. A piece whose points (those
   within a radius of it) span `STROKE_EXTENT` tolerances less a radius (a stroke meeting a
   wall lost the points within a radius of that wall to it), with at least `STROKE_DENSITY`
   points per radius of its length, is a contour with those points its members.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import shapely
from scipy.spatial import cKDTree

from ..geometry import curve_line, polyline_length
from ..types import FloatArray, IntArray, OrderedContour, Ordering
from .neighbourhoods import point_clusters

#: A stroke spans at least this many tolerances, below the issue's bar of 4 ("a stroke of at
#: least 4 tolerances is a contour"): the Intel map's outliers at 0.1 sat at 0.86-1.08 % as
#: the map is shifted or turned, against the issue's 1 %, and its strokes of 3-4 tolerances
#: (wall stubs, furniture edges) hold 0.04-0.15 % of its points: 0.80-0.95 % so. Freiburg
#: at 0.1 gains 67 such pieces (282 -> 349 open), its walls as before.
STROKE_EXTENT = 3.0
#: A point lies on a stroke when at least this many outliers (itself included) are within the
#: radius: points half a radius apart along a line have 4 or 5; strays about a wall, 1 or 2.
STROKE_NEIGHBOURS = 4
#: A stroke holds at least this many points per radius of its length (a line of returns, not
#: a sprinkling of strays the chain happened to join).
STROKE_DENSITY = 2.0
#: A stroke keeps this many tolerances clear of the first reading's contours: the polygons
#: drawn later each move up to a tolerance off their chains, and must not cross.
CLEARANCE = 0.5
#: A chain's segment whose middle is farther than this many radii from its points has left
#: them (it joined two groups across a gap).
UNSUPPORTED = 0.5


def stroke_contours(pts: FloatArray, outliers: IntArray, first: list[OrderedContour],
                    radius: float, tolerance: float, read: Callable[[FloatArray], Ordering]
                    ) -> tuple[list[OrderedContour], IntArray]:
    """Contours of the strokes among ``outliers`` (indices into ``pts``) and the outliers left.

    ``first``: the contours of the first reading, which the strokes keep clear of;
    ``read``: orders a set of points as a clean sample (`wavepoly.ordering.order_points`'s
    reading at the radius).
    """
    candidates = _stroke_points(pts, outliers, radius, tolerance)
    if not len(candidates):
        return [], outliers
    obstacles = shapely.STRtree([curve_line(c.points, c.closed) for c in first])
    found: list[OrderedContour] = []
    for chain in read(pts[candidates]).contours:
        members = candidates[chain.members]
        if chain.closed and _untouched(chain, pts[members], obstacles, radius, tolerance):
            found.append(OrderedContour(chain.points, True, members))  # a loop, whole and clear
            continue
        pieces = _clear_pieces(chain, pts[members], obstacles, radius, tolerance)
        found += _with_members(pieces, members, pts, radius, tolerance)
    if not found:
        return [], outliers
    used = np.concatenate([c.members for c in found])
    return found, np.setdiff1d(outliers, used)


def _stroke_points(pts: FloatArray, outliers: IntArray, radius: float, tolerance: float
                   ) -> IntArray:
    """The outliers that are not strays and lie in a group spanning `STROKE_EXTENT`
    tolerances."""
    xy = pts[outliers]
    if not len(xy):
        return outliers
    crowd = cKDTree(xy).query_ball_point(xy, radius, return_length=True)
    dense = outliers[crowd >= STROKE_NEIGHBOURS]
    if not len(dense):
        return dense
    label = point_clusters(pts[dense], radius)
    k = label.max() + 1
    low = np.full((k, 2), np.inf)
    high = np.full((k, 2), -np.inf)
    np.minimum.at(low, label, pts[dense])
    np.maximum.at(high, label, pts[dense])
    wide = np.linalg.norm(high - low, axis=1) >= STROKE_EXTENT * tolerance
    return dense[wide[label]]


def _supported(chain: OrderedContour, members: FloatArray, radius: float
               ) -> tuple[FloatArray, np.ndarray]:
    """The chain's polyline (closed: back to its start) and which of its segments run along
    its points (`UNSUPPORTED`)."""
    xy = np.vstack([chain.points, chain.points[:1]]) if chain.closed else chain.points
    if len(xy) < 2:
        return xy, np.zeros(0, dtype=bool)
    gap, _ = cKDTree(members).query(0.5 * (xy[1:] + xy[:-1]))
    return xy, gap <= UNSUPPORTED * radius


def _untouched(chain: OrderedContour, members: FloatArray, obstacles: shapely.STRtree,
               radius: float, tolerance: float) -> bool:
    """Whether every segment of ``chain`` runs along its points, clear of the obstacles."""
    _, along = _supported(chain, members, radius)
    line = curve_line(chain.points, True)
    return bool(along.all()) and not len(
        obstacles.query(line, predicate="dwithin", distance=CLEARANCE * tolerance))


def _clear_pieces(chain: OrderedContour, members: FloatArray, obstacles: shapely.STRtree,
                  radius: float, tolerance: float) -> list[FloatArray]:
    """The stretches of ``chain`` along its points and clear of the ``obstacles``."""
    xy, along = _supported(chain, members, radius)
    lines = [shapely.linestrings(xy[run[0]:run[-1] + 2]) for run in _runs(np.flatnonzero(along))]
    pieces = []
    for line in lines:
        near = obstacles.query(line, predicate="dwithin", distance=CLEARANCE * tolerance)
        if len(near):
            zone = shapely.union_all(obstacles.geometries[near]).buffer(CLEARANCE * tolerance)
            line = line.difference(zone)
        parts = shapely.get_parts(shapely.line_merge(line)) if not line.is_empty else []
        pieces += [shapely.get_coordinates(p) for p in parts if p.length > 0]
    return pieces


def _runs(index: IntArray) -> list[IntArray]:
    """Runs of consecutive integers in sorted ``index``."""
    if not len(index):
        return []
    return np.split(index, np.flatnonzero(np.diff(index) > 1) + 1)


def _with_members(pieces: list[FloatArray], members: IntArray, pts: FloatArray, radius: float,
                  tolerance: float) -> list[OrderedContour]:
    """The pieces that make strokes, each with the ``members`` nearest it within a radius."""
    pieces = [p for p in pieces if len(p) >= 2]
    if not pieces:
        return []
    where = shapely.points(pts[members])
    dist = np.column_stack([shapely.distance(where, shapely.linestrings(p)) for p in pieces])
    owner = np.argmin(dist, axis=1)
    near = dist[np.arange(len(members)), owner] <= radius
    strokes = []
    for k, piece in enumerate(pieces):
        own = np.sort(members[near & (owner == k)])
        if (len(own) >= 2 and _extent(pts[own]) >= STROKE_EXTENT * tolerance - radius
                and len(own) * radius >= STROKE_DENSITY * polyline_length(piece, False)):
            strokes.append(OrderedContour(piece, False, own))
    return strokes


def _extent(xy: FloatArray) -> float:
    """Diagonal of the bounding box of ``xy``."""
    return float(np.linalg.norm(np.ptp(xy, axis=0)))
