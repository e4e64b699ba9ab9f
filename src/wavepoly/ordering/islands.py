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

A speck, smaller still and clear of other points, is a closed contour too: its points' hull
(`speck_contours`). The march drew such specks as scraps of lines, slivers, or lines to the
next speck a few tolerances away, and left most of their points out. On a noisy laser map,
a speck among the outliers that its points surround (a chair's or a table's leg, seen from
round about) is its hull too (`clutter_specks`); one seen from one side (an arc, a person
standing by) or a dash of scatter is left out.
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.spatial import cKDTree

from ..types import FloatArray, IntArray, OrderedContour
from .neighbourhoods import group_extents, point_clusters

#: Groups spanning at least this many tolerances are contours: a sliver of a hole that a
#: silhouette's slit leaves spans 1.9 (silhouette row 0, seed 53); a smaller group lies within
#: a tolerance of any point of itself and is no curve a polygon could show.
ISLAND_EXTENT = 1.5
#: ... with at least this many points: fewer make no curve worth a polygon.
ISLAND_POINTS = 5
#: A group that nothing drew, clear of other points, is a polygon up to this many tolerances
#: across (the issue's "a loop or a stroke of at least 4 tolerances is a contour"; beyond,
#: the march makes a chain of it).
SPECK_EXTENT = 4.0
#: A group surrounds its centre, and is a loop, when no gap between the directions from the
#: centre to its points is wider than this (degrees): 7 points round the hole of vase.txt
#: leave one of 93, the sliver of silhouette 0:53 one of 126; an open stroke leaves two of
#: about 180.
LOOP_GAP = 135.0
#: A group that only open scraps drew is a loop where its points at least this share of
#: their median distance from its centre surround it: a ring's are all about as far, a
#: dash's lie along its two halves (and those near its middle anywhere round it).
RIM = 0.5


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


def speck_contours(contours: list[OrderedContour], outliers: IntArray, pts: FloatArray,
                   radius: float, tolerance: float, scraps: bool = True
                   ) -> tuple[list[OrderedContour], IntArray]:
    """Each speck a closed contour of its own: a group of at least `ISLAND_POINTS` points,
    each within ``radius`` of another and clear of every other point by ``radius``, that
    spans less than `ISLAND_EXTENT` ``tolerance`` s (a star in a photograph at a coarse
    tolerance, a traced mask's hole of a pixel or two). The march draws such a group as a
    scrap of a line, a sliver, or nothing; every point of it lies within a tolerance of its
    convex hull, which becomes its ring. Contours whose members all lie in one speck, and
    its outliers, give way to it; a contour that holds a speck's points and others is left.
    A group up to `SPECK_EXTENT` tolerances across that nothing drew (all outliers: an arc
    sampled on one side only, no loop for `island_contours`) becomes its hull too, where
    every point lies within a tolerance of the hull's outline; so does one that only open
    scraps drew and whose points surround its centre (a speck 1.5-2 tolerances across drawn
    as a line through it: a loop, `LOOP_GAP`), unless ``scraps`` is False (a noisy scan's
    outliers read again: scatter beside a wall, whose hull is a sliver, not a speck).

    Returns the contours and the outliers left.
    """
    small = [k for k, c in enumerate(contours) if len(c.members)
             and np.linalg.norm(np.ptp(pts[c.members], axis=0)) < SPECK_EXTENT * tolerance]
    cand = np.unique(np.concatenate([outliers, *[contours[k].members for k in small]]))
    if len(cand) < ISLAND_POINTS:
        return contours, outliers
    label = point_clusters(pts[cand], radius)  # groups among the outliers and small contours
    size = np.bincount(label)
    clear = _clear_groups(pts[cand], label, pts, radius)
    extent = group_extents(pts[cand], label)
    undrawn = np.bincount(label[np.searchsorted(cand, outliers)], minlength=len(size)) == size
    owner = {k: np.unique(label[np.searchsorted(cand, contours[k].members)]) for k in small}
    drawn_by_scraps = np.ones(len(size), dtype=bool)  # open scraps alone, or nothing
    for k, groups in owner.items():
        drawn_by_scraps[groups] &= not contours[k].closed
    small_enough = clear & (size >= ISLAND_POINTS) & (extent < SPECK_EXTENT * tolerance)
    loose = undrawn.copy()
    if scraps:
        for g in np.flatnonzero(small_enough & drawn_by_scraps & ~undrawn):
            loose[g] = _surrounds(*_about_centre(pts[cand[label == g]]), RIM)
    speck = small_enough & ((extent < ISLAND_EXTENT * tolerance) | loose)
    if not speck.any():
        return contours, outliers
    for groups in owner.values():  # a contour reaching beyond a group leaves it be
        if len(groups) > 1:
            speck[groups] = False
    found = {}
    for g in np.flatnonzero(speck):
        members = cand[label == g]
        ring = _hull_ring(pts[members], tolerance)
        if ring is not None:
            found[g] = OrderedContour(ring, True, members)
    if not found:
        return contours, outliers
    gone = {k for k, groups in owner.items() if len(groups) == 1 and groups[0] in found}
    kept = [c for k, c in enumerate(contours) if k not in gone]
    taken = np.concatenate([c.members for c in found.values()])
    return kept + list(found.values()), np.setdiff1d(outliers, taken)


