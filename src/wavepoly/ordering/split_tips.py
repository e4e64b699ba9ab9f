"""Tips closed apart: a slit's or a thin limb's tip that the march closed as a ring of its own.

Where a slit narrows, or a limb thins out, the march may follow the walls of the wide part each
on its own and turn back where they come within a radius or two (a hairpin of the outline),
while beyond it the narrow tip, its two walls merged into one chain, closes on itself as a thin
ring. The outline and the tip are one: the thin ring lies within `TIP_GAP` radii of the
hairpin and runs on the other way from it (`slits.runs_on_from_hairpin`). Joined across the gap
by the hull of their facing vertices, the boundary of the union (a limb's tip, outside the
outline) or of the difference (a slit's tip, inside it) is the one outline.
"""

from __future__ import annotations

import numpy as np
import shapely

from ..types import FloatArray, OrderedContour
from .slits import runs_on_from_hairpin

#: A tip ring lies within this many radii of its outline's hairpin: the march stops up to
#: 2.3 radii short of a narrowing slit (as `piece_graph.T_REACH`).
TIP_GAP = 3.0
#: A tip ring is thin: its mean width (twice its area over its perimeter) is at most this
#: many radii, two walls the march followed as one chain, or a limb's tip as narrow.
TIP_WIDTH = 2.0
#: The bridge spans the vertices of each ring within this many radii of the gap's ends.
BRIDGE_REACH = 1.0
#: ... padded by this many radii (a twentieth of the tolerance: no shape to speak of).
BRIDGE_PAD = 0.05


def rejoin_split_tips(contours: list[OrderedContour], radius: float) -> list[OrderedContour]:
    """The contours, each thin closed ring that is the tip of a closed outline joined to it.

    Parameters
    ----------
    contours : the ordered contours; only the closed ones are read.
    radius : the neighbourhood radius of the ordering.
    """
    rings = [k for k, c in enumerate(contours) if c.closed]
    if len(rings) < 2:
        return contours
    out: list[OrderedContour | None] = list(contours)
    lines = [shapely.LinearRing(contours[k].points) for k in rings]
    tree = shapely.STRtree(lines)
    for i in np.argsort([len(contours[k].points) for k in rings], kind="stable"):
        b = rings[i]
        if out[b] is None or not _thin(out[b].points, radius):
            continue
        near = [j for j in tree.query(lines[i], predicate="dwithin",
                                      distance=TIP_GAP * radius)
                if j != i and out[rings[j]] is not None]
        for j in sorted(near, key=lambda j: shapely.distance(lines[i], lines[j])):
            joined = _joined(out[rings[j]], out[b], radius)
            if joined is not None:
                out[rings[j]], out[b] = joined, None
                lines[j] = shapely.LinearRing(joined.points)  # an outline grows by its tip
                tree = shapely.STRtree(lines)
                break
    return [c for c in out if c is not None]


def _thin(xy: FloatArray, radius: float) -> bool:
    """Whether a ring's mean width is at most `TIP_WIDTH` radii."""
    ring = _polygon(xy)
    return ring is not None and 2 * ring.area <= TIP_WIDTH * radius * ring.length


def _polygon(xy: FloatArray) -> shapely.Polygon | None:
    """The ring's polygon, without the folds of no width where its chain runs out and back
    along one line (the march's zigzag in a thin part); None where it crosses itself."""
    ring = shapely.Polygon(xy)
    if ring.is_valid:
        return ring
    parts = [g for g in shapely.get_parts(shapely.make_valid(ring)) if g.area > 0]
    return parts[0] if len(parts) == 1 and parts[0].geom_type == "Polygon" else None


def _joined(outline: OrderedContour, tip: OrderedContour, radius: float
            ) -> OrderedContour | None:
    """The outline with the tip joined at its hairpin, or None where the tip does not run on
    from a hairpin of the outline, or the join is no simple polygon."""
    a_xy, b_xy = outline.points, tip.points
    pa, pb = (np.asarray(p) for p in shapely.shortest_line(
        shapely.LinearRing(a_xy), shapely.LinearRing(b_xy)).coords)
    ia = int(np.argmin(np.linalg.norm(a_xy - pa, axis=1)))
    n = len(a_xy)
    ahead, back = a_xy[(ia + np.arange(n)) % n], a_xy[(ia - np.arange(n)) % n]
    far = b_xy[np.argmax(np.linalg.norm(b_xy - pb, axis=1))]
    if not runs_on_from_hairpin(back, ahead, np.array([a_xy[ia], far]), radius):
        return None
    a_poly, b_poly = _polygon(a_xy), _polygon(b_xy)
    if a_poly is None or b_poly is None:  # the fit's selection may yet make it valid
        return None
    reach = BRIDGE_REACH * radius
    ends = np.vstack([pa, pb, a_xy[np.linalg.norm(a_xy - pa, axis=1) <= reach],
                      b_xy[np.linalg.norm(b_xy - pb, axis=1) <= reach]])
    # padded, so that it overlaps each ring rather than touching it at a point
    bridge = shapely.MultiPoint(ends).convex_hull.buffer(BRIDGE_PAD * radius, join_style="mitre")
    if not isinstance(bridge, shapely.Polygon):
        return None
    if a_poly.contains(b_poly):  # a slit's tip: cut out of the outline
        region = a_poly.difference(shapely.union(b_poly, bridge))
    else:  # a limb's tip: added to it
        region = shapely.union_all([a_poly, b_poly, bridge])
    if not isinstance(region, shapely.Polygon) or region.interiors or not region.is_valid:
        return None
    xy = np.asarray(region.exterior.coords)[:-1]
    members = np.union1d(outline.members, tip.members)
    return OrderedContour(xy, True, members)
