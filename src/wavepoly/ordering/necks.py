"""A lobe on a narrow neck: one outline, not two rings.

Where a lobe meets the body through a neck a few radii long and about a radius wide or less
(a silhouette's head on a thin throat, a blob joined to the next by a bridge of pixels), the
march can close the lobe on itself across the neck and run the body's outline past its mouth,
each covering the neck's walls with a bump or a spike: two rings where the truth is one
outline pinched at the neck. Cutting a few edges of each ring where they face and linking the
cut ends (a 2-opt move between the rings) gives the one outline.

The two rings are joined only where the gap between them is filled: a line across it between
their cores (each ring shrunk by half a radius, which takes off the spike and the bulge; the
ring itself where it is thinner than that by the neck) has points beside it all the way, the
neck's walls. Across the gap between two shapes of their own the nearest points lie ahead and
behind (their walls facing each other), or there are none (two triangles corner to corner,
their walls running on in line). Nor are two rings joined that together enclose a region
(each grown by half the reach): a letter's bowl split off at both of the hairlines that join
it to the stem, around its counter, which one join would open. Of the moves, one is kept
whose links cross the gap from mouths of a neck's width and whose *bridge* (the region
between its links and the cuts' chords) holds the neck's walls: points clear of the rings'
own walls, as many as two walls as long as the links would hold. A neck shorter than the
rings' nodes are apart has its walls between the nodes: each move is also tried with its
links routed through the points beside them (`neck_routes`).

This differs from `mouths`, which joins a ring capped by a sharp turn at its root to a bare
straight pass of the body's outline: a neck's lobe may close round the neck with no cap (a
spike into it), and the body's outline may bulge into the neck's mouth, covering its points.

References
----------
.. [1] G. A. Croes, "A method for solving traveling-salesman problems", Operations Research
   6(6), 1958, pp. 791-812 (the 2-opt move).
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.spatial import cKDTree

from ..geometry import curve_line, polyline_distance, polyline_length
from ..types import FloatArray, OrderedContour
from .gaps import keeps_members, meets_others
from .neck_routes import Links, MidGap, bridge_points, continuous, kept_clear, routed

#: Two rings this many radii apart or nearer may be a lobe and the body on a neck: the march
#: closes a lobe across a neck up to a couple of radii long.
NECK_REACH = 2.5
#: Edges of each ring tried for the move: those nearest the other ring...
NECK_EDGES = 6
#: ... each the first of a cut of up to this many edges: the lobe's ring may close round the
#: neck in a spike, and the body's bulge into its mouth, whose nodes the move drops.
CUT_EDGES = 3
#: Each link is at least this many radii long: two shapes a fraction of a radius apart,
#: touching at a pixel's corner, are split at their waist (`waists`)...
MIN_LINK = 0.75
#: ... and the cut's chord on either ring, the neck's mouth, at least this many: where two
#: shapes touch at a corner both links run along their one shared band of points.
MIN_MOUTH = 0.45
#: ... and at most this many: a neck wider than that is two walls the march follows apart,
#: and a cut that long takes a stretch of a ring's own wall, whose points bulge into the
#: bridge (two disks two tolerances apart with noise a quarter of one).
MAX_MOUTH = 3.0
#: Each link leaves the chord of one of the cuts at this many degrees or more: the neck runs
#: from the body's mouth across to the lobe's, where a link along the walls of two rings
#: side by side (closer than the radius) runs beside the edges it replaces.
ACROSS_MOUTH = 45.0
#: The two links run within this many degrees of parallel, along the neck's two walls: links
#: that splay apart join two shapes at corners that face each other across a gap.
NECK_PARALLEL = 45.0
#: The bridge's points: those inside it or within this many radii of its links, and farther
#: than this from the rest of the two rings and from the cuts (the walls they ran along)...
WALL_BAND = 0.35
#: ... number at least this share of what two walls as long as the links hold, at the two
#: rings' points per length.
BRIDGE_SHARE = 0.5
#: A move with routed links cuts at least this many edges of each ring, a node or more: the
#: spike the march drew into the neck and the bulge past its mouth. A single edge is a wall
#: that runs on, as where a fin's thin tip touches another outline (Porpi.svg).
ROUTED_CUT = 2
#: The gap between the rings is filled where a line across it between their cores (each
#: ring shrunk by this many radii, taking off the spikes and bulges the march drew into the
#: neck)...
CORE_DEPTH = 0.5
#: ... has points beside it every this many radii along it...
AXIS_STEP = 0.25
#: ... within this many radii (the walls of a neck up to about two radii wide; the body's
#: outline either side of the neck's mouth, the lobe's at its end)...
NECK_HALF = 1.25
#: ... in a strip this many radii wide across it.
STRIP = 0.25
#: A core more than this many radii farther from the other ring than its own ring is, is
#: not the shape the neck leaves but a thicker part beyond a thin one (the march's spike
#: into a neck is up to a couple of radii long).
CORE_REACH = 3.0
#: Lines across the gap start every this many radii along each core's outline...
LINE_STEP = 0.5
#: ... where it lies at most this many radii farther from the other core than the cores'
#: nearest points: a neck a few radii along the facing walls from where the cores come
#: nearest.
NECK_SPREAD = 2.0
#: The points about the move: those within this many radii of its links and the cuts'
#: chords...
NECK_BAND = 1.0
#: ... lie, on average, at most this many times as far from the joined ring as from the two
#: rings: the spike and the bulge that the move takes out ran along the neck's walls, and
#: the links may slant across them by a node's offset (the fit covers those points).
NECK_GAIN = 1.6
#: The neck's tests read at most about this many points per radius along the rings: every
#: k-th point of a denser scan (the tests count points against a wall's density and
#: average distances, which a fraction of a dense scan's points gives as well; all of 70,000
#: points along a neck took 0.9 s of a 1.2 s fit).
NECK_DENSITY = 12.0
#: Joins made per call; each leaves one ring fewer.
MAX_JOINS = 8


def join_through_necks(contours: list[OrderedContour], points: FloatArray, radius: float
                       ) -> list[OrderedContour]:
    """Join two rings side by side that a neck's walls bridge into one outline.

    Parameters
    ----------
    contours : the ordered contours; only closed ones, neither inside the other, are joined.
    points : the input points (the contours' members index them).
    radius : the neighbourhood radius of the ordering.

    Returns
    -------
    The contours, joined rings replaced by the one ring they make: where a neck fills the
    gap between two rings (`_necked`), of the moves between their `NECK_EDGES` edges
    nearest each other (cuts of up to `CUT_EDGES` edges) whose links cross the gap
    (`_across_the_gap`) and whose bridge holds the neck's walls (`BRIDGE_SHARE`), or whose
    links routed through the points beside them run along points with points in the middle
    of the gap (`neck_routes`), the one that brings the points about it nearest
    (`NECK_GAIN`) and is a valid polygon that meets no other contour and keeps every member
    of the two as near as its own ring did (or within a radius).
    """
    out = list(contours)
    tree, stride = None, 1
    for _ in range(MAX_JOINS):
        pairs = _near_pairs(out, radius)
        if not pairs:
            break
        if tree is None:  # a dense scan's every k-th point: as many per radius as a sparse one's
            stride = _stride(out, radius)
            tree = cKDTree(points[::stride])
        join = next((j for a, b in pairs
                     if (j := _best_move(out, a, b, points, tree, radius, stride)) is not None),
                    None)
        if join is None:
            break
        a, b, ring = join
        out[a] = OrderedContour(ring, True, np.union1d(out[a].members, out[b].members))
        del out[b]
    return out


def _near_pairs(contours: list[OrderedContour], radius: float) -> list[tuple[int, int]]:
    """Pairs of valid rings (a < b) within `NECK_REACH` radii, neither inside the other,
    nearest first."""
    rings = [k for k, c in enumerate(contours) if c.closed and len(c.points) >= 4]
    if len(rings) < 2:
        return []
    polygons = [shapely.Polygon(contours[k].points) for k in rings]
    valid = shapely.is_valid(polygons)  # the moves and the cores need valid rings
    near_a, near_b = shapely.STRtree(polygons).query(polygons, predicate="dwithin",
                                                     distance=NECK_REACH * radius)
    pairs = []
    for i, j in zip(near_a, near_b):
        if i < j and valid[i] and valid[j] and not polygons[i].intersects(polygons[j]):
            pairs.append((float(polygons[i].distance(polygons[j])), rings[i], rings[j]))
    return [(a, b) for _, a, b in sorted(pairs)]


def _stride(contours: list[OrderedContour], radius: float) -> int:
    """Every how many points the neck's tests read: the rings' points per radius along them
    over `NECK_DENSITY`, rounded up (1 where they hold fewer)."""
    rings = [c for c in contours if c.closed]
    length = sum(polyline_length(c.points, True) for c in rings)
    per_radius = sum(len(c.members) for c in rings) * radius / max(length, 1e-300)
    return max(int(np.ceil(per_radius / NECK_DENSITY)), 1)


def _best_move(contours: list[OrderedContour], a: int, b: int, points: FloatArray,
               tree: cKDTree, radius: float, stride: int = 1
               ) -> tuple[int, int, FloatArray] | None:
    """Where a neck joins rings a and b (`_necked`) and they enclose nothing together
    (`_enclose`), the move that brings the points about it nearest and whose walls are borne
    out, with its ring, or None. Each move is tried with straight links crossing the gap
    (`_across_the_gap`), whose bridge holds the neck's walls (`_bridged`), and with links
    routed through the points beside them (`neck_routes.routed`), where points lie in the
    middle of the gap (`neck_routes.MidGap`)."""
    one, two = contours[a].points, contours[b].points
    if _enclose(one, two, radius) or not _necked(one, two, tree, radius):
        return None
    length = polyline_length(one, True) + polyline_length(two, True)
    density = ((len(contours[a].members) + len(contours[b].members)) / stride
               / max(length, 1e-300))
    band = WALL_BAND * radius
    middle = MidGap((contours[a], contours[b]), points, radius, stride)
    both = (shapely.LinearRing(one), shapely.LinearRing(two))
    lines = None
    best = None
    cuts_two = _facing_cuts(two, one)
    for cut_one in _facing_cuts(one, two):
        for cut_two in cuts_two:
            for ring, links, rest in _moves(one, cut_one, two, cut_two):
                if not _mouths_fit(rest, radius):
                    continue
                straight = _across_the_gap(links, rest, radius)
                routing = min(cut_one[1], cut_two[1]) >= ROUTED_CUT
                if not (straight or routing):
                    continue
                near = bridge_points(links, tree, band)
                clear = kept_clear(near, rest, band)
                tries = [(ring, True)] if straight else []
                if routing:
                    joined, routes = routed(links, rest, near[clear], radius)
                    if continuous(routes, tree, radius):
                        tries.append((joined, False))
                if not tries:
                    continue
                about = _about(links, both, tree, radius)
                for joined, straight in tries:
                    gain = _gain(joined, about, radius)
                    if gain > NECK_GAIN or (best is not None and gain >= best[0]):
                        continue
                    if not ((_bridged(links, near[clear], band, density) if straight
                             else middle.borne_out(links, near, density))
                            and shapely.Polygon(joined).is_valid):
                        continue
                    if lines is None:
                        lines = shapely.STRtree([curve_line(c.points, c.closed)
                                                 for c in contours])
                    if (not meets_others(joined, (a, b), lines)
                            and all(keeps_members(joined, contours[k], points, radius)
                                    for k in (a, b))):
                        best = (gain, joined)
    return None if best is None else (min(a, b), max(a, b), best[1])


def _facing_cuts(xy: FloatArray, other: FloatArray) -> list[tuple[int, int]]:
    """Cuts (i, k) of ring ``xy``: the k edges from xy[i] to xy[i + k], k up to `CUT_EDGES`,
    starting at one of its `NECK_EDGES` edges nearest the ring ``other``."""
    edges = shapely.linestrings(np.stack([xy, np.roll(xy, -1, axis=0)], axis=1))
    gap = shapely.distance(edges, shapely.LinearRing(other))
    first = np.argsort(gap, kind="stable")[:NECK_EDGES]
    return [(int(i), k) for i in first for k in range(1, min(CUT_EDGES, len(xy) - 3) + 1)]


Move = tuple[FloatArray, Links, tuple[FloatArray, FloatArray]]


def _moves(one: FloatArray, cut_one: tuple[int, int], two: FloatArray,
           cut_two: tuple[int, int]) -> list[Move]:
    """The rings through ``one`` and ``two`` without their cuts, either way round ``two``,
    each with its two links and the two paths it keeps."""
    p, q = _without(one, *cut_one), _without(two, *cut_two)
    return [(np.vstack([p, path]), ((p[-1], path[0]), (path[-1], p[0])), (p, path))
            for path in (q, q[::-1])]


def _without(xy: FloatArray, i: int, k: int) -> FloatArray:
    """Ring ``xy`` without its k edges from xy[i]: the path from xy[i + k] round to xy[i]."""
    return np.roll(xy, -(i + k), axis=0)[:len(xy) - k + 1]


def _mouths_fit(rest: tuple[FloatArray, FloatArray], radius: float) -> bool:
    """Are the cuts' chords (the neck's two mouths) `MIN_MOUTH` to `MAX_MOUTH` radii wide?"""
    widths = [float(np.linalg.norm(path[0] - path[-1])) for path in rest]
    return min(widths) >= MIN_MOUTH * radius and max(widths) <= MAX_MOUTH * radius


def _across_the_gap(links: Links, rest: tuple[FloatArray, FloatArray], radius: float) -> bool:
    """Do both straight links cross the gap as a neck's walls do: at least `MIN_LINK` radii
    long, within `NECK_PARALLEL` of parallel, each at `ACROSS_MOUTH` or more to one of the
    mouths?"""
    mouths = [path[0] - path[-1] for path in rest]
    (a0, a1), (b0, b1) = links
    if _sine(a1 - a0, b1 - b0) > np.sin(np.radians(NECK_PARALLEL)):
        return False
    least = np.sin(np.radians(ACROSS_MOUTH))
    for a, b in links:
        if (float(np.linalg.norm(b - a)) < MIN_LINK * radius
                or max(_sine(b - a, m) for m in mouths) < least):
            return False
    return True


def _sine(u: FloatArray, v: FloatArray) -> float:
    """The sine of the angle between two directions (0 where either is a point)."""
    norms = float(np.linalg.norm(u) * np.linalg.norm(v))
    return abs(float(u[0] * v[1] - u[1] * v[0])) / norms if norms > 0 else 0.0


def _bridged(links: Links, beside: FloatArray, band: float, density: float) -> bool:
    """Does the bridge between the links hold the neck's walls: of its points clear of the
    kept paths (``beside``, `neck_routes.kept_clear`), those farther than ``band`` from the
    cuts' chords too, at least `BRIDGE_SHARE` of what two walls as long as the links hold at
    ``density`` points per length?"""
    (a0, a1), (b0, b1) = links
    if len(beside) == 0:
        return False
    chords = [np.vstack([a1, b0]), np.vstack([b1, a0])]
    clear = np.min([polyline_distance(beside, w, False) for w in chords], axis=0) > band
    needed = BRIDGE_SHARE * density * sum(float(np.linalg.norm(b - a)) for a, b in links)
    return bool(clear.sum() >= max(needed, 1.0))


def _enclose(one: FloatArray, two: FloatArray, radius: float) -> bool:
    """Do the two rings, each grown by half of `NECK_REACH` radii, enclose a region between
    them: the two halves of an outline around a counter (a letter's bowl split off at both
    of the hairlines that join it to the stem, an annulus's two halves), which a join at one
    place would open."""
    alone = [shapely.buffer(shapely.Polygon(xy), NECK_REACH / 2 * radius) for xy in (one, two)]
    grown = shapely.union(*alone)
    holes = [shapely.Polygon(hole).point_on_surface()
             for part in getattr(grown, "geoms", [grown]) for hole in part.interiors]
    # a hole one ring's grown polygon has alone (an inlet the reach wide that the growth
    # closes over) is not enclosed between the two
    return any(not any(shapely.within(hole, shapely.Polygon(inner))
                       for g in alone for inner in g.interiors)
               for hole in holes)


def _necked(one: FloatArray, two: FloatArray, tree: cKDTree, radius: float) -> bool:
    """Is the gap between the two rings filled: does a line across it between their cores
    (each ring shrunk by `CORE_DEPTH` radii, which takes off the spikes and bulges the march
    drew into the neck; `_gap_lines`) have points beside it all the way, within `NECK_HALF`
    radii in a strip `STRIP` radii wide across it every `AXIS_STEP` radii? Across the gap
    between two shapes of their own the nearest points lie ahead and behind (their walls
    facing each other), or there are none (walls running on in line)."""
    cores = [_core(xy, other, radius) for xy, other in ((one, two), (two, one))]
    return any(_filled(a, b, tree, radius) for a, b in _gap_lines(*cores, radius))


def _gap_lines(one: shapely.Geometry, two: shapely.Geometry, radius: float
               ) -> list[tuple[FloatArray, FloatArray]]:
    """Lines across the gap between two cores: the shortest, and from each core's outline
    every `LINE_STEP` radii where it lies within `NECK_SPREAD` radii as near the other, the
    shortest line from there to the other (the neck need not be where the cores come
    nearest: a bulge of the body's core beside it)."""
    nearest = shapely.get_coordinates(shapely.shortest_line(one, two))
    lines = [(nearest[0], nearest[1])]
    reach = float(np.linalg.norm(nearest[1] - nearest[0])) + NECK_SPREAD * radius
    for core, other in ((one, two), (two, one)):
        outline = shapely.boundary(core) if core.geom_type != "Point" else core
        along = np.arange(0.0, shapely.length(outline), LINE_STEP * radius)
        starts = shapely.line_interpolate_point(outline, along) if len(along) else [core]
        starts = [s for s in starts if shapely.distance(s, other) <= reach]
        for ends in shapely.get_coordinates(shapely.shortest_line(starts, other)).reshape(-1, 2, 2):
            lines.append((ends[0], ends[1]) if core is one else (ends[1], ends[0]))
    return lines


def _filled(a: FloatArray, b: FloatArray, tree: cKDTree, radius: float) -> bool:
    """Does the line from a to b have points beside it all the way (`_necked`)?"""
    length = float(np.linalg.norm(b - a))
    if length == 0:
        return False
    u = (b - a) / length
    normal = np.array([-u[1], u[0]])
    for t in np.linspace(0.0, length, max(int(np.ceil(length / (AXIS_STEP * radius))), 1) + 1):
        at = a + t * u
        near = tree.data[tree.query_ball_point(at, float(np.hypot(NECK_HALF, STRIP)) * radius)]
        along, across = (near - at) @ u, (near - at) @ normal
        beside = (np.abs(along) <= STRIP * radius) & (np.abs(across) <= NECK_HALF * radius)
        if not np.any(beside):
            return False
    return True


def _core(xy: FloatArray, other: FloatArray, radius: float) -> shapely.Geometry:
    """The ring's polygon shrunk by `CORE_DEPTH` radii, or its centroid where that leaves
    nothing, or the polygon itself where the core lies more than `CORE_REACH` radii farther
    from the ``other`` ring than the polygon does (a body thin by the neck)."""
    polygon, facing = shapely.Polygon(xy), shapely.LinearRing(other)
    core = shapely.buffer(polygon, -CORE_DEPTH * radius)
    core = polygon.centroid if core.is_empty else core
    if shapely.distance(core, facing) > shapely.distance(polygon, facing) + CORE_REACH * radius:
        return polygon
    return core


def _about(links: Links, rings: tuple[shapely.Geometry, shapely.Geometry], tree: cKDTree,
           radius: float) -> tuple[FloatArray, float]:
    """The points about the move (within `NECK_BAND` radii of its links or the cuts'
    chords) and their mean distance to the two ``rings``."""
    (a0, a1), (b0, b1) = links
    segments = [np.vstack(s) for s in ((a0, a1), (b0, b1), (a1, b0), (b1, a0))]
    reach = NECK_BAND * radius
    near = np.unique(np.concatenate([
        tree.query_ball_point(s.mean(axis=0), np.linalg.norm(s[1] - s[0]) / 2 + reach)
        for s in segments]).astype(np.intp))
    at = shapely.points(tree.data[near])
    close = np.min([shapely.distance(at, shapely.linestrings(s)) for s in segments], axis=0)
    pts, at = tree.data[near[close <= reach]], at[close <= reach]
    if len(pts) == 0:
        return pts, 0.0
    return pts, float(np.mean(np.minimum(*(shapely.distance(at, r) for r in rings))))


def _gain(ring: FloatArray, about: tuple[FloatArray, float], radius: float) -> float:
    """Mean distance of the points ``about`` the move to the joined ring, over their mean
    distance to the two rings (`_about`)."""
    pts, before = about
    if len(pts) == 0:
        return np.inf
    after = shapely.distance(shapely.points(pts), shapely.LinearRing(ring))
    return float(np.mean(after) / max(before, 1e-12 * radius))
