"""Joining chain ends (paper §2's march across corners and gaps).

The links along the tangents leave a chain's end free where the march cannot see its next
point ahead: at a sharp corner (both neighbours of the corner node lie ahead of its tangent),
at the tip of a notch whose walls merged, and across a gap in the scan. `join_ends` joins free
ends (and lone nodes) that are each other's nearest free node, under the rules below, in a few
rounds, so that a lone node can bridge a gap. R is the neighbourhood reach (the radius, or
wider on noisy scans); every distance here is in R.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from ..types import FloatArray, IntArray
from .neighbourhoods import Nodes, group_extents

#: Rounds of joining: each joins mutual nearest free ends; a gap bridged by lone nodes needs
#: one round per node, and no case seen needs more than a few.
JOIN_ROUNDS = 8
#: Free nodes considered per end (the nearest first): an end's partner is among the nearest few.
JOIN_CANDIDATES = 5
#: Ends that face each other join across a gap in the scan of up to this many R.
FACING_GAP = 5.0
#: Ends join within this many R whatever their directions (sharp corners, merged notch tips).
ANY_DIRECTION_GAP = 4.0
#: An end faces another when the gap's component along its outward direction is at least this
#: fraction of the gap (the other end within about 45 degrees of straight ahead).
FACING_COS = 0.7
#: An end joins a partner it faces across a gap rather than the nearest free end beside it,
#: when that partner is at most this many times as far.
FACING_PREFERENCE = 1.5
#: A chain closes on itself only with at least this many nodes (fewer cannot enclose anything).
MIN_CLOSING_NODES = 4
#: A chain of at least this many nodes whose ends are within `LONG_CLOSE_GAP` R closes even when
#: neither end faces the other (the march crossed between a notch's walls).
LONG_CHAIN_NODES = 16
LONG_CLOSE_GAP = 3.0
#: A long chain closes across up to this many R when one end points at the other: at the tip
#: of a sharp notch the neighbourhoods sit between the walls, and the march on the second wall
#: stops several R short of the tip where the first wall's end is.
CLOSING_GAP = 8.0
#: On a clean scan such a closing join wider than `ANY_DIRECTION_GAP` R runs along points
#: within this many radii of it: a wedge slit's walls part a couple of radii by its mouth,
#: while a chain that ran out along one thin stroke and back along another (a thresholded
#: photograph's text) was closed across 13.8 tolerances with no point within 4 R...
CLOSING_SUPPORT = 2.0
#: ... except where both ends point at each other within about 25 degrees (this cosine): a
#: gap in the sampling of a smooth outline (a scan thinned to a quarter on one side: 6.2 R
#: without a point, its ends at 0.99 and 0.91; the photographed text's strokes, closed
#: across 7.7 R: 0.91 and 0.81).
IN_LINE_COS = 0.9
#: A way between two places runs along points where every spot of it, `ALONG_STEP` radii
#: apart, lies within this many radii of a point: two specks 2 tolerances apart leave a spot
#: a quarter radius from the middle of the empty stretch, a radius from the points, while a
#: sharp corner's tip and a notch's merged walls hold points nearer (`runs_along_points`).
ALONG_REACH = 0.75
ALONG_STEP = 0.375
#: On a clean scan, a join between two chains wider than this many R runs along points, or
#: continues a chain at least `SPAN_PER_GAP` x as long as the gap: a sharp corner's two legs
#: end by its tip, and a gap in the sampling of a curve is bridged from the curve's long
#: chains; two specks a few tolerances apart (stars in a photograph at a coarse tolerance),
#: whose ends face any way, are not.
ASIDE_GAP = 1.5
SPAN_PER_GAP = 2.0


def join_ends(nodes: Nodes, links: IntArray, support: Support | None = None) -> IntArray:
    """Join free ends (and lone nodes) that are each other's nearest free node.

    Ends join within `ANY_DIRECTION_GAP` R whatever their directions, and across a gap of up
    to `FACING_GAP` R when each end faces the other. A chain's two ends join only when the
    chain is long enough to close on itself and one end points at the other. The joining
    repeats (`JOIN_ROUNDS`), so a lone node can bridge a gap. With ``support`` (the scan's
    points), a join wider than `ANY_DIRECTION_GAP` R must run along points (`Support`).
    """
    reach = nodes.reach
    n = len(nodes.xy)
    for _ in range(JOIN_ROUNDS):
        degree = np.bincount(links.ravel(), minlength=n) if len(links) else np.zeros(n, int)
        free = np.flatnonzero(degree < 2)
        if len(free) < 2:
            break
        pairs = _mutual_nearest_ends(nodes, links, free, degree, reach, support)
        if not len(pairs):
            break
        links = np.vstack([links, pairs])
    return links


def _mutual_nearest_ends(nodes: Nodes, links: IntArray, free: IntArray, degree: IntArray,
                         reach: float, support: Support | None = None) -> IntArray:
    """One round of joining: pairs of free nodes that choose each other."""
    n = len(nodes.xy)
    comp = _components(links, n)
    size = np.bincount(comp)
    span = group_extents(nodes.xy, comp) if support is not None and support.aside > 0 else None
    outward = _outward(nodes.xy, links, free, degree)
    k = min(JOIN_CANDIDATES, len(free))
    dist, nbr = cKDTree(nodes.xy[free]).query(nodes.xy[free], k=k,
                                              distance_upper_bound=CLOSING_GAP * reach)
    best = np.full(len(free), -1)
    facing_best = np.full(len(free), -1)
    best_dist = np.full(len(free), np.inf)
    for col in range(1, k):
        cand = np.minimum(nbr[:, col], len(free) - 1)
        ok = np.isfinite(dist[:, col])
        same = comp[free] == comp[free[cand]]
        ok &= ~_linked(links, free, free[cand], n)
        gap = nodes.xy[free[cand]] - nodes.xy[free]
        ahead = np.einsum("ij,ij->i", gap, outward)
        ahead_other = np.einsum("ij,ij->i", -gap, outward[cand])
        # a chain closes on itself only when one of its ends points at the other: a short
        # straight run has its ends close together too, but both face away (at a sharp
        # notch one end may overshoot the other, so one end facing is enough; where the
        # march crossed between the notch's walls, neither faces, but a long chain whose
        # ends are this close is a closed contour)
        facing_one = (ahead > 0) | (ahead_other > 0)
        long_close = ((size[comp[free]] >= LONG_CHAIN_NODES)
                      & (dist[:, col] <= LONG_CLOSE_GAP * reach))
        ok &= ~same | ((size[comp[free]] >= MIN_CLOSING_NODES) & (facing_one | long_close))
        # a march never turns back: a lone node joins a chain's end only ahead of it (lone
        # nodes between two walls of a sharp notch would otherwise hook the end round)
        lone, lone_other = degree[free] == 0, degree[free[cand]] == 0
        ok &= ~(lone & ~lone_other & (ahead_other <= 0))
        ok &= ~(lone_other & ~lone & (ahead <= 0))
        facing = ((ahead > FACING_COS * dist[:, col])
                  & (ahead_other > FACING_COS * dist[:, col])
                  & (dist[:, col] <= FACING_GAP * reach))
        in_line = np.minimum(ahead, ahead_other) > IN_LINE_COS * dist[:, col]
        # a long chain closes across a wider gap when one of its ends points at the other: at
        # the tip of a sharp notch the march runs out on one wall and the other wall's end
        # points back along it
        closing = same & (size[comp[free]] >= LONG_CHAIN_NODES) & (
            (ahead > FACING_COS * dist[:, col]) | (ahead_other > FACING_COS * dist[:, col]))
        ok &= (dist[:, col] <= ANY_DIRECTION_GAP * reach) | facing | closing
        if support is not None:  # across a door, the empty floor between strays, or space
            wide = ok & (dist[:, col] > ANY_DIRECTION_GAP * reach)
            if not support.every_wide_join:
                wide &= closing & ~in_line
            wide = np.flatnonzero(wide)
            ok[wide] = support.along(nodes.xy[free[wide]], nodes.xy[free[cand[wide]]])
            if support.aside > 0:  # two specks are no curve with a gap in it
                short = (np.maximum(span[comp[free]], span[comp[free[cand]]])
                         < SPAN_PER_GAP * dist[:, col])
                aside = np.flatnonzero(ok & ~same & short & (dist[:, col] > ASIDE_GAP * reach))
                ok[aside] = runs_along_points(support.tree, nodes.xy[free[aside]],
                                              nodes.xy[free[cand[aside]]], support.aside)
        first = ok & (best < 0)
        best_dist = np.where(first, dist[:, col], best_dist)
        best[first] = cand[first]
        # an end that faces a partner across a gap continues there rather than turn aside to a
        # nearer end beside it (two rings with gaps side by side would merge into one)
        take = ok & facing & (facing_best < 0) & (dist[:, col] <= FACING_PREFERENCE * best_dist)
        facing_best[take] = cand[take]
    best = np.where(facing_best >= 0, facing_best, best)
    mutual = (best >= 0) & (best[np.maximum(best, 0)] == np.arange(len(free)))
    pairs = np.column_stack([free[mutual], free[best[mutual]]])
    return pairs[pairs[:, 0] < pairs[:, 1]]


@dataclass(frozen=True)
class Support:
    """The points a wide join must run along: points within a ``radius`` of every sample
    along it, a radius apart. ``every_wide_join``: on a noisy scan every join wider than
    `ANY_DIRECTION_GAP` R (a laser map's gap that wide is a door); on a clean one only a
    chain closing on itself where only one of its ends points at the other (`CLOSING_GAP`):
    at a notch's tip the join runs between the walls, while a chain that ran out along one
    thin stroke and back along another (a thresholded photograph's text, strokes under a
    tolerance wide) was closed across 13.8 tolerances of empty space. Ends in line with
    each other (`IN_LINE_COS`) close without: a gap in the sampling of a smooth outline.
    ``aside``: on a clean scan, the scan's radius, by which a join wider than `ASIDE_GAP` R
    between two chains, neither of them `SPAN_PER_GAP` x as long as the gap, runs along
    points (`runs_along_points`; 0: no such test)."""

    tree: cKDTree
    radius: float
    every_wide_join: bool = True
    aside: float = 0.0

    def along(self, a: FloatArray, b: FloatArray) -> np.ndarray:
        """Whether points lie along each segment from ``a[i]`` to ``b[i]``: within the
        support's radius of every sample along it, a radius apart."""
        return _along(self.tree, a, b, self.radius, self.radius)


def runs_along_points(tree: cKDTree, a: FloatArray, b: FloatArray, radius: float
                      ) -> np.ndarray:
    """Whether the way from each ``a[i]`` to ``b[i]`` runs along the points of ``tree``
    (`ALONG_REACH`, `ALONG_STEP`; ``radius``: the scan's), not across empty space."""
    return _along(tree, a, b, ALONG_REACH * radius, ALONG_STEP * radius)


def _along(tree: cKDTree, a: FloatArray, b: FloatArray, reach: float, step: float
           ) -> np.ndarray:
    """Whether a point of ``tree`` lies within ``reach`` of every sample, ``step`` apart,
    along each segment from ``a[i]`` to ``b[i]``."""
    if not len(a):
        return np.zeros(0, dtype=bool)
    steps = np.maximum(np.ceil(np.linalg.norm(b - a, axis=1) / step), 1).astype(int)
    owner = np.repeat(np.arange(len(a)), steps + 1)
    t = np.concatenate([np.linspace(0.0, 1.0, k + 1) for k in steps])
    at = a[owner] + t[:, None] * (b - a)[owner]
    near, _ = tree.query(at, distance_upper_bound=reach)
    return np.bincount(owner, ~np.isfinite(near), len(a)) == 0


def _outward(xy: FloatArray, links: IntArray, free: IntArray, degree: IntArray) -> FloatArray:
    """Unit direction out of the chain at each free node (away from its one neighbour)."""
    out = np.zeros((len(free), 2))
    if not len(links):
        return out
    neighbour = np.full(len(xy), -1)
    neighbour[links[:, 0]] = links[:, 1]
    neighbour[links[:, 1]] = links[:, 0]
    ends = degree[free] == 1
    vec = xy[free[ends]] - xy[neighbour[free[ends]]]
    norm = np.linalg.norm(vec, axis=1, keepdims=True)
    out[ends] = vec / np.where(norm > 0, norm, 1.0)
    return out


def _linked(links: IntArray, a: IntArray, b: IntArray, n: int) -> np.ndarray:
    """Whether each pair (a[i], b[i]) is already a link."""
    if not len(links) or not len(a):
        return np.zeros(len(a), dtype=bool)
    keys = np.concatenate([links[:, 0] * n + links[:, 1], links[:, 1] * n + links[:, 0]])
    return np.isin(a * n + b, keys)


def _components(links: IntArray, n: int) -> IntArray:
    graph = coo_matrix((np.ones(len(links)), (links[:, 0], links[:, 1])), shape=(n, n))
    return connected_components(graph, directed=False)[1]
