"""Untangling an ordered chain that crosses itself (2-opt moves).

Where a thin part of the shape is narrower than the neighbourhoods, the march can come back
across its own way: the chain visits the points in an order whose polyline crosses itself, and
every polygon through its points in that order would cross too. A 2-opt move reverses the run
of the chain between two crossing edges, which removes their crossing and strictly shortens the
chain (the triangle inequality), so repeating it ends with a simple chain; the set of ordered
points does not change.

References
----------
.. [1] G. A. Croes, "A method for solving traveling-salesman problems", Operations Research
   6(6), 1958, pp. 791-812.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial

import numpy as np
import shapely

from ..geometry import nearest_of_segments
from ..types import FloatArray, IntArray, OrderedContour
from ..validity import split_at_crossings_of
from .marching import turning

#: Rounds of 2-opt moves; each round reverses every crossing run that no other run overlaps,
#: and real chains are simple after a few rounds (the chain shortens every time).
MAX_ROUNDS = 200
#: Where two closed chains cross on edges that each turn by more than this (degrees) from an
#: edge beside them, the march switched between near-touching rings (it jumped across);
#: two smooth curves that truly cross run straight through the crossing.
SWITCH_TURN = 20.0
#: Two crossing closed chains overlapping by less than this share of the smaller one's area
#: are two parts of one outline that nearly touch (`merge_overlapping_rings`); the 'k' of
#: STIX at tolerance 0.3 overlaps by 0.04 %.
OVERLAP_SHARE = 0.01
#: A closed chain that crosses itself is two shapes that nearly touch, read as one figure
#: eight (`split_kissing_rings`), when each of its two loops is at least this wide, in radii
#: (twice its area over its perimeter: a disk's radius); where the march crossed between the
#: walls of a part narrower than the neighbourhoods, the loop it cuts off is narrower.
KISSING_WIDTH = 1.5
#: ... and where its two passes through the crossing meet at at least this angle (degrees):
#: at a kiss the march runs off one outline onto the other and the passes spread like an X
#: (blobs touching at a pixel's corner: 61-87 degrees), where it crossed inside a neck
#: narrower than the tolerance they run along the neck (17-43 degrees).
KISS_ANGLE = 50.0
#: ... and where neither loop closes on a U-turn: the turn (degrees) across the edge that
#: closes it, between arms of `ARM_NODES` nodes, is at most this. A shape's own outline runs
#: on round its tip (blobs: 51-115; two circles whose chain left each 60 degrees short of
#: the kiss: 132); a loop cut across a stroke thinner than the radius turns back along its
#: other wall (a serif font's hairlines at 4 % of its height: 143-179, a few 122-125).
KISS_CLOSING_TURN = 140.0
#: Nodes on either side of a pass that its arms span: the turns are taken between them (3
#: bends the arms round a small blob's outline as much as the waist turns).
ARM_NODES = 2
#: Splits tried on one chain: each split leaves two loops that are split again in turn.
MAX_SPLITS = 8
#: A loop of fewer nodes encloses no shape worth a ring of its own.
MIN_LOOP_NODES = 4
#: 2-opt moves that clear touching edges, per chain: such contacts are rare (one at the
#: inner apex of DejaVu Sans Mono's 'W' at tolerance 0.1), and each move is checked whole.
MAX_TOUCH_MOVES = 8


def untangle(xy: FloatArray, closed: bool) -> FloatArray:
    """The chain's points in an order whose polyline does not cross itself.

    Reverses the run between two crossing edges (a 2-opt move), shortest runs first, until no
    two non-adjacent edges cross or `MAX_ROUNDS` have passed. Then a point that lies on an
    edge not its own (a corner the sharpening put on the line of a leg beyond it) is moved
    off it the same way, where a move leaves fewer such contacts.
    """
    n = len(xy)
    if n < 4:
        return xy
    out = xy.copy()
    for _ in range(MAX_ROUNDS):
        pairs = crossing_edges(out, closed)
        if not len(pairs):
            break
        for i, j in _disjoint_runs(pairs):
            out[i + 1:j + 1] = out[i + 1:j + 1][::-1].copy()
    return _untouched(out, closed)


def _untouched(xy: FloatArray, closed: bool) -> FloatArray:
    """The chain with the 2-opt moves that clear its touching non-adjacent edges
    (`touching_edges`), each kept where it leaves fewer touching or crossing pairs."""
    out = xy
    for _ in range(MAX_TOUCH_MOVES):
        if _simple(out, closed):
            break
        pairs = touching_edges(out, closed)
        if not len(pairs):
            break
        count = len(pairs)
        for i, j in pairs:
            moved = out.copy()
            moved[i + 1:j + 1] = moved[i + 1:j + 1][::-1].copy()
            left = len(touching_edges(moved, closed)) + len(crossing_edges(moved, closed))
            if left < count:
                out = moved
                break
        else:
            break
    return out


def split_kissing_rings(xy: FloatArray, radius: float) -> list[FloatArray]:
    """A closed chain that crosses itself like a figure eight, as the two rings it visits.

    Where two shapes nearly touch (blobs whose outlines run closer than the neighbourhoods at
    one spot), the march runs along one outline into the neck and straight on along the other:
    the chain visits both rings and crosses itself there. A 2-opt move (`untangle`) would keep
    it one outline with a neck; reconnecting the crossing edges the other way gives the two
    rings. That is kept where the two passes cross at `KISS_ANGLE` or more, neither loop
    closes on a U-turn (`KISS_CLOSING_TURN`: a stroke cut across), both loops are simple once
    untangled, lie side by side (neither meets nor holds the other) and are both at least
    `KISSING_WIDTH` radii wide. Each loop is split again where it still crosses itself.
    """
    return [untangle(ring, True) for ring in split_repeatedly(xy, partial(_kissing_split,
                                                                         radius=radius))]


def split_repeatedly(xy: FloatArray, split: Callable[[FloatArray], list[FloatArray] | None]
                     ) -> list[FloatArray]:
    """The rings left once ``split`` (a ring's pieces, or None where it stays whole) has been
    applied to a closed chain and to each piece in turn, up to `MAX_SPLITS` splits."""
    done, todo = [], [xy]
    while todo:
        ring = todo.pop()
        pieces = split(ring) if len(done) + len(todo) < MAX_SPLITS else None
        if pieces is None:
            done.append(ring)
        else:
            todo += pieces
    return done


def _kissing_split(xy: FloatArray, radius: float) -> list[FloatArray] | None:
    """The first crossing of closed chain ``xy`` at which it splits into two wide simple
    loops side by side (`split_kissing_rings`), or None."""
    if len(xy) < 2 * MIN_LOOP_NODES:
        return None
    for i, j in crossing_edges(xy, True):
        if _crossing_angle(xy, i, j) < KISS_ANGLE:
            continue
        _, from_i, from_j = pass_turns(xy, np.array([i]), np.array([j]))
        if max(from_i[0], from_j[0]) > KISS_CLOSING_TURN:
            continue  # a stroke cut across: its two walls, not two shapes
        loops = [untangle(xy[i + 1:j + 1], True),
                 untangle(np.concatenate([xy[j + 1:], xy[:i + 1]]), True)]
        if min(len(loop) for loop in loops) < MIN_LOOP_NODES:
            continue
        polys = [shapely.Polygon(loop) for loop in loops]
        if not all(p.is_valid for p in polys) or shapely.intersects(*polys):
            continue
        if min(2 * p.area / p.length for p in polys) >= KISSING_WIDTH * radius:
            return loops
    return None


def pass_turns(xy: FloatArray, i: IntArray, j: IntArray, after_i: IntArray | None = None,
               after_j: IntArray | None = None) -> tuple[FloatArray, FloatArray, FloatArray]:
    """For each pair of edges i and j: how much the chain turns (degrees) across them,
    summed, and across each of the two edges that reconnect them the other way (from i, and
    from j); each turn taken between the arms of `ARM_NODES` nodes on either side (a short
    edge's own direction is noise). ``after_i``, ``after_j``: the nodes the passes run on
    from, where nodes between are left out (default i + 1 and j + 1)."""
    after_i = i + 1 if after_i is None else after_i
    after_j = j + 1 if after_j is None else after_j
    old = turn_across(xy, i, after_i) + turn_across(xy, j, after_j)
    return old, turn_across(xy, i, after_j), turn_across(xy, j, after_i)


def turn_across(xy: FloatArray, start: IntArray, end: IntArray) -> FloatArray:
    """How much closed chain ``xy`` turns (degrees) from arriving at node ``start`` to
    leaving node ``end``, between arms of `ARM_NODES` nodes."""
    n = len(xy)
    arriving = xy[start % n] - xy[(start - ARM_NODES) % n]
    leaving = xy[(end + ARM_NODES) % n] - xy[end % n]
    return angle_between(arriving, leaving)


def angle_between(a: FloatArray, b: FloatArray) -> FloatArray:
    """Angle (degrees) between the directions in each row of a and b."""
    norms = np.maximum(np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1), 1e-300)
    cos = np.einsum("ij,ij->i", a, b) / norms
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def _crossing_angle(xy: FloatArray, i: int, j: int) -> float:
    """Angle (degrees, 0-90) between edges i and j of closed chain ``xy``."""
    d1 = xy[(i + 1) % len(xy)] - xy[i]
    d2 = xy[(j + 1) % len(xy)] - xy[j]
    cos = abs(d1 @ d2) / max(np.linalg.norm(d1) * np.linalg.norm(d2), 1e-300)
    return float(np.degrees(np.arccos(min(cos, 1.0))))


def _simple(xy: FloatArray, closed: bool) -> bool:
    """Whether the chain is a valid polygon (closed) or a simple line (open)."""
    if closed:
        return bool(shapely.Polygon(xy).is_valid)
    return bool(shapely.LineString(xy).is_simple)


def crossing_edges(xy: FloatArray, closed: bool) -> IntArray:
    """(i, j), i < j: edge i (xy[i] -> xy[i+1]) properly crosses edge j, not adjacent to it."""
    return _edge_pairs(xy, closed, "crosses")


def touching_edges(xy: FloatArray, closed: bool) -> IntArray:
    """(i, j), i < j: edge i touches edge j, not adjacent to it (a point of one on the other)."""
    return _edge_pairs(xy, closed, "touches")


def _edge_pairs(xy: FloatArray, closed: bool, predicate: str) -> IntArray:
    """(i, j), i < j, of non-adjacent edges that meet by the shapely ``predicate``."""
    n = len(xy)
    m = n if closed else n - 1
    a = xy[:m]
    b = np.roll(xy, -1, axis=0)[:m] if closed else xy[1:]
    segs = shapely.linestrings(np.stack([a, b], axis=1))
    tree = shapely.STRtree(segs)
    i, j = tree.query(segs, predicate=predicate)
    keep = (i < j) & (j - i > 1) & ~(closed & (i == 0) & (j == m - 1))
    return np.column_stack([i[keep], j[keep]]).astype(np.intp)


def _disjoint_runs(pairs: IntArray) -> list[tuple[int, int]]:
    """Crossing pairs whose edges i .. j (the run and the two edges it changes) do not overlap,
    the shortest first."""
    order = np.argsort(pairs[:, 1] - pairs[:, 0], kind="stable")
    taken: list[tuple[int, int]] = []
    for i, j in pairs[order]:
        if all(j < s or i > e for s, e in taken):
            taken.append((int(i), int(j)))
    return taken


def swap_crossed_stretches(contours: list[OrderedContour], points: FloatArray
                           ) -> list[OrderedContour]:
    """Two closed chains that cross each other twice where the march jumped, with the stretches
    between the crossings swapped.

    Where two near-touching rings both have a gap in their samples at the same place, the
    march can run along one ring into the gap and jump to the other; the two chains then
    cross twice, each following the other's ring between the crossings, on edges that turn
    sharply (`SWITCH_TURN`). Swapping those
    stretches gives each chain its own ring back; the swap is kept only when neither new
    chain crosses itself or the other. Where both rings thinned out at several places, the
    chains cross at four or more, and swap at every crossing (`_swap_at_every_crossing`).
    Each chain's members go to the nearer new chain.
    """
    closed = [k for k, c in enumerate(contours) if c.closed and len(c.points) >= 4]
    if len(closed) < 2:
        return contours
    out = list(contours)
    rings = [shapely.LinearRing(contours[k].points) for k in closed]
    tree = shapely.STRtree(rings)
    first, second = tree.query(rings, predicate="crosses")
    for p, q in zip(first, second):
        a, b = closed[p], closed[q]
        if a >= b or out[a] is not contours[a] or out[b] is not contours[b]:
            continue
        swapped = _swap_pair(contours[a], contours[b], points)
        if swapped is not None:
            out[a], out[b] = swapped
    return out


def merge_overlapping_rings(contours: list[OrderedContour]) -> list[OrderedContour]:
    """Two closed chains that still cross where they overlap by a sliver: one outline whose
    two parts nearly touch (a 'k' whose arms meet the stem through a slit narrower than the
    tolerance: the march ran along the stem across the slit, and the arms became a ring of
    their own sharing the stem's edge). The outline is the union of the two, when it is one
    polygon with no new hole and the overlap is under `OVERLAP_SHARE` of the smaller ring's
    area (a hole crossing its outer ring overlaps it wholly, and stays apart).
    """
    closed = [k for k, c in enumerate(contours) if c.closed and len(c.points) >= 4]
    if len(closed) < 2:
        return contours
    polys = [shapely.Polygon(contours[k].points) for k in closed]
    rings = shapely.STRtree([p.exterior for p in polys])
    first, second = rings.query([p.exterior for p in polys], predicate="crosses")
    out: dict[int, OrderedContour | None] = {}
    for p, q in zip(first, second):
        a, b = closed[p], closed[q]
        if a >= b or a in out or b in out:
            continue
        merged = _union_ring(polys[p], polys[q])
        if merged is not None:
            members = np.union1d(contours[a].members, contours[b].members)
            out[a], out[b] = OrderedContour(merged, True, members), None
    if not out:
        return contours
    return [out.get(k, c) for k, c in enumerate(contours) if out.get(k, c) is not None]


def _union_ring(one: shapely.Polygon, two: shapely.Polygon) -> FloatArray | None:
    """The exterior of the union of two barely overlapping simple polygons, or None."""
    if not (one.is_valid and two.is_valid):
        return None
    overlap = one.intersection(two).area
    if overlap > OVERLAP_SHARE * min(one.area, two.area):
        return None
    union = shapely.union(one, two)
    if union.geom_type != "Polygon" or len(union.interiors) or not union.is_valid:
        return None
    ring = np.asarray(union.exterior.coords)[:-1]
    return ring if len(ring) >= 3 else None


def _swap_pair(one: OrderedContour, two: OrderedContour, points: FloatArray
               ) -> tuple[OrderedContour, OrderedContour] | None:
    """`swap_crossed_stretches` for one pair of closed chains, or None.

    Cut at the two crossings, each chain is two arcs; the new chains join an arc of one with
    an arc of the other. Of the two ways to pair them, the one kept has simple chains that do
    not meet, and the larger smaller area (the wrong pairing leaves a sliver between the
    rings)."""
    crossings = _crossings_between(one.points, two.points)
    if len(crossings) > 2 and len(crossings) % 2 == 0:
        return _swap_at_every_crossing(one, two, crossings, points)
    if len(crossings) != 2 or min(c[2] for c in crossings) < SWITCH_TURN:
        return None
    (i1, j1, _), (i2, j2, _) = sorted(crossings)
    p = _arcs(one.points, i1, i2)
    q = _arcs(two.points, *sorted((j1, j2)))
    if j1 > j2:  # two's arcs then run from the second crossing to the first
        q = (q[0][::-1], q[1][::-1])
    best, best_area = None, 0.0
    for pairing in (((p[0], q[0]), (p[1], q[1])), ((p[0], q[1]), (p[1], q[0]))):
        rings = [np.vstack([arc, other[::-1]]) for arc, other in pairing]
        if min(len(r) for r in rings) < 4:
            continue
        lines = [shapely.LinearRing(r) for r in rings]
        if not all(shapely.is_simple(line) for line in lines) or shapely.intersects(*lines):
            continue
        area = min(shapely.area(shapely.Polygon(r)) for r in rings)
        if area > best_area:
            best, best_area = rings, area
    return None if best is None else _with_members(best, one, two, points)


def _with_members(rings: list[FloatArray], one: OrderedContour, two: OrderedContour,
                  points: FloatArray) -> tuple[OrderedContour, OrderedContour]:
    """The two swapped ``rings`` as closed contours, each with the members of ``one`` and
    ``two`` nearer it."""
    members = np.concatenate([one.members, two.members])
    dist = np.stack([shapely.distance(shapely.points(points[members]), shapely.LinearRing(r))
                     for r in rings])
    mine = dist[0] <= dist[1]
    return (OrderedContour(rings[0], True, np.sort(members[mine])),
            OrderedContour(rings[1], True, np.sort(members[~mine])))


def _swap_at_every_crossing(one: OrderedContour, two: OrderedContour,
                            crossings: list[tuple[int, int, float]], points: FloatArray
                            ) -> tuple[OrderedContour, OrderedContour] | None:
    """`_swap_pair` where the chains cross at four places or more (the march jumped between
    the rings wherever both thinned out): both chains run the same way round, and at every
    crossing each continues along the other's arc from there (an X uncrossed the way that
    keeps the direction). Kept where that walks two simple rings that do not meet, most of
    the crossings turning sharply (`SWITCH_TURN`: smooth curves that truly cross run
    straight through); else None."""
    if np.median([c[2] for c in crossings]) < SWITCH_TURN:
        return None
    a, b = one.points, two.points
    if shapely.is_ccw(shapely.LinearRing(a)) != shapely.is_ccw(shapely.LinearRing(b)):
        b = b[::-1]
        crossings = [(e, (len(b) - 2 - f) % len(b), t) for e, f, t in crossings]
    along_a, along_b = _crossing_stations(a, b, crossings)
    arcs_a = _arcs_between(a, along_a)
    arcs_b = _arcs_between(b, along_b)
    rings, left = [], set(range(len(crossings)))
    while left:
        start = min(left)
        at, on, parts = start, 0, []
        while True:
            if on == 0:
                left.discard(at)
            arc, at = (arcs_a if on == 0 else arcs_b)[at]
            parts.append(arc)
            on = 1 - on
            if on == 0 and at == start:
                break
            if len(parts) > 2 * len(crossings):
                return None
        rings.append(np.vstack(parts))
    if len(rings) != 2 or min(len(r) for r in rings) < 4:
        return None
    lines = [shapely.LinearRing(r) for r in rings]
    if not all(shapely.is_simple(line) for line in lines) or shapely.intersects(*lines):
        return None
    return _with_members(rings, one, two, points)


def _crossing_stations(a: FloatArray, b: FloatArray, crossings: list[tuple[int, int, float]]
                       ) -> tuple[FloatArray, FloatArray]:
    """Where each crossing lies along closed chains ``a`` and ``b``: its edge's index plus
    how far along that edge (0 to 1), so that two crossings on one edge keep their order."""
    e = np.array([c[0] for c in crossings])
    f = np.array([c[1] for c in crossings])
    p, r = a[e], np.roll(a, -1, axis=0)[e] - a[e]
    q, s = b[f], np.roll(b, -1, axis=0)[f] - b[f]
    denom = r[:, 0] * s[:, 1] - r[:, 1] * s[:, 0]
    denom = np.where(np.abs(denom) > 0, denom, 1.0)
    qp = q - p
    t = (qp[:, 0] * s[:, 1] - qp[:, 1] * s[:, 0]) / denom
    u = (qp[:, 0] * r[:, 1] - qp[:, 1] * r[:, 0]) / denom
    return e + np.clip(t, 0.0, 1.0), f + np.clip(u, 0.0, 1.0)


def _arcs_between(xy: FloatArray, stations: FloatArray) -> dict[int, tuple[FloatArray, int]]:
    """For each crossing k (at ``stations[k]`` along closed chain ``xy``: `_crossing_stations`),
    the vertices from it on to the next crossing along the chain, and that crossing."""
    order = np.argsort(stations, kind="stable")
    n = len(xy)
    out = {}
    for pos, k in enumerate(order):
        nxt = int(order[(pos + 1) % len(order)])
        first = int(np.floor(stations[k])) + 1
        last = int(np.floor(stations[nxt])) + (n if pos + 1 == len(order) else 0)
        out[int(k)] = (xy[np.arange(first, last + 1) % n], nxt)  # the last runs on past 0
    return out


def _arcs(xy: FloatArray, e1: int, e2: int) -> tuple[FloatArray, FloatArray]:
    """The two arcs of closed chain ``xy`` cut inside edges ``e1 < e2``, both running from the
    first cut to the second: the vertices e1 + 1 .. e2, and e1 .. 0, n - 1 .. e2 + 1."""
    return xy[e1 + 1:e2 + 1], np.concatenate([xy[:e1 + 1][::-1], xy[e2 + 1:][::-1]])


def _crossings_between(a: FloatArray, b: FloatArray) -> list[tuple[int, int, float]]:
    """(edge of a, edge of b, turn in degrees) where closed chains a and b cross; the turn is
    the smaller of the two crossing edges' sharpest turn from an edge beside it."""
    seg = [shapely.linestrings(np.stack([xy, np.roll(xy, -1, axis=0)], axis=1)) for xy in (a, b)]
    i, j = shapely.STRtree(seg[1]).query(seg[0], predicate="crosses")
    turn_a, turn_b = _edge_turns(a), _edge_turns(b)
    return [(int(e), int(f), float(min(turn_a[e], turn_b[f]))) for e, f in zip(i, j)]


def _edge_turns(xy: FloatArray) -> FloatArray:
    """Per edge of closed chain ``xy``: the larger turn (degrees) at its two vertices."""
    at_vertex = turning(xy, True, step=1)  # edge i runs from vertex i to vertex i + 1
    return np.maximum(at_vertex, np.roll(at_vertex, -1))


def split_at_crossings(contours: list[OrderedContour], points: FloatArray
                       ) -> list[OrderedContour]:
    """Chains that still cross (two walls meeting at a T or an X, a stroke crossing another)
    split at the crossing point into pieces that meet there, each piece ending exactly on it.

    The crossing point joins every chain through it as a vertex, so the pieces' polygons meet
    only at their end points (a junction), never across each other. A chain's members go to the
    nearest of its pieces.
    """
    if not contours:
        return contours
    # a chain meeting itself after untangling is left to the fit (its polygon skips the spot);
    # cutting it there would open a closed outline
    pieces = split_at_crossings_of([c.points for c in contours], [c.closed for c in contours],
                                   between_only=True)
    out = []
    for k, contour in enumerate(contours):
        if k not in pieces:
            out.append(contour)
        else:
            out += share_members(pieces[k], contour.members, points)
    return out


def share_members(pieces: list[FloatArray], members: IntArray, points: FloatArray,
                  closed: bool = False) -> list[OrderedContour]:
    """Contours of the pieces of one chain (open pieces, or ``closed`` rings), each with the
    members nearest to it."""
    if not pieces:
        return []
    ends = [np.roll(p, -1, axis=0) if closed else p[1:] for p in pieces]
    a = np.concatenate([p[:len(e)] for p, e in zip(pieces, ends)])
    b = np.concatenate(ends)
    piece_of = np.repeat(np.arange(len(pieces)), [len(e) for e in ends])
    nearest = piece_of[nearest_of_segments(points[members], a, b)[0]]
    return [OrderedContour(p, closed, members[nearest == k]) for k, p in enumerate(pieces)
            if (nearest == k).any()]  # a piece that stands for no point is no curve
