"""Tips closed apart: a slit's or a thin limb's tip that the march closed as a ring of its own.

Where a slit narrows, or a limb thins out, the march may follow the walls of the wide part each
on its own and turn back where they come within a radius or two (a hairpin of the outline),
while beyond it the narrow tip, its two walls merged into one chain, closes on itself as a thin
ring. The outline and the tip are one: the thin ring lies within `TIP_GAP` radii of the
hairpin and runs on the other way from it (`slits.runs_on_from_hairpin`). Joined across the gap
by the hull of their facing vertices, the boundary of the union (a limb's tip, outside the
outline) or of the difference (a slit's tip, inside it) is the one outline.

A slit may also run into a hole (a keyhole): the march leaves the slit's end a radius or so
from the hole, and the outline and the hole come out as two rings. A hole within
`KEYHOLE_GAP` radii of the outline, where either ring turns back at a hairpin pointing at the
other and the slit's walls run on across the gap (its points lie there), is cut out of the
outline the same way. A hole by a smooth wall (a thin wall of the shape) has no hairpin there,
and one facing a notch across solid wall (a glyph's counter by its neck) no points between:
both stay holes.
"""

from __future__ import annotations

import numpy as np
import shapely

from ..geometry import along_and_across
from ..types import FloatArray, OrderedContour
from .slits import runs_on_from_hairpin

#: A tip ring lies within this many radii of its outline's hairpin: the march stops up to
#: 2.3 radii short of a narrowing slit (as `piece_graph.T_REACH`).
TIP_GAP = 3.0
#: A ring that is no thin tip joins its outline only as a hole a slit reaches: within this
#: many radii of it, where the march leaves the slit's end by the hole (0.7-1.1 radii on the
#: silhouettes' keyholes). A slit that stops farther from a hole is a slit of its own.
KEYHOLE_GAP = 1.5
#: ... and the slit's walls run on across the gap: at least this many points lie across its
#: middle half (one per wall; the keyholes held 2-5, and a glyph's counter facing the notch
#: of its neck across 1.4 radii of solid stroke, 'g' at a tolerance of 0.3, none).
KEYHOLE_WALLS = 2
#: A tip ring farther than this many radii from the outline's hairpin joins it only where
#: the walls run on across the gap: at least one point lies across its middle half. The
#: silhouettes' tips lie up to 1.4 radii off, most with one to seven points across, some with
#: none (gaps of 0.5 and 1.04 radii, where the line between the rings crosses the slit). A
#: round dot 2.5 radii beyond a stroke's end with nothing between (a '?' at ε 4 % of its
#: height) is a ring of its own; so, wrongly, is a ball terminal the march left as far from
#: its stroke (Computer Modern's 'a' at that tolerance).
TIP_BARE_GAP = 1.5
#: A tip ring is thin: its mean width (twice its area over its perimeter) is at most this
#: many radii, two walls the march followed as one chain, or a limb's tip as narrow.
TIP_WIDTH = 2.0
#: The bridge spans the vertices of each ring within this many radii of the gap's ends.
BRIDGE_REACH = 1.0
#: ... padded by this many radii (a twentieth of the tolerance: no shape to speak of).
BRIDGE_PAD = 0.05


