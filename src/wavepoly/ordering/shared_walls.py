"""Two rings that share a thin wall: three pieces between two junctions (a theta).

Where a hole comes closer to its outline than the radius (a thin wall between them), or two
shapes lie closer than the radius along a stretch (a thin gap), the neighbourhoods span both
walls there and the march follows them as one chain. The outline runs into that chain at one
end and out at the other, and so does the other ring: three pieces between the same two
junctions, which no walk of one cycle can draw (`wavepoly.ordering.stems`), so they stayed
open pieces.

The piece that holds the two walls, twice the points per length of the others
(`SHARED_DENSITY`), tells which reading the points make:

- on the outline of the region the three bound, it is a thin wall between the outside and a
  hole: the body is the face the other two pieces bound, with the wall's strip added, one
  outline and one hole;
- between the two faces, it is a thin gap between two shapes: each face, with the gap's
  strip taken out, is an outline of its own.

The strip is the shared piece widened by its walls' measured half-width
(`wavepoly.ordering.passes.half_widths`), so the two rings stay apart. Set operations (GEOS)
keep each ring simple. Where a hole's corner comes that close, its points along the merged
stretch are too few to double the wall's: there the shared piece is the one far shorter than
the others (`SHORT_SHARE`); where it is shorter than the junctions' reach, the two junctions
are one and the theta a figure eight, two loops at one node, each a ring of its own.
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.spatial import cKDTree

from ..geometry import polyline_distance, polyline_length
from ..types import FloatArray
from .faces import COVER_REACH, MERGE_VERTICES, SLIVER_AREA
from .passes import half_widths, left_normals
from .piece_graph import Edge

#: The two rings share at most this share of either one's length (within a radius of the
#: other): a hole's side along its outline's wall is a quarter of the hole or less, while a
#: wavy wall of the turbine blade's root, which the march followed as two chains side by side,
#: gave an outline and a "hole" a third of a radius inside it all the way round.
SIDE_BY_SIDE = 0.5
#: A piece's midpoints lie on a face's outline within this share of the radius.
ON_FACE = 1e-6
#: Pieces are measured this many radii or more from the junctions, where the walls part...
JUNCTION_REACH = 1.0
#: ... in stretches this many radii long (some 6 points on one wall sampled at 3 per radius)...
DENSITY_BIN = 2.0
#: ... and the shared piece holds at least this many times the points per length of each other
#: piece over its denser half: two walls merged hold twice as many, but where a hole's side
#: slants along the outline's wall they merge over part of the piece (its denser half held
#: 1.30 x; a stem of one cycle must hold 1.5 x, `wavepoly.ordering.slits.STEM_DENSITY`).
SHARED_DENSITY = 1.25
#: A piece at most this share of the length of each other one is the shared one: where a
#: hole's corner comes within the radius of its outline, the merged stretch is a few radii
#: (3.9, against 45 of the hole's other sides: 0.09; stress sweep, a square hole by an
#: ellipse's wall). Where two shapes overlap by less than the radius, the march's chord
#: across the stretch where they meet is longer (0.23: scikit-image's random shapes, seed
#: 14, one outline that this read as two)...
SHORT_SHARE = 0.15
#: ... and holds at least this share of the points per length of each other one: a wall runs
#: along it, not a bare chord (the hole's corner: 0.67 over the denser half).
SHORT_DENSITY = 0.5


def theta_rings(comp: list[int], edges: list[Edge], members: FloatArray, radius: float
                ) -> list[FloatArray] | None:
    """The two rings of a component of three pieces between two junctions, one of which holds
    two walls, or None.

    Parameters
    ----------
    comp : the component's edges (indices into ``edges``).
    edges : the pieces of the graph (`wavepoly.ordering.piece_graph.Edge`).
    members : the points of the component's pieces.
    radius : the neighbourhood radius of the ordering.

    Returns
    -------
    Two rings ((M, 2) vertices, not repeating the first): an outline and its hole, or two
    outlines; None where the component is no theta (nor a figure eight: two loops at one
    junction, `_figure_eight`), no piece is the shared one (`_two_walls`), or the rings are
    not simple, touch, or leave a member farther than `COVER_REACH` radii.

    Examples
    --------
    A square hole whose left wall runs 0.4 radii inside the outline's (both 0.2 radii off the
    chain the march followed between them).

    >>> from wavepoly.ordering.piece_graph import Edge
    >>> t = np.linspace(0.0, 1.0, 41)[:, None]
    >>> wall = [0.0, 0.2] + t * [0.0, 0.6]
    >>> outer = np.vstack([[0.0, 0.2], [0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0],
    ...                    [0.0, 0.8]])
    >>> hole = np.array([[0.0, 0.2], [0.5, 0.2], [0.5, 0.8], [0.0, 0.8]])
    >>> pieces = [Edge(outer, 0, 1, 0), Edge(wall, 0, 1, 1), Edge(hole, 0, 1, 2)]
    >>> along = lambda xy, n: np.vstack([a + np.linspace(0, 1, n, endpoint=False)[:, None]
    ...                                  * (b - a) for a, b in zip(xy[:-1], xy[1:])])
    >>> pts = np.vstack([along(outer, 20), along(hole, 20), wall + [0.01, 0.0],
    ...                  wall - [0.01, 0.0]])
    >>> rings = theta_rings([0, 1, 2], pieces, pts, 0.05)
    >>> [round(abs(shapely.Polygon(r).area), 3) for r in rings]
    [1.006, 0.294]
    """
    if len({frozenset((edges[k].start, edges[k].end)) for k in comp}) != 1:
        return None
    lines = [edges[k].xy for k in comp]
    if len(comp) == 2 and edges[comp[0]].start == edges[comp[0]].end:
        return _figure_eight(lines, members, radius)
    if len(comp) != 3 or edges[comp[0]].start == edges[comp[0]].end:
        return None
    shared = _two_walls(lines, members, radius)
    if shared is None:
        return None
    try:
        rings = _rings(lines, shared, members, radius)
    except shapely.errors.GEOSException:
        return None
    if rings is None or not _covers(rings, members, radius) or _side_by_side(rings, radius):
        return None
    return rings


def _figure_eight(loops: list[FloatArray], members: FloatArray, radius: float
                  ) -> list[FloatArray] | None:
    """Two loops from one junction back to it as two rings, each without the junction, so
    that they do not touch: where the shared stretch is shorter than the junctions' reach
    (`wavepoly.ordering.piece_graph.END_REACH`), its two junctions are one, and the theta a
    figure eight."""
    rings = [xy[1:-1] for xy in loops]
    if any(len(r) < 3 or not shapely.Polygon(r).is_valid for r in rings):
        return None
    if shapely.intersects(shapely.LinearRing(rings[0]), shapely.LinearRing(rings[1])):
        return None
    return rings if _covers(rings, members, radius) else None


def _two_walls(lines: list[FloatArray], members: FloatArray, radius: float) -> int | None:
    """The piece that holds `SHARED_DENSITY` x the points per length of each other one; else
    one at most `SHORT_SHARE` as long as each other one, with a wall along it
    (`SHORT_DENSITY`: a hole's corner that comes within the radius of its outline's wall
    merges with it for a radius or two, where the hole's points are too few to double the
    wall's); else None."""
    density = np.array([_density(xy, members, radius) for xy in lines])
    best = int(np.argmax(density))
    if density[best] >= SHARED_DENSITY * np.delete(density, best).max():
        return best
    length = np.array([polyline_length(xy, False) for xy in lines])
    short = int(np.argmin(length))
    if length[short] > SHORT_SHARE * np.delete(length, short).min():
        return None
    return short if density[short] >= SHORT_DENSITY * np.delete(density, short).max() else None


def _density(xy: FloatArray, members: FloatArray, radius: float) -> float:
    """Members per length within a radius across a piece's stretch `JUNCTION_REACH` radii or
    more from its ends (the whole piece where that stretch is shorter than a radius), over
    the denser half of its stretches `DENSITY_BIN` radii long: where a hole's side runs
    along the outline's wall at a slant, the two walls merge over part of the piece only."""
    ends = shapely.points(xy[[0, -1]])
    away = np.min(shapely.distance(shapely.points(xy)[:, None], ends[None, :]), axis=1)
    inner = xy[away > JUNCTION_REACH * radius]
    line = shapely.LineString(inner if len(inner) >= 2 and shapely.LineString(inner).length
                              >= radius else xy)
    at = shapely.line_locate_point(line, shapely.points(members))
    across = shapely.distance(line, shapely.points(members))
    inside = (at > 0.0) & (at < line.length) & (across <= radius)
    bins = max(int(line.length // (DENSITY_BIN * radius)), 1)
    counts = np.sort(np.bincount(np.minimum((at[inside] / line.length * bins).astype(int),
                                            bins - 1), minlength=bins))[::-1]
    denser = counts[:max(bins // 2, 1)]
    return float(denser.sum()) / (line.length * len(denser) / bins)


def _rings(lines: list[FloatArray], shared: int, members: FloatArray, radius: float
           ) -> list[FloatArray] | None:
    """The two rings the faces make with the shared piece's strip added or taken out."""
    faces = [f for f in shapely.get_parts(shapely.polygonize(shapely.get_parts(shapely.node(
        shapely.MultiLineString(lines))))) if f.area > SLIVER_AREA * radius**2]
    if len(faces) != 2:  # slivers left out: where two pieces cross by a junction
        return None
    wall = shapely.LineString(lines[shared])
    strip = wall.buffer(_half_width(lines[shared], members, radius), cap_style="square",
                        join_style="mitre")
    middle = shapely.line_interpolate_point(wall, 0.5, normalized=True)
    bounded_by_wall = [shapely.distance(middle, f.exterior) <= ON_FACE * radius for f in faces]
    if all(bounded_by_wall):  # a thin gap between two shapes
        parts = [_one_polygon(f.difference(strip)) for f in faces]
        if any(p is None or p.interiors for p in parts):
            return None
        rings = [p.exterior for p in parts]
        if shapely.intersects(parts[0], parts[1]):
            return None
    elif any(bounded_by_wall):  # a thin wall between the outside and a hole
        body = _one_polygon(faces[bounded_by_wall.index(False)].union(strip))
        if body is None or len(body.interiors) != 1:
            return None
        rings = [body.exterior, body.interiors[0]]
    else:
        return None
    out = [np.asarray(shapely.remove_repeated_points(r, MERGE_VERTICES * radius).coords)[:-1]
           for r in rings]
    if any(len(r) < 3 or not shapely.Polygon(r).is_valid for r in out):
        return None
    return out


def _half_width(wall: FloatArray, members: FloatArray, radius: float) -> float:
    """The median half-width between the two walls along the shared piece."""
    normal = left_normals(wall)
    return float(np.median(half_widths(wall, normal, cKDTree(members), radius)))


def _one_polygon(region: shapely.Geometry) -> shapely.Polygon | None:
    """The region where it is one valid polygon, else None."""
    return region if region.geom_type == "Polygon" and region.is_valid else None


def _side_by_side(rings: list[FloatArray], radius: float) -> bool:
    """Whether more than `SIDE_BY_SIDE` of either ring runs within a radius of the other: one
    outline drawn twice, not two rings that share a stretch of wall."""
    one, two = (shapely.LinearRing(r) for r in rings)
    return any(shapely.intersection(a, b.buffer(radius)).length > SIDE_BY_SIDE * a.length
               for a, b in ((one, two), (two, one)))


def _covers(rings: list[FloatArray], members: FloatArray, radius: float) -> bool:
    """Whether every member lies within `COVER_REACH` radii of a ring."""
    nearest = np.min([polyline_distance(members, r, True) for r in rings], axis=0)
    return bool(nearest.max() <= COVER_REACH * radius)
