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

import numpy as np
import shapely

from ..types import FloatArray, IntArray, OrderedContour
from ..validity import split_at_crossings_of

#: Rounds of 2-opt moves; each round reverses every crossing run that no other run overlaps,
#: and real chains are simple after a few rounds (the chain shortens every time).
MAX_ROUNDS = 200


def untangle(xy: FloatArray, closed: bool) -> FloatArray:
    """The chain's points in an order whose polyline does not cross itself.

    Reverses the run between two crossing edges (a 2-opt move), shortest runs first, until no
    two non-adjacent edges cross or `MAX_ROUNDS` have passed.
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
    return out


def crossing_edges(xy: FloatArray, closed: bool) -> IntArray:
    """(i, j), i < j: edge i (xy[i] -> xy[i+1]) properly crosses edge j, not adjacent to it."""
    n = len(xy)
    m = n if closed else n - 1
    a = xy[:m]
    b = np.roll(xy, -1, axis=0)[:m] if closed else xy[1:]
    segs = shapely.linestrings(np.stack([a, b], axis=1))
    tree = shapely.STRtree(segs)
    i, j = tree.query(segs, predicate="crosses")
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
            out += _share_members(pieces[k], contour.members, points)
    return out


def _share_members(pieces: list[FloatArray], members: IntArray, points: FloatArray
                   ) -> list[OrderedContour]:
    """Open contours of the pieces, each with the members nearest to it."""
    if not pieces:
        return []
    lines = [shapely.linestrings(p) for p in pieces]
    where = shapely.points(points[members])
    dist = np.stack([shapely.distance(where, line) for line in lines])
    nearest = np.argmin(dist, axis=0)
    return [OrderedContour(p, False, members[nearest == k]) for k, p in enumerate(pieces)
            if (nearest == k).any()]  # a piece that stands for no point is no curve
