"""Two shapes that nearly touch, read as one ring pinched at a waist.

Where the outlines of two shapes run closer than the neighbourhoods at one spot (blobs that
nearly touch, a pixel's corner apart), the march may run along one outline into the narrow
place and on along the other, and come back the same way on the far side: the chain is the
outline of their union, pinched at a waist, and it does not cross itself (where it does,
`untangle.split_kissing_rings` splits it). At the waist each of its two passes turns sharply
from one shape onto the other, while each shape's own outline runs smoothly past it.
Reconnecting the two passes the other way (a 2-opt move that splits the ring) gives the two
shapes; that is kept where it takes away most of the turning at the waist, the outlines run
smoothly into it, and it leaves two simple rings side by side, each wide. A limb on a narrow
root turns as much when closed apart (across the root, back along the limb) and stays one; a
chain that zigzags through a narrow part turns everywhere there and is left alone. Shapes
that truly touch at a point (blobs a bitmap joins at a pixel's corner) read the same as
shapes a fraction of a tolerance apart, and are split too.

A hole that nearly touches its outline reads the same way: the march runs from the outline
into the hole, round it and back out (often at a corner of the hole, whose sides part from
the wall there). Split, the hole lies inside the outline; it is kept apart where the outline
closes smoothly and the hole does not close on a spike, since where a slit runs from the
outline into the hole (a keyhole, one outline) the one keeps the slit's walls as a notch or
the other as a spike. A slit narrower than about ε (its walls' noise) reads like a hole's
wall as thin, and is split too. Outlines that the stems pass closes from open pieces
(`stems`) are searched for such holes too.

Two rings closer than the neighbourhoods that run side by side for a while (circles 2 ε
apart with noise ε / 4) read the same where one's points thin out: the march steps across
on a node or two between them and back beside where it stepped in, a hairpin each way.
Those bridge nodes are left out of both rings (`BRIDGE_NODES`).
"""

from __future__ import annotations

from functools import partial

import numpy as np
import shapely

from ..geometry import polyline_length
from ..types import FloatArray, IntArray
from .marching import turning
from .untangle import (
    ARM_NODES,
    MIN_LOOP_NODES,
    angle_between,
    pass_turns,
    split_repeatedly,
    turn_across,
)

#: Two passes of a ring at most this many radii apart may be a waist: the march crosses
#: between two outlines that come within about a radius of each other, and where they run
#: close for a while it may cross a few radii on (disks 1 ε apart with noise ε / 8: passes
#: 1.06 radii apart; a hole 0.5-1 ε from its outline: 1.5-2.2; 3 split a blob at a neck
#: 2 ε wide).
WAIST_GAP = 2.5
#: ... and the edges that close each shape across the waist are at most this many radii
#: long: where two large disks run within a radius of each other for a few radii, the march
#: follows one of them through that stretch and crosses at its far end (disks 12-30 ε
#: across, 0.5-1 ε apart: closing edges up to 4.5 radii).
CLOSING_EDGE = 5.0
#: Splitting must take away at least this much turning (degrees, over both passes): each pass
#: turns from one shape onto the other, where each shape's own outline runs on (blobs a
#: pixel's corner apart gained 68-150, disks 0.5-1 ε apart up to 230; a limb closed across
#: its root gains nothing; 30 split a silhouette's body at a narrow place).
TURN_GAIN = 60.0
#: ... where the outlines run smoothly into the waist: the median turn (degrees) of the
#: `ARM_NODES` nodes on either side of each pass is at most this (blobs: 1-13; a chain
#: zigzagging through a thin part of a silhouette traced from a bitmap: 60 and more).
ARM_TURN = 30.0
#: A pass may cross the waist by up to this many nodes between the shapes (where one
#: shape's points thin out, the march steps across on a node between them), left out of
#: both rings.
BRIDGE_NODES = 2
#: ... where that pass turns back by more than this (degrees): the march ran along one shape
#: and back along the other (a neck's wall turns 90 degrees at each end).
BRIDGE_TURN = 135.0
#: ... and where the two rings run side by side for at least this many nodes each...
BRIDGED_RUN = 8
#: ... and each is at least this many radii wide (twice its area over its perimeter): at a
#: small shape's scale a bridge of nodes reads the same as a neck or the gap between two
#: serifs (STIX 'h' and Computer Modern's 'r' at ε 0.8 lost their counter and terminal
#: as rings of their own); circles 30 ε across are 28 radii wide.
BRIDGED_WIDTH = 8.0
#: Each shape is at least this many radii wide (twice its area over its perimeter, a disk's
#: radius): a disk 4 radii across, the smallest ring counted as a shape of its own.
WAIST_WIDTH = 2.0
#: An outline split from a hole inside it closes turning by at most this (degrees) across the
#: edge that closes it: the outline runs smoothly past the thin wall (1-30 in the hole sweep),
#: where a slit's walls left on it would turn back into the slit.
HOLE_CLOSING_TURN = 60.0
#: The hole may close at a corner of its own (a square hole's), but not on a spike where it
#: keeps a slit's walls: no node within this many radii of the edge that closes it ...
SPIKE_LENGTH = 3.0
#: ... turns by more than this (degrees) between its arms (a square hole's corner 54-93 in
#: the hole sweep; the tip of a slit 1-1.5 ε wide that a hole kept, 124-177) ...
SPIKE_TURN = 120.0
#: ... each this many radii long (a slit's square tip turns 135 degrees between arms 2.5
#: radii long where it is 1.5 radii wide, twice 90 within 1.5 of each other) ...
SPIKE_ARM = 2.5
#: ... or this share of the hole's perimeter where that is shorter (a circle turns 72 degrees
#: between arms a tenth of its perimeter long: a small round hole is no spike).
SPIKE_ARMS_ROUND = 10.0


