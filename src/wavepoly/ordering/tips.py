"""Tips the march stopped short of: a closed contour's notch or spike carried out to its end.

Where two walls of a closed outline converge (the waist of a 'B' or a serif '8', a
tentacle's tip), the neighbourhoods span both walls for the last few radii, and the march
turns back before the end. What is left beyond the turn is a small group of points: outliers,
a short open stroke or a little loop of its own. A group that lies beyond a sharp turn of a
closed contour, along the turn's bisector, is that contour's tip: the turn's vertex moves out
to the group's farthest point, and the group's points become members of the contour.

A loop must span less than `TIP_STROKE` radii: a larger one is a contour of its own (the
issue's "a loop or a stroke of at least 4 tolerances is a contour"). An open stroke may span up
to `TIP_OPEN` radii: a clean outline has no open piece of its own, and a longer spike's or
slit's tip, its walls merged into one chain, is left as such a stroke. A T junction's stem
meets a straight stretch, not a sharp turn. Outlines that the later passes close (`stems`,
`gaps`, `mouths`) take the strokes left beyond their turns too.
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.spatial import cKDTree

from ..geometry import curve_line, nearest_segment
from ..types import FloatArray, IntArray, OrderedContour
from .joining import runs_along_points
from .marching import turning
from .neighbourhoods import point_clusters

#: A tip's vertex turns by at least this (degrees, between the chords two vertices away; the
#: rounded tip of the 'B' waist, a 40 degree wedge, turns by 98 there). A group beyond a
#: lesser corner is a corner the march cut, and moving the vertex out to it is right too.
TIP_TURN = 60.0
#: The group lies within this angle (degrees) of the turn's outward bisector.
TIP_CONE = 45.0
#: ... and its nearest point within this many radii of the vertex.
TIP_REACH = 3.0
#: Groups of fewer points are strays, not a tip.
TIP_GROUP = 3
#: The moved tip keeps this many radii from every other contour: each polygon may lie up to
#: a tolerance from its contour, and two could meet nearer (a laser map's thick wall, whose
#: tip reached over to the next wall, was then split at the crossing).
TIP_CLEARANCE = 2.0
#: Loops spanning this many radii are contours of their own, never a tip (a hoof beside a
#: leg's turn; the sliver ring beside Keyboard0's doubled end wall stays a ring).
TIP_STROKE = 4.0
#: Open strokes spanning this many radii are contours of their own. A shorter one beyond a
#: sharp turn is the rest of a spike or slit narrower than the radius, its two walls merged
#: into one chain (7.2 and 8.0 radii on a bitmap silhouette's spike and a horse's tail slit);
#: a ring takes one only where it then covers it within the gap (straight along the bisector).
TIP_OPEN = 12.0


def extend_tips(contours: list[OrderedContour], outliers: IntArray, pts: FloatArray,
                radius: float, gap: float) -> tuple[list[OrderedContour], IntArray]:
    """Closed contours carried out to the groups of points beyond their sharp turns.

    The groups are clusters of ``outliers`` (points within a radius of each other) and the
    members of small contours, open or closed. A group is taken when it lies beyond a vertex
    that turns by `TIP_TURN`, within `TIP_CONE` of the turn's bisector and `TIP_REACH` radii of the
    vertex, and when the contour with the vertex moved to the group's farthest point is still a
    simple polygon with the group and its own members within ``gap`` of it, and the way from
    the vertex to the group runs along points (`joining.runs_along_points`: a notch's merged
    walls run on to its tip, a speck beside the turn lies across empty space); else, a group off
    the bisector is joined by its hull (`_tip_hull`). Each sharp vertex near a group is
    tried, the sharpest first. For clean scans (`contours.CLEAN_NOISE`), where a group is
    real shape: on a noisy laser map it may be clutter by a corner (Freiburg lost a closed
    room and gained pieces when its tips were taken).

    Returns the contours (a taken stroke or loop removed) and the remaining outliers.
    """
    small = [_extent(c.points) < (TIP_STROKE if c.closed else TIP_OPEN) * radius
             for c in contours]
    # only outlines that are no group themselves take a tip: no point is passed on twice
    rings = [k for k, c in enumerate(contours) if c.closed and len(c.points) >= 4
             and not small[k]]
    if not rings:
        return contours, outliers
    groups = [(g, -1) for g in _outlier_groups(outliers, pts, radius)] + [
        (c.members, k) for k, c in enumerate(contours)
        if small[k] and len(c.members) >= TIP_GROUP]
    contours = list(contours)
    lines = shapely.STRtree([curve_line(c.points, c.closed) for c in contours])
    turns = {k: turning(contours[k].points, True) for k in rings}
    boxes = _Boxes(contours, rings)
    tree = cKDTree(pts) if groups else None
    taken: list[IntArray] = []
    dropped: set[int] = set()
    for group, stroke in groups:
        xy = pts[group]
        for k, v in _tip_candidates(contours, boxes.near(xy, TIP_REACH * radius), turns, xy,
                                    radius):
            vertex = contours[k].points[v]
            nearest = xy[np.argmin(np.linalg.norm(xy - vertex, axis=1))]
            if not runs_along_points(tree, vertex[None], nearest[None], radius)[0]:
                continue  # across empty space: a shape of its own (a speck by the turn)
            new_xy = _tip_moved(contours[k], v, xy, pts, gap)
            if new_xy is None:
                new_xy = _tip_hull(contours[k], xy, pts, radius, gap)
            if new_xy is None:
                continue
            change = shapely.Polygon(new_xy).symmetric_difference(
                shapely.Polygon(contours[k].points)).boundary
            near = lines.query(change, predicate="dwithin", distance=TIP_CLEARANCE * radius)
            if set(near.tolist()) - {k, stroke}:
                continue  # the polygons of the two could meet
            contours[k] = OrderedContour(new_xy, True, np.union1d(contours[k].members, group))
            turns[k] = turning(new_xy, True)
            boxes.update(k, new_xy)
            taken.append(group)
            dropped.add(stroke)
            break
    if not taken:
        return contours, outliers
    contours = [c for k, c in enumerate(contours) if k not in dropped]
    return contours, np.setdiff1d(outliers, np.concatenate(taken))


class _Boxes:
    """The boxes around the rings that may take a tip, so that each group looks only at the
    rings whose box comes within its reach (a noisy band read exactly: 1927 groups against
    some 600 rings, 8.6 s of 43 s in testing every ring's points)."""

    def __init__(self, contours: list[OrderedContour], rings: list[int]) -> None:
        self.rings = np.asarray(rings, dtype=np.intp)
        self.at = {k: i for i, k in enumerate(rings)}
        self.lo = np.array([contours[k].points.min(axis=0) for k in rings])
        self.hi = np.array([contours[k].points.max(axis=0) for k in rings])

    def near(self, group: FloatArray, reach: float) -> list[int]:
        """The rings whose box comes within ``reach`` of the box around ``group``."""
        lo, hi = _reach_box(group, reach)
        overlap = ((self.hi >= lo) & (self.lo <= hi)).all(axis=1)
        return self.rings[overlap].tolist()

    def update(self, k: int, ring: FloatArray) -> None:
        """Ring ``k`` now runs along ``ring``."""
        self.lo[self.at[k]], self.hi[self.at[k]] = ring.min(axis=0), ring.max(axis=0)


def _tip_candidates(contours: list[OrderedContour], rings: list[int],
                    turns: dict[int, FloatArray], group: FloatArray, radius: float
                    ) -> list[tuple[int, int]]:
    """The closed contours' vertices within `TIP_REACH` radii of ``group`` that turn by at
    least `TIP_TURN` (``turns``: each ring's turning angles), the sharpest first (a rounded
    tip spreads its turn over a few)."""
    found: list[tuple[float, int, int]] = []
    reach = TIP_REACH * radius
    lo, hi = _reach_box(group, reach)
    tree = cKDTree(group)
    for k in rings:
        ring = contours[k].points
        inside = np.flatnonzero(((ring >= lo) & (ring <= hi)).all(axis=1))
        if not len(inside):
            continue
        near = inside[tree.query(ring[inside], distance_upper_bound=reach)[0] <= reach]
        angle = turns[k][near]
        found += [(float(a), k, int(v)) for a, v in zip(angle, near) if a >= TIP_TURN]
    return [(k, v) for _, k, v in sorted(found, reverse=True)]


def _reach_box(group: FloatArray, reach: float) -> tuple[FloatArray, FloatArray]:
    """The corners of the box around ``group`` grown by ``reach``."""
    return group.min(axis=0) - reach, group.max(axis=0) + reach


def _outlier_groups(outliers: IntArray, pts: FloatArray, radius: float) -> list[IntArray]:
    """Clusters of at least `TIP_GROUP` outliers, each point within a radius of another."""
    if len(outliers) < TIP_GROUP:
        return []
    label = point_clusters(pts[outliers], radius)
    sizes = np.bincount(label)
    return [outliers[label == g] for g in np.flatnonzero(sizes >= TIP_GROUP)]


def _extent(xy: FloatArray) -> float:
    """Diagonal of the box around ``xy``."""
    return float(np.linalg.norm(xy.max(axis=0) - xy.min(axis=0)))


def _extended(ring: FloatArray, v: int, group: FloatArray) -> FloatArray | None:
    """The ring with vertex ``v`` moved to the point of ``group`` farthest beyond it, if ``v``
    is a sharp turn and the group lies along its outward bisector; else None."""
    n = len(ring)
    before, after = ring[(v - 2) % n], ring[(v + 2) % n]
    outward = _unit(ring[v] - before) + _unit(ring[v] - after)
    if np.linalg.norm(outward) == 0:
        return None
    outward = _unit(outward)
    towards = group.mean(axis=0) - ring[v]
    if np.linalg.norm(towards) == 0:
        return None
    if float(_unit(towards) @ outward) < np.cos(np.radians(TIP_CONE)):
        return None
    far = group[np.argmax((group - ring[v]) @ outward)]
    if float((far - ring[v]) @ outward) <= 0:
        return None
    new = ring.copy()
    new[v] = far
    return new if shapely.Polygon(new).is_valid else None


def _tip_moved(ring: OrderedContour, v: int, group: FloatArray, pts: FloatArray, gap: float
               ) -> FloatArray | None:
    """The ring's points with the tip ``v`` moved out to ``group`` (`_extended`), if the ring
    then still covers its members and the group within ``gap``."""
    new_xy = _extended(ring.points, v, group)
    if new_xy is None or not _covers(new_xy, ring.points, pts[ring.members], group, gap):
        return None
    return new_xy


def _tip_hull(ring: OrderedContour, group: FloatArray, pts: FloatArray, radius: float,
              gap: float) -> FloatArray | None:
    """The ring's polygon joined with the convex hull of ``group`` and the ring's vertices
    within a radius of it (a spike whose end the march closed into a little loop of its own),
    or that hull cut out of it (the same at a notch), if the result is one simple polygon that
    still covers the ring's members and the group within ``gap``."""
    near = np.flatnonzero(cKDTree(group).query(ring.points, distance_upper_bound=radius)[0]
                          <= radius)
    if not len(near):
        return None
    hull = shapely.MultiPoint(np.vstack([group, ring.points[near]])).convex_hull
    poly = shapely.Polygon(ring.points)
    if not poly.is_valid or hull.area <= 0:
        return None
    # a spike of the shape is joined to it; a notch into it (the hull mostly inside) cut out
    inside = poly.intersection(hull).area > 0.5 * hull.area
    union = poly.difference(hull) if inside else shapely.union(poly, hull)
    if union.geom_type != "Polygon" or len(union.interiors) or not union.is_valid:
        return None
    new_xy = np.asarray(union.exterior.coords)[:-1]
    if union.exterior.is_ccw != shapely.LinearRing(ring.points).is_ccw:
        new_xy = new_xy[::-1]
    if not _covers(new_xy, ring.points, pts[ring.members], group, gap):
        return None
    return new_xy


def _covers(ring: FloatArray, old: FloatArray, members: FloatArray, group: FloatArray,
            gap: float) -> bool:
    """Do the ring's own members and the group all lie within ``gap`` of the ``ring`` that
    replaces ``old``? Only members near where the two differ can have moved away from it
    (the others' nearest edges are kept), so only they are measured."""
    box = np.vstack([_changed(ring, old), _changed(old, ring), group])
    lo, hi = box.min(axis=0) - 2 * gap, box.max(axis=0) + 2 * gap
    near = members[((members >= lo) & (members <= hi)).all(axis=1)]
    pts = np.vstack([near, group])
    return bool(nearest_segment(pts, ring, True)[1].max(initial=0.0) <= gap)


def _changed(ring: FloatArray, other: FloatArray) -> FloatArray:
    """The vertices of ``ring`` that ``other`` lacks, with their neighbours on the ring."""
    new = ~np.isin(ring[:, 0] + 1j * ring[:, 1], other[:, 0] + 1j * other[:, 1])
    return ring[new | np.roll(new, 1) | np.roll(new, -1)]


def _unit(v: FloatArray) -> FloatArray:
    n = float(np.linalg.norm(v))
    return v / n if n > 0 else v
