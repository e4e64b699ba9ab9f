"""Links routed through a neck's walls, for necks shorter than the rings' nodes are apart.

A move between two rings (`necks`) links a cut end of one to a cut end of the other by a
straight line. Where the neck is about as long as the rings' nodes are apart (a tolerance
or two), its walls lie between the nodes: the links across its two mouths pass a wall's
width from them, and links along the walls leave the rings at the lobe's side. Routing each
link through the points beside it (`routed`) draws the walls. A routed link must run along
points all the way (`continuous`), not hop across the empty gap between two letters, and the
move must have points in the middle of the gap (`MidGap`): far from both rings with their
spikes and bulges taken off. Two shapes side by side have none there but their walls'
noise, which the band's width (a few times the rings' own scatter) leaves out.

References
----------
.. [1] J. Serra, *Image Analysis and Mathematical Morphology*, Academic Press, 1982 (the
   opening that takes off features narrower than a disk).
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.spatial import cKDTree

from ..geometry import polyline_distance
from ..types import FloatArray, OrderedContour

Links = tuple[tuple[FloatArray, FloatArray], ...]

#: A link is routed through the points beside it, their means every this many radii along
#: it: about the spacing of the ordering's nodes.
ROUTE_STEP = 0.5
#: A routed link runs along a wall where a point lies within this many radii of it every
#: half `ROUTE_STEP`: a wall sampled at random every third of a radius leaves a gap of a
#: radius now and then (1 in 20); the gap between two letters a radius apart is wider.
ROUTE_REACH = 0.5
#: The rings' spikes and bulges are taken off by an opening with a disk this many radii
#: across: the march's spike into a neck a radius wide or less.
OPENING = 1.0
#: A point is in the middle of the gap when it lies farther than this many radii from both
#: opened rings...
MID_BAND = 0.35
#: ... and farther than this many times the rings' scatter (the noise of two walls side by
#: side reaches into the gap between them: 2.5 standard deviations leaves 0.6 % of a wall's
#: points beyond)...
MID_SIGMAS = 2.5
#: ... and the move is borne out when such points number at least this share of what two
#: walls as long as its links hold.
MID_SHARE = 0.5
#: The median distance of Gaussian scatter to its curve, in standard deviations.
MEDIAN_TO_SIGMA = 0.674


def bridge_points(links: Links, tree: cKDTree, band: float) -> FloatArray:
    """The points inside the bridge between the two links (the region they bound with the
    cuts' chords) or within ``band`` of it; none where the bridge is not a valid polygon."""
    (a0, a1), (b0, b1) = links
    bridge = shapely.Polygon([a0, a1, b0, b1])
    if not bridge.is_valid or bridge.area == 0:
        return np.empty((0, 2))
    span = shapely.buffer(bridge, band)
    x0, y0, x1, y1 = span.bounds
    centre = np.array([(x0 + x1) / 2, (y0 + y1) / 2])
    near = tree.data[tree.query_ball_point(centre, float(np.hypot(x1 - x0, y1 - y0)) / 2)]
    return near[shapely.contains_xy(span, near[:, 0], near[:, 1])]


def kept_clear(near: FloatArray, rest: tuple[FloatArray, FloatArray], band: float
               ) -> FloatArray:
    """Which of the points ``near`` lie farther than ``band`` from both kept paths ``rest``
    (the rings' own walls, which the move keeps)."""
    at = shapely.points(near)
    return np.min([shapely.distance(at, shapely.linestrings(w)) for w in rest], axis=0,
                  initial=np.inf) > band


def routed(links: Links, rest: tuple[FloatArray, FloatArray], beside: FloatArray,
           radius: float) -> tuple[FloatArray, tuple[FloatArray, FloatArray]]:
    """The joined ring with each link routed through the points ``beside`` the links (those
    of the bridge clear of the kept paths ``rest``, `kept_clear`) nearer it than the other,
    their means every `ROUTE_STEP` radii along it; and the two routed links, each from its
    start to its end."""
    (a0, a1), (b0, b1) = links
    at = shapely.points(beside)
    to_a = shapely.distance(at, shapely.linestrings([a0, a1]))
    to_b = shapely.distance(at, shapely.linestrings([b0, b1]))
    route_a = _route(a0, a1, beside[to_a <= to_b], radius)
    route_b = _route(b0, b1, beside[to_b < to_a], radius)
    return (np.vstack([rest[0], route_a, rest[1], route_b]),
            (np.vstack([a0, route_a, a1]), np.vstack([b0, route_b, b1])))


def continuous(routes: tuple[FloatArray, FloatArray], tree: cKDTree, radius: float) -> bool:
    """Does each routed link have a point within `ROUTE_REACH` radii every `ROUTE_STEP` / 2
    radii along it: a wall all the way, not a hop across the empty gap between two shapes
    (letters a tolerance apart) or their walls' noise?"""
    for route in routes:
        line = shapely.linestrings(route)
        at = np.arange(0.0, line.length + 1e-12, ROUTE_STEP / 2 * radius)
        samples = shapely.get_coordinates(shapely.line_interpolate_point(line, at))
        gap, _ = tree.query(samples, distance_upper_bound=ROUTE_REACH * radius)
        if not np.all(np.isfinite(gap)):
            return False
    return True


def _route(start: FloatArray, end: FloatArray, beside: FloatArray, radius: float
           ) -> FloatArray:
    """Nodes between ``start`` and ``end`` through the points ``beside`` the line: their
    means every `ROUTE_STEP` radii along it (none where no point lies between the ends)."""
    u = end - start
    t = (beside - start) @ u / max(float(u @ u), 1e-300)
    inside = (t > 0) & (t < 1)
    if not np.any(inside):
        return np.empty((0, 2))
    step = ROUTE_STEP * radius / max(float(np.linalg.norm(u)), 1e-300)
    bins = np.floor(t[inside] / step).astype(np.intp)
    order, counts = np.unique(bins, return_counts=True)
    sums = np.zeros((len(order), 2))
    np.add.at(sums, np.searchsorted(order, bins), beside[inside])
    return sums / counts[:, None]


class MidGap:
    """The middle of the gap between two rings: the opened rings' outlines, and how far from
    them a point is in the middle (`MID_BAND` radii, or `MID_SIGMAS` x the rings' scatter:
    the median distance of their members to them, read every ``stride``-th)."""

    def __init__(self, rings: tuple[OrderedContour, OrderedContour], points: FloatArray,
                 radius: float, stride: int = 1):
        self.outlines = [_opened(ring.points, radius) for ring in rings]
        spread = np.concatenate([polyline_distance(points[ring.members[::stride]], ring.points,
                                                   True) for ring in rings])
        scatter = float(np.median(spread)) / MEDIAN_TO_SIGMA if len(spread) else 0.0
        self.band = max(MID_BAND * radius, MID_SIGMAS * scatter)

    def borne_out(self, links: Links, near: FloatArray, density: float) -> bool:
        """Do the points ``near`` the bridge (`bridge_points`) that lie in the middle of the
        gap number at least `MID_SHARE` of what two walls as long as the links hold at
        ``density`` points per length?"""
        if len(near) == 0:
            return False
        at = shapely.points(near)
        gap = np.min([shapely.distance(at, o) for o in self.outlines], axis=0,
                     initial=np.inf)
        needed = MID_SHARE * density * sum(float(np.linalg.norm(b - a)) for a, b in links)
        return bool(np.count_nonzero(gap > self.band) >= max(needed, 1.0))


def _opened(xy: FloatArray, radius: float) -> shapely.Geometry:
    """The outline of the ring's polygon opened by a disk `OPENING` radii across: without
    the spikes and bulges narrower than that (the ring's own where all of it is)."""
    half = OPENING / 2 * radius
    polygon = shapely.Polygon(xy)
    opened = shapely.buffer(shapely.buffer(polygon, -half), half)
    return shapely.boundary(polygon if opened.is_empty else opened)