def split_at_waists(xy: FloatArray, radius: float, holes_only: bool = False
                    ) -> list[FloatArray]:
    """A closed chain pinched at waists, as the rings of the shapes that nearly touch there.

    Each split leaves two rings that are split again in turn, up to `untangle.MAX_SPLITS`;
    ``holes_only``: split off only holes that nearly touch their outline.

    References
    ----------
    .. [1] G. A. Croes, "A method for solving traveling-salesman problems", Operations
       Research 6(6), 1958, pp. 791-812 (the 2-opt move).
    """
    return split_repeatedly(xy, partial(_waist_split, radius=radius, holes_only=holes_only))


def _waist_split(xy: FloatArray, radius: float, holes_only: bool = False
                 ) -> list[FloatArray] | None:
    """The two rings of the waist of closed chain ``xy`` that gains the most turning, or
    None where no waist splits it into simple, wide rings side by side. A pass may cross
    the waist by a node or two between the shapes (`BRIDGE_NODES`), left out of both."""
    n = len(xy)
    if n < 2 * MIN_LOOP_NODES:
        return None
    near_i, near_j = _near_edges(xy, WAIST_GAP * radius)
    turn = turning(xy, True, step=1)
    # two loops each BRIDGED_WIDTH wide are each at least 2 pi times that long, less the
    # edges that close them
    shortest = (4 * np.pi * BRIDGED_WIDTH - 2 * CLOSING_EDGE) * radius
    bridges = BRIDGE_NODES if polyline_length(xy, True) >= shortest else 0
    found = [_waists(xy, near_i, near_j, a, b, radius, turn)
             for a in range(bridges + 1) for b in range(bridges + 1)]
    i, j, a, b, gain, new_i, new_j = (np.concatenate(f) for f in zip(*found))
    for k in np.argsort(-gain, kind="stable"):  # the largest gain first, then the first pair
        loops = [xy[np.arange(i[k] + 1 + a[k], j[k] + 1)],
                 xy[np.arange(j[k] + 1 + b[k], i[k] + n + 1) % n]]
        if (a[k] or b[k]) and not _side_by_side(loops, radius):
            continue  # a neck or a glyph's stroke, not two wide rings a gap apart
        # the edge from j closes the first loop, the edge from i the second
        if _apart(loops, radius, (float(new_j[k]), float(new_i[k])), holes_only):
            return loops
    return None


def _side_by_side(loops: list[FloatArray], radius: float) -> bool:
    """Whether both loops are at least `BRIDGED_WIDTH` radii wide and at least
    `BRIDGED_RUN` nodes of each lie within `WAIST_GAP` radii of the other: two wide rings
    that run side by side for a while, which the march crossed between where one's points
    thin out, not lobes that a narrow neck joins, nor a small shape's parts."""
    polygons = [shapely.Polygon(loop) for loop in loops]
    if min(2 * p.area / max(p.length, 1e-300) for p in polygons) < BRIDGED_WIDTH * radius:
        return False
    one, two = (p.exterior for p in polygons)
    return all(int((shapely.distance(shapely.points(loop), other) <= WAIST_GAP * radius).sum())
               >= BRIDGED_RUN for loop, other in ((loops[0], two), (loops[1], one)))