def rejoin_split_tips(contours: list[OrderedContour], radius: float,
                      points: FloatArray | None = None) -> list[OrderedContour]:
    """The contours, each thin closed ring that is the tip of a closed outline joined to it,
    and each hole that a slit reaches cut into it as a keyhole.

    Parameters
    ----------
    contours : the ordered contours; only the closed ones are read.
    radius : the neighbourhood radius of the ordering.
    points : the input points, which the contours' members index: the walls of a slit that
        reaches a hole run on across the gap between them (`KEYHOLE_WALLS`), and so do a
        tip's across a gap wider than `TIP_BARE_GAP`. Without them no hole is joined, and a
        tip across any gap up to `TIP_GAP`.
    """
    rings = [k for k, c in enumerate(contours) if c.closed]
    if len(rings) < 2:
        return contours
    out: list[OrderedContour | None] = list(contours)
    lines = [shapely.LinearRing(contours[k].points) for k in rings]
    tree = shapely.STRtree(lines)
    for i in np.argsort([len(contours[k].points) for k in rings], kind="stable"):
        b = rings[i]
        if out[b] is None:
            continue
        hole = not thin_ring(out[b].points, radius)  # a hole a slit may reach, else a tip
        if hole and points is None:
            continue
        near = [j for j in tree.query(lines[i], predicate="dwithin",
                                      distance=(KEYHOLE_GAP if hole else TIP_GAP) * radius)
                if j != i and out[rings[j]] is not None]
        for j in sorted(near, key=lambda j: shapely.distance(lines[i], lines[j])):
            joined = _joined(out[rings[j]], out[b], radius, points, hole)
            if joined is not None:
                out[rings[j]], out[b] = joined, None
                lines[j] = shapely.LinearRing(joined.points)  # an outline grows by its tip
                tree = shapely.STRtree(lines)
                break
    return [c for c in out if c is not None]


def thin_ring(xy: FloatArray, radius: float) -> bool:
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


def _joined(outline: OrderedContour, tip: OrderedContour, radius: float,
            points: FloatArray | None = None, hole: bool = False) -> OrderedContour | None:
    """The outline with the tip joined at its hairpin, or None where the tip does not run on
    from a hairpin of the outline, the walls do not run on across a gap wider than
    `TIP_BARE_GAP` (``points``: the input points; without them, not asked), or the join is
    no simple polygon. A ``hole`` (no thin tip; ``points`` needed) joins only inside the
    outline, where the outline's hairpin (a slit's end) or its own (the hole's end of the
    slit) points at the other across the gap, and the slit's walls run on across it
    (`_walls_across`)."""
    a_xy, b_xy = outline.points, tip.points
    pa, pb = (np.asarray(p) for p in shapely.shortest_line(
        shapely.LinearRing(a_xy), shapely.LinearRing(b_xy)).coords)
    far = b_xy[np.argmax(np.linalg.norm(b_xy - pb, axis=1))]
    a_poly, b_poly = _polygon(a_xy), _polygon(b_xy)
    if a_poly is None or b_poly is None:  # the fit's selection may yet make it valid
        return None
    if hole:
        if (points is None or not a_poly.contains(b_poly)
                or not (_hairpin_at(a_xy, pa, pb, radius) or _hairpin_at(b_xy, pb, pa, radius))
                or _walls_across(points[np.union1d(outline.members, tip.members)], pa, pb,
                                 radius) < KEYHOLE_WALLS):
            return None
    elif not _hairpin_at(a_xy, pa, far, radius):
        return None
    elif (points is not None and np.linalg.norm(pb - pa) > TIP_BARE_GAP * radius
          and _walls_across(points, pa, pb, radius) == 0):
        return None  # nothing between: a dot beyond a stroke's end
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


def _walls_across(points: FloatArray, a: FloatArray, b: FloatArray, radius: float) -> int:
    """How many points lie across the middle half of the gap from ``a`` to ``b``, within a
    radius of the line through them."""
    length = float(np.linalg.norm(b - a))
    if length == 0:
        return 0
    along, across = along_and_across(points, a, b)
    return int(((along > 0.25 * length) & (along < 0.75 * length) & (across <= radius)).sum())


def _hairpin_at(xy: FloatArray, at: FloatArray, towards: FloatArray, radius: float) -> bool:
    """Whether the ring turns back at its vertex nearest ``at`` with the line on to
    ``towards`` running between its arms (`slits.runs_on_from_hairpin`)."""
    i = int(np.argmin(np.linalg.norm(xy - at, axis=1)))
    n = len(xy)
    ahead, back = xy[(i + np.arange(n)) % n], xy[(i - np.arange(n)) % n]
    return runs_on_from_hairpin(back, ahead, np.array([xy[i], towards]), radius)
