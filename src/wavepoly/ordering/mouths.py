"""Two rings the march closed across a narrow mouth: one outline, not two.

Where a limb meets the body through a root a few radii wide, or a pocket opens through a mouth
as narrow, the march can close the limb (the pocket) on itself across its root and run the
body's outline straight past it: two closed rings where the truth is one. The limb's ring ends
in a *cap*, an edge across the root (or two meeting in a V by the body's wall) where it turns
sharply the same way at both ends (its two walls end there), far more than it bends elsewhere
(every chord of a small round ring turns as much); the body's ring *passes* the root on a
straight edge that is *bare*, with no points along it, since no wall runs across a root.
Replacing the cap and the pass by the two links between their ends (a 2-opt move
between the rings) gives the one outline. Two rings of their own that come close (two blobs a
tolerance apart) face each other along walls of points, and curve gently where they do, so
they stay apart.

A notch whose mouth is narrower than the radius (the slit between a horse's ears) may be closed
the same way, its walls drawn as a thin ring inside the outline: a hole where the truth is a
notch. Such a *pocket* comes within a couple of radii of the outline and is a few radii wide
at most; it joins the outline by the 2-opt move of least detour that takes out a stretch of
the outline across the mouth (bare of points: no wall runs there) and whose links run along
points. A true hole of a silhouette keeps a wall of its own between it and the outline, and a
ring inside a ring (an annulus) is no thin ring; nor is a small round one (a letter's counter):
a pocket is long for its width, as a slit's walls are. A slot hole that thin and that near its
outline, with less than two radii of wall between them where the outline's points leave a gap,
reads as a notch too (the lens that touches the beak's wall in the shared drawing f3): the points
cannot tell the two apart at that scale, and the notch keeps them within the tolerance.

References
----------
.. [1] G. A. Croes, "A method for solving traveling-salesman problems", Operations Research
   6(6), 1958, pp. 791-812 (the 2-opt move).
"""

from __future__ import annotations

from collections.abc import Callable
from functools import cache, partial

import numpy as np
import shapely
from scipy.spatial import cKDTree

from ..geometry import along_and_across, curve_line, polyline_length
from ..types import FloatArray, OrderedContour
from .gaps import is_supported, keeps_members, meets_others
from .untangle import untangle

#: A cap turns by at least this (degrees) at both of its ends, the same way (a limb cut at its
#: root: 121 and 60); ordered points half a radius to a radius apart turn by some 20 degrees
#: each on a blob a few radii across.
CAP_TURN = 45.0
#: ... and by this many times what its own bend gives a chord that long (the median turn of
#: its nodes): on a small round ring (a hole 4 ε across) every node turns 25-30 degrees, and
#: any chord over two edges turns 45 into it; the rings that joined at caps in the sweeps (a
#: silhouette's limb, a random shape's, a keyhole's round chamber) turn 4-8 degrees a node in
#: the median, and their caps 46-137.
CAP_CONTRAST = 3.0
#: A cap spans at most this many edges: one across the root, or two meeting in a V.
CAP_EDGES = 2
#: A pass turns by at most this at either end, over one edge and over two.
PASS_TURN = 30.0
#: Cap and pass face each other: the angle between them is at most this (degrees).
FACING = 30.0
#: They come this many radii close: the march closes a limb across a root up to about two
#: radii wide.
MOUTH_REACH = 3.0
#: The points along a segment are those within this many radii of it, away from its ends...
BAND = 0.5
#: ... at least this many radii from either end (the walls the segment ends on lie there).
END_CLEARANCE = 0.5
#: A pass is bare when it holds at most this share of the points a wall as long would hold
#: (at the rings' own points per length)...
BARE_SHARE = 0.25
#: ... judged where such a wall would hold at least this many points.
MIN_EXPECTED = 1.5
#: Joins made per call; each leaves one ring fewer.
MAX_JOINS = 8
#: A pocket comes within this many radii of the ring around it: the notches closed so on
#: scikit-image's horse came within 0.3-1.9 tolerances, the true holes of the silhouette and
#: blob sweeps stay 2.4 or more from their outlines.
POCKET_GAP = 2.0
#: ... and is thin: twice its area over its length is at most this many radii (the horse's
#: ear slit 1.0-2.2 tolerances, a made-up silhouette's closed-off slit 2.6; an annulus's inner
#: ring is as wide as its radius).
POCKET_WIDTH = 3.0
#: ... and long: its length squared is more than this many times 4 pi its area (1 for a
#: circle). A slit's walls closed off into a ring are long for their width (the closed-off
#: slits and notches of the silhouette sweeps, the horse and the photographs: 1.42-9.8); a
#: ring this round is a hole (a letter's counter on scikit-image's page, a small hole 1-2
#: radii inside a blob's outline: 1.06-1.25), which its own wall of points keeps apart.
POCKET_ROUNDNESS = 1.33
#: Edges of the pocket tried for the move, the nearest to the ring around it first.
POCKET_EDGES = 6
#: The pass the move takes out of the ring around a pocket runs across its mouth, where no
#: wall runs: the middle half of the pass lies at least this many radii from every point
#: somewhere (0.39-0.69 across the horse's ear slit and a silhouette's slit; along a wall
#: sampled every third of a radius, a sixth of one).
POCKET_BARE = 0.3
#: A pocket's node this many radii or less from the node before it is dropped: the march
#: stepped back by a tenth of a radius there, and the edge after it grazed the node before.
POCKET_STEP = 0.25