def _waists(xy: FloatArray, i: IntArray, j: IntArray, a: int, b: int, radius: float,
            turn: FloatArray) -> tuple[np.ndarray, ...]:
    """Of the pairs of edges i and j near each other, those that make a waist when the
    ``a`` nodes after i and the ``b`` after j are left out: the loops keep
    `MIN_LOOP_NODES` nodes, the edges that close them are at most `CLOSING_EDGE` radii,
    the split takes away more than `TURN_GAIN` of turning, and the outlines run smoothly
    into the waist (``turn``: each node's turn). Returns i, j, a, b, the gain and the turns
    across the closing edges from i and from j."""
    n = len(xy)
    after_i, after_j = i + 1 + a, (j + 1 + b) % n
    keep = (j + 1 - after_i >= MIN_LOOP_NODES) & (i + n + 1 - (j + 1 + b) >= MIN_LOOP_NODES)
    closing = np.maximum(np.linalg.norm(xy[j] - xy[after_i % n], axis=1),
                         np.linalg.norm(xy[i] - xy[after_j], axis=1))
    keep &= closing <= CLOSING_EDGE * radius
    i, j, after_i, after_j = i[keep], j[keep], after_i[keep], after_j[keep]
    old, new_i, new_j = pass_turns(xy, i, j, after_i, after_j)
    gain = old - new_i - new_j
    keep = (gain > TURN_GAIN) & _smooth_arms(turn, i, j, after_i, after_j)
    for skipped, start, end in ((a, i, after_i), (b, j, after_j)):
        if skipped:  # the nodes left out bridge a hairpin, not a neck's wall
            keep &= turn_across(xy, start, end) > BRIDGE_TURN
    k = int(keep.sum())
    return (i[keep], j[keep], np.full(k, a), np.full(k, b), gain[keep], new_i[keep],
            new_j[keep])


def _near_edges(xy: FloatArray, gap: float) -> tuple[IntArray, IntArray]:
    """(i, j), i < j: edges i and j of closed chain ``xy`` within ``gap`` of each other,
    with at least `MIN_LOOP_NODES` nodes between them either way round."""
    n = len(xy)
    segs = shapely.linestrings(np.stack([xy, np.roll(xy, -1, axis=0)], axis=1))
    i, j = shapely.STRtree(segs).query(segs, predicate="dwithin", distance=gap)
    keep = (i < j) & (j - i >= MIN_LOOP_NODES) & (n - (j - i) >= MIN_LOOP_NODES)
    return i[keep], j[keep]


def _smooth_arms(turn: FloatArray, i: IntArray, j: IntArray, after_i: IntArray,
                 after_j: IntArray) -> np.ndarray:
    """Whether the chain runs smoothly into the waist at each pair of passes, from i to
    ``after_i`` and from j to ``after_j``: the median turn of the `ARM_NODES` nodes before
    each pass and after it is at most `ARM_TURN`."""
    before = np.arange(-ARM_NODES, 0)
    beyond = np.arange(1, 1 + ARM_NODES)
    arms = np.concatenate([i[:, None] + before, after_i[:, None] + beyond,
                           j[:, None] + before, after_j[:, None] + beyond], axis=1) % len(turn)
    return np.median(turn[arms], axis=1) <= ARM_TURN


def _apart(loops: list[FloatArray], radius: float, closing_turns: tuple[float, float],
           holes_only: bool = False) -> bool:
    """Whether both loops are simple, lie side by side or one wholly inside the other without
    meeting, and are both at least `WAIST_WIDTH` radii wide. One inside the other is a hole
    that nearly touches its outline only where the outline closes smoothly (its turn in
    ``closing_turns``, the turns across the edges that close the two loops, at most
    `HOLE_CLOSING_TURN`) and the hole not on a spike (`_closes_on_a_spike`): where a slit runs
    from the outline into the hole, one or the other keeps the slit's walls. The hole may
    close at a corner of its own: where a hole's corner nears the wall, the march crosses the
    wall there. ``holes_only``: side by side does not count."""
    one, two = (shapely.Polygon(loop) for loop in loops)
    if not (one.is_valid and two.is_valid):
        return False
    if shapely.intersects(one, two):
        if one.contains_properly(two):
            outline_turn, hole = closing_turns[0], loops[1]
        elif two.contains_properly(one):
            outline_turn, hole = closing_turns[1], loops[0]
        else:
            return False
        if outline_turn > HOLE_CLOSING_TURN or _closes_on_a_spike(hole, radius):
            return False
    elif holes_only:
        return False
    return min(2 * p.area / p.length for p in (one, two)) >= WAIST_WIDTH * radius


def _closes_on_a_spike(loop: FloatArray, radius: float) -> bool:
    """Whether ``loop`` turns back on itself near the edge that closes it (from its last node
    to its first): at a node within `SPIKE_LENGTH` radii of it, the arms `SPIKE_ARM` radii
    long (a `SPIKE_ARMS_ROUND`-th of the loop's length where that is shorter) turn by more
    than `SPIKE_TURN` degrees."""
    ring = shapely.LinearRing(loop)
    length = ring.length
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(loop, axis=0), axis=1))])
    closing_starts = arc[-1]
    near = (arc <= SPIKE_LENGTH * radius) | (arc >= closing_starts - SPIKE_LENGTH * radius)
    at, arm = arc[near], min(SPIKE_ARM * radius, length / SPIKE_ARMS_ROUND)
    back = shapely.get_coordinates(shapely.line_interpolate_point(ring, (at - arm) % length))
    ahead = shapely.get_coordinates(shapely.line_interpolate_point(ring, (at + arm) % length))
    return bool((angle_between(loop[near] - back, ahead - loop[near]) > SPIKE_TURN).any())
