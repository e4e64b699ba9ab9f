"""Validity in the fewest-vertex selection: the chords of a path that break it, forbidden.

`wavepoly.simplify.select_vertices` solves the fewest-edge path over feasible chords, then
checks it: a chord that meets an obstacle, or another chord of the path (a self-crossing or a
fold), is made infeasible and the path is solved again. The edges of the backbone (the
verified polygon the selection may always fall back on) are never forbidden, so a path always
exists. Where a family of chords meets the same backbone edges, one chord per round, they are
forbidden together after a few exact rounds.
"""

from __future__ import annotations

import numpy as np
import shapely

from .types import FloatArray, IntArray
from .validity import bad_edges

#: Rounds of forbidding the chords that break validity and solving again; each round removes
#: every bad chord of the current path, and real contours settle within a few. A slit whose
#: walls run closer than the tolerance for a long way took 50-200 (silhouette 13: 38 vertices,
#: where the simple backbone the caller falls back to has 970).
MAX_VALIDITY_ROUNDS = 200
#: Rounds that forbid only the path's own bad chords (the exact optimum under validity); a
#: path still crossing after these meets the backbone's edges with a family of chords, one
#: per round (a noisy silhouette's spike of the backbone across a wall's long chord: 200
#: rounds, each forbidding the chord one vertex along, and the fallback had 589 vertices
#: where the selection had 73), and they are forbidden together (`forbid_across`).
EXACT_ROUNDS = 20


def fixed_edges_met(vertices: FloatArray, path: IntArray, bad: list[tuple[int, int]], k: int,
                    fixed: set[tuple[int, int]]) -> FloatArray:
    """The backbone (``fixed``) edges of ``path`` that its ``bad`` chords meet, as (m, 2, 2)
    segments."""
    a, b = path[:-1], path[1:]
    is_fixed = np.array([(int(x) % k, int(y - x)) in fixed for x, y in zip(a, b)], dtype=bool)
    if not is_fixed.any():
        return np.empty((0, 2, 2))
    edges = np.stack([vertices[a[is_fixed] % k], vertices[b[is_fixed] % k]], axis=1)
    chords = np.array([[vertices[x % k], vertices[y % k]] for x, y in bad])
    tree = shapely.STRtree(shapely.linestrings(edges))
    _, hit = tree.query(shapely.linestrings(chords), predicate="intersects")
    return edges[np.unique(hit)]


def forbid_across(feasible: list[np.ndarray], vertices: FloatArray, edges: FloatArray, k: int,
                  closed: bool, fixed: set[tuple[int, int]]) -> None:
    """Mark infeasible every chord (but the backbone's) that meets one of ``edges`` other
    than at a shared end."""
    if not len(edges):
        return
    rows = np.repeat(np.arange(len(feasible)), [len(f) for f in feasible])
    spans = np.concatenate([np.flatnonzero(f) + 1 for f in feasible] or [np.zeros(0, int)])
    rows = rows[np.concatenate(feasible).astype(bool)] if len(rows) else rows
    a, b = vertices[rows % k], vertices[(rows + spans) % k]
    lo, hi = edges.min(axis=(0, 1)), edges.max(axis=(0, 1))
    near = np.all((np.minimum(a, b) <= hi) & (np.maximum(a, b) >= lo), axis=1)
    rows, spans, a, b = rows[near], spans[near], a[near], b[near]  # the rest miss every edge
    tree = shapely.STRtree(shapely.linestrings(edges))
    chord, edge = tree.query(shapely.linestrings(np.stack([a, b], axis=1)),
                             predicate="intersects")
    shares = np.zeros(len(chord), dtype=bool)
    for end in (a, b):
        for tip in (edges[:, 0], edges[:, 1]):
            shares |= np.all(end[chord] == tip[edge], axis=1)
    for x, span in zip(rows[chord[~shares]], spans[chord[~shares]]):
        if (int(x) % k, int(span)) not in fixed:
            forbid(feasible, int(x), int(x + span), k, closed)


def invalid_chords(vertices: FloatArray, path: IntArray, k: int, closed: bool,
                   obstacles: shapely.STRtree | None, fixed: set[tuple[int, int]]
                   ) -> list[tuple[int, int]]:
    """Chords (a, b) of ``path`` that break validity and may be forbidden."""
    ring = path[:-1] if closed else path
    bad = bad_edges(vertices[ring % k], closed, obstacles)
    ends = np.column_stack([path[:-1], path[1:]])[bad]
    return [(int(a), int(b)) for a, b in ends if (int(a) % k, int(b) - int(a)) not in fixed]


def forbid(feasible: list[np.ndarray], a: int, b: int, k: int, closed: bool) -> None:
    """Mark chord (a, b) infeasible (on a closed contour, on both turns of the unrolling)."""
    rows = (a % k, a % k + k) if closed else (a,)
    for row in rows:
        if row < len(feasible) and b - a - 1 < len(feasible[row]):
            feasible[row][b - a - 1] = False


def allow_backbone(feasible: list[np.ndarray], backbone: IntArray, k: int, closed: bool
                   ) -> set[tuple[int, int]]:
    """Mark the edges of an already verified polygon (vertex indices ``backbone``) feasible,
    so that a path always exists; the caller verifies the choice again. Returns the edges as
    (start vertex, span) pairs."""
    a = backbone if not closed else np.concatenate([backbone, backbone + k])
    b = np.roll(a, -1)[:-1]
    a = a[:-1]
    if closed:
        b = np.where(b <= a, b + k, b)
    for x, y in zip(a, b):
        if 0 < y - x < len(feasible) - x:
            if y - x > len(feasible[x]):  # beyond where the cone test stopped
                feasible[x] = np.pad(feasible[x], (0, y - x - len(feasible[x])))
            feasible[x][y - x - 1] = True
    return {(int(x) % k, int(y - x)) for x, y in zip(a, b)}
