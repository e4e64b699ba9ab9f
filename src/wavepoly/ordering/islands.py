"""Islands: compact groups of points too small for the march that are still curves.

A loop of a few points a little wider than the radius (a hole in a silhouette, a rivet in a
slice) fills every neighbourhood it has: the regression lines have no direction along it, and
the march makes no chain. Its points were outliers. A group of outliers, each within a radius
of another, that spans at least `ISLAND_EXTENT` tolerances (below the issue's bar, "a compact
group of points that forms a loop or a stroke of at least 4 tolerances is a contour, never
outliers": on a clean scan a hole 2 tolerances across is as real as a larger one) becomes a
contour when its points surround their centre: a closed ring in the order of their angles
about it. Only loops: a group that does not close is left to the march (strokes of 4
tolerances already make chains), and in a slab of a sliced cap, where strays of the surface
are no curve, such groups became open pieces where the true section is empty. Only on a clean
scan: on a noisy laser map such groups are clutter (Freiburg at 0.1 would gain 151 pieces).
"""

from __future__ import annotations

import numpy as np
import shapely

from ..types import FloatArray, IntArray, OrderedContour
from .neighbourhoods import point_clusters

#: Groups spanning at least this many tolerances are contours: a sliver of a hole that a
#: silhouette's slit leaves spans 1.9 (silhouette row 0, seed 53); a smaller group lies within
#: a tolerance of any point of itself and is no curve a polygon could show.
ISLAND_EXTENT = 1.5
#: ... with at least this many points: fewer make no curve worth a polygon.
ISLAND_POINTS = 5
#: A group surrounds its centre, and is a loop, when no gap between the directions from the
#: centre to its points is wider than this (degrees): 7 points round the hole of vase.txt
#: leave one of 93, the sliver of silhouette 0:53 one of 126; an open stroke leaves two of
#: about 180.
LOOP_GAP = 135.0


def island_contours(outliers: IntArray, pts: FloatArray, radius: float, tolerance: float
                    ) -> tuple[list[OrderedContour], IntArray]:
    """Contours of the groups of ``outliers`` (points within ``radius`` of one another) that
    span `ISLAND_EXTENT` ``tolerance`` s, and the outliers left."""
    if len(outliers) < ISLAND_POINTS:
        return [], outliers
    xy = pts[outliers]
    label = point_clusters(xy, radius)
    wide = group_extents(xy, label) >= ISLAND_EXTENT * tolerance
    found, used = [], []
    for g in np.flatnonzero((np.bincount(label) >= ISLAND_POINTS) & wide):
        members = np.flatnonzero(label == g)
        contour = _island(xy[members], outliers[members])
        if contour is not None:
            found.append(contour)
            used.append(outliers[members])
    if not found:
        return [], outliers
    return found, np.setdiff1d(outliers, np.concatenate(used))


def group_extents(xy: FloatArray, label: IntArray) -> FloatArray:
    """The diagonal of each labelled group's bounding box (labels 0..k-1)."""
    lo = np.full((label.max(initial=-1) + 1, 2), np.inf)
    hi = -lo
    np.minimum.at(lo, label, xy)
    np.maximum.at(hi, label, xy)
    return np.linalg.norm(hi - lo, axis=1)


def _island(group: FloatArray, members: IntArray) -> OrderedContour | None:
    """The group as a ring about its centre, if it surrounds it and the ring is simple.

    The centre is that of the group's convex hull (its area centroid), not the points' mean,
    which leans toward a side sampled more densely: round a thin sliver whose long side held
    no point between its ends, that side spanned 136 degrees from the mean and 111 from the
    hull's centre. On an open arc the hull's centre lies nearer the chord than the mean does,
    so an arc is no more a loop than it was (a half circle: 134 degrees against 115).
    """
    centre = np.asarray(shapely.MultiPoint(group).convex_hull.centroid.coords[0])
    angle = np.arctan2(group[:, 1] - centre[1], group[:, 0] - centre[0])
    order = np.argsort(angle)
    gaps = np.diff(np.concatenate([angle[order], [angle[order][0] + 2 * np.pi]]))
    if np.degrees(gaps.max()) > LOOP_GAP:
        return None
    ring = group[order]
    return OrderedContour(ring, True, np.sort(members)) if shapely.Polygon(ring).is_valid else None