def join_through_mouths(contours: list[OrderedContour], points: FloatArray, radius: float
                        ) -> list[OrderedContour]:
    """Join a ring capped at a narrow root to the ring that passes the root, as one ring.

    A join replaces the cap and the pass by the two links between their ends, each at most
    `MOUTH_REACH` radii long, when the joined ring is a valid polygon that meets no other
    contour and keeps every member of the two as near as its own ring did (or within a
    radius).

    Parameters
    ----------
    contours : the ordered contours; only closed ones are joined.
    points : the input points (the contours' members index them).
    radius : the neighbourhood radius of the ordering.

    Returns
    -------
    The contours, joined rings replaced by the one ring they make.
    """
    tree = cache(partial(cKDTree, points))  # built only once a ring has a cap
    out = list(contours)
    for _ in range(MAX_JOINS):
        join = _first_join(out, points, tree, radius) or _first_pocket(out, points, tree, radius)
        if join is None:
            break
        a, b, ring = join
        members = np.union1d(out[a].members, out[b].members)
        out[a] = OrderedContour(ring, True, members)
        del out[b]
    return out


def _first_join(contours: list[OrderedContour], points: FloatArray,
                tree: Callable[[], cKDTree], radius: float
                ) -> tuple[int, int, FloatArray] | None:
    """The first cap and pass of two rings (nearest first) that join, with the joined ring.
    ``tree``: gives the points' tree."""
    rings = [k for k, c in enumerate(contours) if c.closed and len(c.points) >= 4]
    if len(rings) < 2:
        return None
    caps = [(k, e) for k in rings for e in _caps(contours[k].points)]  # e: (first, edges)
    if not caps:
        return None
    length = sum(polyline_length(contours[k].points, True) for k in rings)
    density = sum(len(contours[k].members) for k in rings) / max(length, 1e-300)
    passes = [(k, f) for k in rings for f in _bare_passes(contours[k].points, tree(), radius,
                                                          density)]
    if not passes:
        return None
    cap_lines = [shapely.LineString(_edge(contours[k].points, *e)) for k, e in caps]
    pass_lines = shapely.STRtree([shapely.LineString(_edge(contours[k].points, f))
                                  for k, f in passes])
    near_cap, near_pass = pass_lines.query(cap_lines, predicate="dwithin",
                                           distance=MOUTH_REACH * radius)
    pairs = sorted((float(cap_lines[i].distance(pass_lines.geometries[j])), i, j)
                   for i, j in zip(near_cap, near_pass) if caps[i][0] != passes[j][0])
    lines = shapely.STRtree([curve_line(c.points, c.closed) for c in contours])
    for _, i, j in pairs:
        (a, e), (b, f) = caps[i], passes[j]
        one, two = contours[a].points, contours[b].points
        if not _facing(_edge(one, *e), _edge(two, f)):
            continue
        ring = _joined(one, e, two, f, radius)
        if ring is not None and _fits(ring, a, b, contours, points, lines, radius):
            return min(a, b), max(a, b), ring
    return None


