"""Outlines as regions: a cycle of open pieces with stems that no walk along it can draw.

`wavepoly.ordering.stems` walks a cycle of open pieces, and each stem hanging off it out and
back. Where that walk fails (a stem that branches, stems on both sides of the cycle at one
node, a slit's chain that runs across the region from wall to wall, passes that cross each
other by a root), the same outline is a region: the faces that the pieces bound, with each
limb's two walls added to it and each slit's cut out of it. Set operations (GEOS) keep the
result a simple polygon wherever one exists. The stems and chords must hold two walls' points
(`wavepoly.ordering.slits.stems_are_slits`), so that a line drawing's strokes stay strokes.
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.spatial import cKDTree
from shapely.ops import nearest_points, substring

from ..geometry import polyline_distance
from ..types import FloatArray
from .passes import MAX_HALF_WIDTH, MIN_HALF_WIDTH, out_and_back
from .slits import stems_are_slits

#: A chain inside the region shorter than this many radii is where two pieces crossed by a
#: wall (the march's loop of a node or two), not a slit: left out, its points lie by the outline.
MIN_CHORD = 2.0
#: A chord walked as a stem (here, and by `stems` where the walk met it) ends where it comes
#: this many radii from the outline: a slit's tip whose end met the wall beside it is its
#: walls' half-width or so from that wall.
CHORD_TIP = 1.0
#: At most this many chains across the region are tried as slits (each from either end).
MAX_CHORDS = 2
#: Every point of the pieces must lie within this many radii of the outline (here, and by
#: `stems` for the points of an edge the outline leaves out: a chord where a slit tip's chains
#: crossed runs beside its walls).
COVER_REACH = 2.0
#: A stem's walls start this many radii behind its root, so that a slit cuts through the
#: region's outline and a limb grows out of it (its root lies on the outline).
ROOT_OVERLAP = 0.5
#: Pieces of a region smaller than this many square radii, cut off by a stem's walls where its
#: path zigzags, are slivers: dropped, when the outline still covers their points.
SLIVER_AREA = 1.0
#: A hole of a region touches its outline, a slit's mouth, where they come this close (in
#: radii): GEOS puts the pieces' shared node on both.
MOUTH_TOUCH = 1e-6
#: Consecutive vertices of the outline closer than this many radii are one (set operations
#: leave slivers of segments where walls meet).
MERGE_VERTICES = 0.01


def outline_of_faces(lines: list[FloatArray], members: FloatArray, radius: float,
                     open_holes: bool = False) -> FloatArray | None:
    """The closed outline of a component of open pieces, read as a region, or None.

    Parameters
    ----------
    lines : the component's pieces (polylines; they meet at their ends or cross).
    members : the points of the pieces.
    radius : the neighbourhood radius of the ordering.

    Returns
    -------
    The outline's vertices (an (M, 2) ring, not repeating its first vertex), or None where the
    pieces bound no face, bound faces joined only by a bar or a point, the stems are strokes
    (`stems_are_slits`), or the outline misses a point by more than `COVER_REACH` radii.
    GEOS failing on a degenerate arrangement is one more None: the pieces stay as they are.
    ``open_holes``: the region is the largest face with its holes, each opened where it
    touches the outline (a slit's wide part, its walls followed apart, behind a mouth the
    march merged).
    """
    try:
        return _outline_of_faces(lines, members, radius, open_holes)
    except shapely.errors.GEOSException:
        return None


def _outline_of_faces(lines: list[FloatArray], members: FloatArray, radius: float,
                      open_holes: bool = False) -> FloatArray | None:
    """`outline_of_faces`, GEOS errors and all."""
    parts = list(shapely.get_parts(shapely.node(shapely.MultiLineString(
        [xy for xy in lines if len(xy) >= 2]))))
    faces, cuts, dangles, _ = shapely.polygonize_full(parts)
    if faces.is_empty or not (cuts.is_empty or open_holes):
        return None
    heads = shapely.GeometryCollection()
    if open_holes:  # a limb's merged walls run out to a loop where the march parted them
        dangles = shapely.union_all([dangles, cuts])
        faces, heads = _faces_and_heads(faces, radius)
    tree = cKDTree(members)
    regions = _largest_with_holes(faces, radius) if open_holes else _regions(faces)
    for region in regions:
        stems, chords = _stems_and_chords(parts, faces, dangles, region, radius)
        if len(chords) > MAX_CHORDS:
            continue
        for cut in _chords_as_slits(chords, region, radius):
            ring = _region_outline(region, stems + cut, members, tree, radius, open_holes,
                                   heads)
            if ring is not None:
                return ring
    return None


def _regions(faces: shapely.Geometry) -> list[shapely.Polygon]:
    """The regions the outline may bound: all the faces together, else the largest alone (the
    others thin faces between a slit's two walls, which the march followed apart)."""
    polygons = sorted(shapely.get_parts(faces), key=lambda f: -f.area)
    union = shapely.union_all(polygons)
    out = [union] if union.geom_type == "Polygon" and not len(union.interiors) else []
    if len(polygons) > 1:
        out.append(shapely.Polygon(polygons[0].exterior))
    return out


def _faces_and_heads(faces: shapely.Geometry, radius: float
                     ) -> tuple[shapely.Geometry, shapely.Geometry]:
    """The faces that meet the largest one (itself among them), and the others: heads, each
    at the end of a limb's merged walls (a cut edge of the pieces), where the march followed
    them apart round the limb's tip."""
    parts = list(shapely.get_parts(faces))
    largest = _largest(faces)
    apart = [shapely.distance(f, largest) > MOUTH_TOUCH * radius for f in parts]
    return (shapely.GeometryCollection([f for f, a in zip(parts, apart) if not a]),
            shapely.union_all([f for f, a in zip(parts, apart) if a]))


def _largest_with_holes(faces: shapely.Geometry, radius: float) -> list[shapely.Polygon]:
    """The largest face, with its holes, where one of them touches its outline."""
    largest = _largest(faces)
    return [largest] if _mouths(largest, radius) else []


def _largest(faces: shapely.Geometry) -> shapely.Polygon:
    """The face of largest area."""
    return max(shapely.get_parts(faces), key=lambda f: f.area)


def _mouths(region: shapely.Polygon, radius: float) -> list[shapely.Point]:
    """The points where the region's holes touch its outline (within `MOUTH_TOUCH` radii),
    one per touching hole."""
    near = (nearest_points(hole, region.exterior) for hole in region.interiors)
    return [a for a, b in near if a.distance(b) <= MOUTH_TOUCH * radius]


def _stems_and_chords(parts: list[shapely.LineString], faces: shapely.Geometry,
                      dangles: shapely.Geometry, region: shapely.Polygon, radius: float
                      ) -> tuple[list[FloatArray], list[FloatArray]]:
    """The dangling chains (stems, each from the end nearer the region's outline) and the
    chains off its outline that bound two faces (chords at least `MIN_CHORD` radii long).
    Where the region is the largest face alone, a chain of a thin face it leaves out counts
    too, and is cut or added like a stem (silhouette 0:45 needs that; reading only chains
    inside the region left it open)."""
    tol = 1e-9 * radius
    bounds = shapely.union_all([f.exterior for f in shapely.get_parts(faces)])
    solid = [p for p in parts if not p.is_empty]
    middle = shapely.line_interpolate_point(solid, 0.5, normalized=True)
    off_outline = shapely.distance(middle, region.boundary) > tol
    on_a_face = shapely.distance(middle, bounds) <= tol
    inner = [p for p, keep in zip(solid, off_outline & on_a_face) if keep]
    stems = [_from_outline(np.asarray(c.coords), region) for c in _merged(dangles)]
    chords = [np.asarray(c.coords) for c in _merged(shapely.MultiLineString(inner))
              if c.length >= MIN_CHORD * radius]
    return stems, chords


def _merged(lines: shapely.Geometry) -> list[shapely.LineString]:
    """The lines merged into chains through the points where only two meet."""
    if lines.is_empty:
        return []
    return list(shapely.get_parts(shapely.line_merge(shapely.union_all(
        list(shapely.get_parts(lines))))))


def _from_outline(xy: FloatArray, region: shapely.Polygon) -> FloatArray:
    """A polyline from its end nearer the region's outline."""
    near = shapely.distance(shapely.points(xy[[0, -1]]), region.boundary)
    return xy if near[0] <= near[1] else xy[::-1]


def _chords_as_slits(chords: list[FloatArray], region: shapely.Polygon, radius: float
                     ) -> list[list[FloatArray]]:
    """Each way of walking every chord as a slit from one of its ends, up to where it comes
    within `CHORD_TIP` radii of the outline at the other."""
    ways: list[list[FloatArray]] = [[]]
    for xy in chords:
        trimmed = [_trimmed(path, region, radius) for path in (xy, xy[::-1])]
        ways = [way + [t] for way in ways for t in trimmed if t is not None]
    return ways


def _trimmed(path: FloatArray, region: shapely.Polygon, radius: float) -> FloatArray | None:
    """A chord from its start up to its last point farther than `CHORD_TIP` radii from the
    outline, or None when too little of it is."""
    near = shapely.distance(shapely.points(path), region.exterior) <= CHORD_TIP * radius
    far = np.flatnonzero(~near)
    return path[:far[-1] + 1] if len(far) and far[-1] >= 2 else None


def _region_outline(region: shapely.Polygon, stems: list[FloatArray], members: FloatArray,
                    tree: cKDTree, radius: float, open_holes: bool = False,
                    heads: shapely.Geometry | None = None) -> FloatArray | None:
    """The region with each limb's walls added and each slit's cut out (and the ``heads`` at
    the limbs' ends added): its outline, when that is one simple polygon within
    `COVER_REACH` radii of every member and the stems are two walls each."""
    if stems and not stems_are_slits(*_walk_and_paths(region, stems, radius), members,
                                     radius):
        return None
    out = region
    for stem in stems:
        walls = _walls(stem, tree, radius)
        inside = region.contains(shapely.points(stem[1:])).mean() > 0.5
        out = out.difference(walls) if inside else out.union(walls)
    if heads is not None and not heads.is_empty:  # grown a little, to meet the limb's tip
        out = out.union(heads.buffer(MIN_HALF_WIDTH * radius, join_style="mitre"))
    out = _without_slivers(out, radius)
    if out is not None and open_holes:
        out = _without_slivers(_holes_opened(out, radius), radius)
    if out is None or len(out.interiors) or not out.is_valid:
        return None
    ring = shapely.remove_repeated_points(out.exterior, MERGE_VERTICES * radius)
    xy = np.asarray(ring.coords)[:-1]
    if len(xy) < 3 or not shapely.Polygon(xy).is_valid:
        return None
    if polyline_distance(members, xy, True).max() > COVER_REACH * radius:
        return None
    return xy


def _holes_opened(region: shapely.Polygon, radius: float) -> shapely.Geometry:
    """The region with each hole that touches its outline joined to the outside there by a
    mouth `passes.MAX_HALF_WIDTH` radii to either side of the point: the march merged the
    slit's walls there, so they lie within a radius of each other."""
    # a square across each point: four vertices, where a disk would draw a bead of them
    mouths = [a.buffer(MAX_HALF_WIDTH * radius, quad_segs=1) for a in _mouths(region, radius)]
    return region.difference(shapely.union_all(mouths)) if mouths else region


def _without_slivers(region: shapely.Geometry, radius: float) -> shapely.Polygon | None:
    """The largest polygon of a region, where the others are slivers under `SLIVER_AREA`
    square radii (left between a zigzag stem's passes), else None."""
    parts = sorted(shapely.get_parts(region), key=lambda g: -g.area)
    if not parts or parts[0].geom_type != "Polygon":
        return None
    if any(g.area > SLIVER_AREA * radius**2 for g in parts[1:]):
        return None
    return parts[0]


def _walls(stem: FloatArray, tree: cKDTree, radius: float) -> shapely.Geometry:
    """The polygon between a stem's two walls (`out_and_back`), started `ROOT_OVERLAP` radii
    behind its root."""
    step = stem[0] - stem[1]
    back = stem[0] + ROOT_OVERLAP * radius * step / max(np.linalg.norm(step), 1e-300)
    walls = shapely.Polygon(out_and_back(np.vstack([back, stem]), 1.0, tree, radius))
    return walls if walls.is_valid else shapely.make_valid(walls)


def _walk_and_paths(region: shapely.Polygon, stems: list[FloatArray], radius: float
                    ) -> tuple[dict[int, list[FloatArray]], list[tuple[int, FloatArray]]]:
    """The stems by root and the outline's walk between the roots, as
    `stems_are_slits` reads them (a stem whose root is off the outline hangs off another)."""
    outline = region.exterior
    at = np.array([outline.project(shapely.Point(s[0])) for s in stems])
    on = shapely.distance(shapely.points([s[0] for s in stems]), outline) <= 1e-6 * radius
    length = outline.length
    apart = MERGE_VERTICES * radius
    stops = _distinct(at[on], apart) if on.any() else np.zeros(1)
    if len(stops) > 1 and stops[-1] - stops[0] > length - apart:
        stops = stops[:-1]  # the last root is the first one, across the ring's start
    paths: dict[int, list[FloatArray]] = {}
    for k, stem in enumerate(stems):
        gap = np.abs(stops - at[k])
        node = int(np.argmin(np.minimum(gap, length - gap))) if on[k] else -1 - k
        paths.setdefault(node, []).append(stem)
    walk = []
    for i, s in enumerate(stops):
        stop = stops[i + 1] if i + 1 < len(stops) else stops[0] + length
        xy = np.asarray(substring(outline, s, min(stop, length)).coords)
        if stop > length:
            xy = np.vstack([xy, np.asarray(substring(outline, 0.0, stop - length).coords)[1:]])
        walk.append((i, xy))
    return paths, walk


def _distinct(at: FloatArray, apart: float) -> FloatArray:
    """The sorted positions, each at least ``apart`` past the one before (the others merged
    into it), so that the outline between two has length."""
    out: list[float] = []
    for a in np.sort(at):
        if not out or a - out[-1] >= apart:
            out.append(float(a))
    return np.array(out)