def clutter_specks(outliers: IntArray, pts: FloatArray, radius: float, tolerance: float
                   ) -> tuple[list[OrderedContour], IntArray]:
    """On a noisy scan, the rings of the specks among ``outliers`` and the outliers left.

    A speck is a group of at least `ISLAND_POINTS` outliers (each within ``radius`` of
    another), clear of every other point by ``radius``, under `SPECK_EXTENT` ``tolerance`` s
    across, whose points at least `RIM` times their median distance from its centre surround
    it (`_surrounds`): a leg of a chair or a table, or a pillar, that the scanner saw from
    round about. Its ring is its convex hull, where every point lies within a tolerance of
    the hull's outline. An arc seen from one side (a person standing by), or a dash of
    scatter beside a wall, does not surround its centre and is left out: its hull would be a
    sliver, no obstacle's outline.
    """
    if len(outliers) < ISLAND_POINTS:
        return [], outliers
    xy = pts[outliers]
    label = point_clusters(xy, radius)
    small = (group_extents(xy, label) < SPECK_EXTENT * tolerance) & (
        np.bincount(label) >= ISLAND_POINTS)
    groups = [m for m in (np.flatnonzero(label == g) for g in np.flatnonzero(small))
              if _surrounds(*_about_centre(xy[m]), RIM)]
    if not groups:  # the clearance needs a tree of every point: only for groups that count
        return [], outliers
    # outliers within the radius of a group are in it, so the groups' own points suffice
    own_label = np.repeat(np.arange(len(groups)), [len(m) for m in groups])
    clear = _clear_groups(xy[np.concatenate(groups)], own_label, pts, radius)
    found = []
    for members in (m for m, ok in zip(groups, clear) if ok):
        ring = _hull_ring(xy[members], tolerance)
        if ring is not None:
            found.append(OrderedContour(ring, True, outliers[members]))
    if not found:
        return [], outliers
    return found, np.setdiff1d(outliers, np.concatenate([c.members for c in found]))


def _clear_groups(xy: FloatArray, label: IntArray, pts: FloatArray, radius: float
                  ) -> np.ndarray:
    """Whether each group of ``xy`` (by ``label``) is clear of the other ``pts`` by
    ``radius``: no point of it has a point within the radius that is not in ``xy``."""
    within = cKDTree(pts).query_ball_point(xy, radius, return_length=True)
    own = cKDTree(xy).query_ball_point(xy, radius, return_length=True)
    return np.bincount(label, weights=within > own, minlength=label.max() + 1) == 0


def _hull_ring(group: FloatArray, tolerance: float) -> FloatArray | None:
    """The convex hull of ``group`` as a counter-clockwise ring, if it has an area and every
    point lies within ``tolerance`` of its outline; else None."""
    hull = shapely.MultiPoint(group).convex_hull
    if hull.geom_type != "Polygon" or hull.area <= 0:
        return None
    if shapely.distance(shapely.points(group), hull.exterior).max() > tolerance:
        return None
    return np.asarray(shapely.orient_polygons(hull).exterior.coords)[:-1]


def _island(group: FloatArray, members: IntArray) -> OrderedContour | None:
    """The group as a ring about its centre, if it surrounds it and the ring is simple.

    The centre is that of the group's convex hull (its area centroid), not the points' mean,
    which leans toward a side sampled more densely: round a thin sliver whose long side held
    no point between its ends, that side spanned 136 degrees from the mean and 111 from the
    hull's centre. On an open arc the hull's centre lies nearer the chord than the mean does,
    so an arc is no more a loop than it was (a half circle: 134 degrees against 115).
    """
    angle, distance = _about_centre(group)
    if not _surrounds(angle, distance):
        return None
    ring = group[np.argsort(angle)]
    return OrderedContour(ring, True, np.sort(members)) if shapely.Polygon(ring).is_valid else None


def _about_centre(group: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Each point's angle and distance about the group's convex hull's centroid."""
    offset = group - np.asarray(shapely.MultiPoint(group).convex_hull.centroid.coords[0])
    return np.arctan2(offset[:, 1], offset[:, 0]), np.hypot(offset[:, 0], offset[:, 1])


def _surrounds(angle: FloatArray, distance: FloatArray, rim: float = 0.0) -> bool:
    """Whether no two points next in ``angle`` about the group's hull centre (`_island`,
    `_about_centre`) are more than `LOOP_GAP` apart: a loop, where an open stroke leaves two
    gaps of about 180. Only the points at least ``rim`` times the median ``distance`` from
    the centre count (a noisy straight dash has points all round the centre close to it)."""
    angle = np.sort(angle[distance >= rim * np.median(distance)])
    if len(angle) < 3:
        return False
    gaps = np.diff(np.concatenate([angle, [angle[0] + 2 * np.pi]]))
    return bool(np.degrees(gaps.max()) <= LOOP_GAP)