def _first_pocket(contours: list[OrderedContour], points: FloatArray,
                  tree: Callable[[], cKDTree], radius: float
                  ) -> tuple[int, int, FloatArray] | None:
    """The first pocket (`POCKET_GAP`, `POCKET_WIDTH`, `POCKET_ROUNDNESS`) that joins the
    ring around it, with the joined ring: of the moves between its `POCKET_EDGES` edges
    nearest that ring and the ring's edges within `MOUTH_REACH` radii of each that cross a
    mouth (`POCKET_BARE`), the one of least detour whose two links run along points
    (`gaps.is_supported`)."""
    rings = [k for k, c in enumerate(contours) if c.closed and len(c.points) >= 4]
    polygons = [shapely.Polygon(contours[k].points) for k in rings]
    thin = [i for i, p in enumerate(polygons) if 2 * p.area <= POCKET_WIDTH * radius * p.length
            and p.length ** 2 > POCKET_ROUNDNESS * 4 * np.pi * p.area]
    if len(rings) < 2 or not thin:
        return None
    around = shapely.STRtree(polygons)  # the rings that may hold a pocket: those it lies in
    lines = None
    for i in thin:
        for j in around.query(polygons[i], predicate="within"):
            if j == i or polygons[i].distance(polygons[j].exterior) > POCKET_GAP * radius:
                continue
            a, b = rings[i], rings[j]
            if lines is None:
                lines = shapely.STRtree([curve_line(c.points, c.closed) for c in contours])
            for ring in _pocket_moves(contours[a].points, contours[b].points, tree(), radius):
                if _fits(ring, a, b, contours, points, lines, radius):
                    return min(a, b), max(a, b), ring
    return None


def _pocket_moves(one: FloatArray, two: FloatArray, tree: cKDTree, radius: float
                  ) -> list[FloatArray]:
    """The valid rings of the moves between the pocket ``one`` and the ring ``two`` around
    it whose links run along points, the least detour first. The pocket's nodes that
    step back by less than `POCKET_STEP` radii are dropped first, and a ring is untangled
    where the pocket's own kinks cross it."""
    kept = np.linalg.norm(one - np.roll(one, 1, axis=0), axis=1) > POCKET_STEP * radius
    one = one[kept] if kept.sum() >= 4 else one
    pocket, around = _segments(one), _segments(two)
    gap = shapely.distance(pocket, shapely.LinearRing(two))
    bare: dict[int, bool] = {}  # whether each of two's edges crosses a mouth, as looked at
    moves = []
    for e in np.argsort(gap)[:POCKET_EDGES]:
        p = np.roll(one, -(e + 1), axis=0)  # starts after the edge, ends before it
        near = np.flatnonzero(shapely.distance(around, pocket[e]) <= MOUTH_REACH * radius)
        for g in near:
            if g not in bare:
                bare[g] = _bare_middle(two[g], two[(g + 1) % len(two)], tree, radius)
        for f in (g for g in near if bare[g]):
            q = np.roll(two, -(f + 1), axis=0)
            for path in (q, q[::-1]):
                links = ((p[-1], path[0]), (path[-1], p[0]))
                if not all(is_supported(a, b, tree, radius) for a, b in links):
                    continue
                ring = np.vstack([p, path])
                if not shapely.Polygon(ring).is_valid:
                    ring = untangle(ring, True)
                if shapely.Polygon(ring).is_valid:
                    detour = (sum(np.linalg.norm(b - a) for a, b in links)
                              - pocket[e].length - around[f].length)
                    moves.append((detour, len(moves), ring))
    return [ring for *_, ring in sorted(moves, key=lambda m: m[:2])]


def _bare_middle(a: FloatArray, b: FloatArray, tree: cKDTree, radius: float) -> bool:
    """Does the middle half of segment a-b pass `POCKET_BARE` radii from every point
    somewhere (sampled every tenth of a radius)?"""
    steps = max(int(np.ceil(np.linalg.norm(b - a) / (0.1 * radius))), 2)
    t = np.linspace(0.25, 0.75, steps + 1)[:, None]
    return bool(tree.query(a + t * (b - a))[0].max() >= POCKET_BARE * radius)


def _segments(xy: FloatArray) -> np.ndarray:
    """A ring's edges as shapely line strings, edge i from xy[i] to xy[i + 1]."""
    return shapely.linestrings(np.stack([xy, np.roll(xy, -1, axis=0)], axis=1))


def _caps(xy: FloatArray) -> list[tuple[int, int]]:
    """Caps (e, k): chords from xy[e] to xy[e + k] over `CAP_EDGES` edges or fewer, into
    and out of which the ring turns by `CAP_TURN` or more the same way, and `CAP_CONTRAST`
    times what the ring's median turn gives over (k + 1) / 2 nodes. A cap of two edges is a
    root closed in a V (its tip by the other ring's wall)."""
    caps: list[tuple[int, int]] = []
    bend = float(np.median(np.abs(_turns(xy, 1)[0])))
    for k in range(1, CAP_EDGES + 1):
        least = max(CAP_TURN, CAP_CONTRAST * bend * (k + 1) / 2)
        before, after = _chord_turns(xy, k)
        cap = (np.abs(before) >= least) & (np.abs(after) >= least) & (before * after > 0)
        caps += [(int(e), k) for e in np.flatnonzero(cap)]
    return caps


def _chord_turns(xy: FloatArray, k: int) -> tuple[FloatArray, FloatArray]:
    """Signed turns (degrees) into each chord xy[e] to xy[e + k] from the edge before it,
    and out of it to the edge after it."""
    d = np.roll(xy, -1, axis=0) - xy
    chord = np.roll(xy, -k, axis=0) - xy
    into = _signed_turn(np.roll(d, 1, axis=0), chord)
    return into, _signed_turn(chord, np.roll(d, -k, axis=0))


def _bare_passes(xy: FloatArray, tree: cKDTree, radius: float, density: float) -> list[int]:
    """Edges where the ring runs straight on (`PASS_TURN`, over one edge and two) with no
    wall of points along the edge (`BARE_SHARE`)."""
    straight = np.ones(len(xy), dtype=bool)
    for step in (1, 2):
        before, after = _turns(xy, step)
        straight &= (np.abs(before) <= PASS_TURN) & (np.abs(after) <= PASS_TURN)
    nxt = np.roll(xy, -1, axis=0)
    out = []
    for f in np.flatnonzero(straight):
        held, expected = _points_along(xy[f], nxt[f], tree, radius, density)
        if expected >= MIN_EXPECTED and held <= BARE_SHARE * expected:
            out.append(int(f))
    return out


def _turns(xy: FloatArray, step: int) -> tuple[FloatArray, FloatArray]:
    """Signed turns (degrees) into each edge from the edge ``step`` before it, and out of it
    to the edge ``step`` after it."""
    d = np.roll(xy, -1, axis=0) - xy
    return _signed_turn(np.roll(d, step, axis=0), d), _signed_turn(d, np.roll(d, -step, axis=0))


def _signed_turn(u: FloatArray, v: FloatArray) -> FloatArray:
    """Signed angle (degrees, counter-clockwise positive) from each direction u to v."""
    cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    return np.degrees(np.arctan2(cross, np.einsum("ij,ij->i", u, v)))


def _points_along(a: FloatArray, b: FloatArray, tree: cKDTree, radius: float,
                  density: float) -> tuple[int, float]:
    """Points within `BAND` radii of the segment a-b away from its ends (`END_CLEARANCE`),
    and how many a wall that long would hold at ``density`` points per length."""
    length = float(np.linalg.norm(b - a))
    inner = length - 2 * END_CLEARANCE * radius
    if inner <= 0:
        return 0, 0.0
    near = tree.data[tree.query_ball_point((a + b) / 2, length / 2 + BAND * radius)]
    along, across = along_and_across(near, a, b)
    inside = ((along >= END_CLEARANCE * radius) & (along <= length - END_CLEARANCE * radius)
              & (across <= BAND * radius))
    return int(inside.sum()), density * inner


def _facing(cap: FloatArray, wall: FloatArray) -> bool:
    """Do the two edges lie within `FACING` degrees of parallel?"""
    u, v = cap[1] - cap[0], wall[1] - wall[0]
    sine = abs(u[0] * v[1] - u[1] * v[0]) / max(np.linalg.norm(u) * np.linalg.norm(v), 1e-300)
    return bool(sine <= np.sin(np.radians(FACING)))


def _joined(one: FloatArray, e: tuple[int, int], two: FloatArray, f: int, radius: float
            ) -> FloatArray | None:
    """The ring through ``one`` without its edge e and ``two`` without its edge f, linked end
    to end by links at most `MOUTH_REACH` radii long (either way round ``two``) into a valid
    polygon, or None."""
    first, k = e
    p = np.roll(one, -(first + k), axis=0)[:len(one) - k + 1]  # starts after the cap, ends before
    q = np.roll(two, -(f + 1), axis=0)
    reach = MOUTH_REACH * radius
    for path in (q, q[::-1]):
        if (np.linalg.norm(p[-1] - path[0]) <= reach
                and np.linalg.norm(path[-1] - p[0]) <= reach):
            ring = np.vstack([p, path])
            if shapely.Polygon(ring).is_valid:
                return ring
    return None


def _fits(ring: FloatArray, a: int, b: int, contours: list[OrderedContour],
          points: FloatArray, lines: shapely.STRtree, radius: float) -> bool:
    """Does the joined ring meet no other contour and keep every member of the two as near
    as its own ring did (or within a radius)?"""
    return (not meets_others(ring, (a, b), lines)
            and all(keeps_members(ring, contours[k], points, radius) for k in (a, b)))


def _edge(xy: FloatArray, e: int, k: int = 1) -> FloatArray:
    return np.vstack([xy[e], xy[(e + k) % len(xy)]])
