"""Contours from chains (paper §2): sharp corners restored, ends extended, members assigned.

Where a chain turns sharply, the run of turning points is replaced by the intersection of the
straight legs on either side, so corners stay sharp instead of being rounded by the
neighbourhood averaging (`sharpen_corners`). Every input point belongs to the contour of its
nearest ordered point (its *members*); points of chains too short to be curves, or farther than
the radius from their contour, are outliers.
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.spatial import cKDTree

from ..geometry import nearest_segment, nearest_site, polyline_length
from ..types import Chain, Contour, FloatArray, IntArray, OrderedContour
from .annuli import split_annuli
from .detours import cut_detours
from .folds import unfold_rings
from .gaps import close_gaps
from .marching import CORNER_TURN, SIDE_CHAIN_REACH, turning
from .mouths import join_through_mouths
from .necks import join_through_necks
from .neighbourhoods import Nodes
from .split_tips import rejoin_split_tips, thin_ring
from .stems import close_outlines
from .tips import extend_tips
from .untangle import (
    merge_overlapping_rings,
    share_members,
    split_at_crossings,
    split_kissing_rings,
    swap_crossed_stretches,
    untangle,
)
from .waists import split_at_waists

#: Chains shorter than this cannot hold a corner with two legs of two points each.
MIN_CORNER_NODES = 6
#: Two legs meeting at less than this angle (degrees) are too parallel to intersect reliably.
MIN_LEG_ANGLE = 25.0
#: A point belongs to a contour when a node of it is within this many radii.
MEMBER_REACH = 2.0
#: Members farther than this (in radii) from the chain mark a corner it cut.
CORNER_GAP = 0.6
#: A cut corner is a group of at least this many members beyond `CORNER_GAP` (lone noisy
#: points never qualify).
CORNER_GROUP = 3
#: ... and that group is at least this share of the segment's points: the points round a cut
#: corner are, strays about a dense noisy wall are not (inserting them zigzagged the walls of
#: the Intel map).
CORNER_SHARE = 0.15
#: A scan whose scatter about its curves is at most this fraction of the radius is a clean
#: sampling (the issue's σ ≤ ε / 4): a member farther than the radius from its chain is then
#: the tail of that scatter (1.07 ε from the true glyph at σ = ε / 4) or a feature the chain
#: rounded off, not a stray, and it stays a member out to `MEMBER_REACH`. On a noisier scan
#: (the Intel map at 0.1 measures 0.39) strays about a wall are outliers beyond one radius.
CLEAN_NOISE = 0.25
#: On a curve sampled with fewer than `DENSE_CURVE` points per radius, a scatter up to this
#: fraction of the radius is still a clean sampling: a silhouette traced from a bitmap whose
#: pixel is half the tolerance, sampled with noise ε / 4, measures 0.27-0.31 (the staircase
#: adds to the noise), and beyond one radius its noise left 1 or 2 points in 2000 out. A
#: laser map's walls hold tens of points per radius, and there a scatter of 0.3 is a halo
#: with strays in it (a ghost wall beside a dense wall measures 0.3).
SPARSE_CLEAN_NOISE = 0.33
#: On a clean scan, the nodes of a chain too short to be a contour, within this many radii
#: of a contour, count as its nodes: the tip of a notch the march left as 2 or 3 nodes (its
#: points then belong to the contour, which the corner insertion and the tips carry out to
#: them, instead of being outliers).
SHORT_CHAIN_REACH = 4.0
#: Below the scatter (`order_points`'s tolerance), members mark a cut corner only beyond this
#: many times the noise: Gaussian noise leaves 0.3 % of the points beyond 3 sigma, far below
#: `CORNER_SHARE`. (On fish.txt, a scatter as wide as the radius, the noise passed the radii
#: test from both sides in turn, and the inserted points zigzagged the chain across the band.)
CORNER_NOISE = 3.0
#: Rounds of corner insertion: each halves the gap a rounded corner leaves.
CORNER_ROUNDS = 4
#: A chain runs straight through a segment when its directions two segments before and after
#: differ by less than this (degrees): a corner the neighbourhoods rounded off turns the chain
#: by more over those five segments (a right angle rounded over 6 nodes: about 75).
STRAIGHT_TURN = 30.0
#: A dense curve holds at least this many points per radius of its chain (the Intel map's walls
#: 19, Freiburg's 118; silhouettes and glyphs 2-8). Along a straight stretch of one, a group
#: off the chain is no corner: neighbourhoods that hold hundreds of points follow any real
#: turn, and what lies off them is a second band beside the wall (a ghost wall), the foot of a
#: wall meeting it, or strays; reaching each with a spike zigzagged the walls of both maps.
#: Those points are left to the outliers' second reading (`strokes`). On a sparse sample a
#: few points off a straight stretch are a feature the reach smoothed over (the crab's mouth).
DENSE_CURVE = 12.0


def contours_of(pts: FloatArray, tree: cKDTree, nodes: Nodes, chains: list[Chain],
                absorbed: IntArray, radius: float, min_points: int, clean: bool,
                corner_gap: float | None = None, stems: bool = True
                ) -> tuple[list[OrderedContour], IntArray]:
    """Contours from chains of at least ``min_points`` nodes, each with its member points.

    A point belongs to the contour of its nearest node among those contours (within
    `MEMBER_REACH` radii; farther points, and the points of shorter chains that no contour is
    near, are outliers). The ``absorbed`` nodes of dropped side chains count as nodes of the
    contour nearest them where they lie beside it (`SIDE_CHAIN_REACH`: a speck's lone node
    beside another speck's chain, too short to be a contour, is no part of a ring 8 radii
    away), as do, on a clean scan, the nodes of chains shorter than
    ``min_points`` near a contour (`SHORT_CHAIN_REACH`). A member farther than the radius
    from its contour's chain (once the cut corners are restored) is an outlier too, unless
    the scan is ``clean`` (`clean_scan`). ``corner_gap``: how far off the chain a group of
    members marks a corner it cut (default `CORNER_GAP` radii).
    """
    short = [c.nodes for c in chains if len(c) < min_points]
    chains = [c for c in chains if len(c) >= min_points]
    if not chains:
        return [], np.arange(len(pts), dtype=np.intp)
    node_ids = np.concatenate([c.nodes for c in chains])
    owner = np.repeat(np.arange(len(chains)), [len(c) for c in chains])
    chain_nodes = cKDTree(nodes.xy[node_ids])
    if clean and short:  # the tip of a notch left as a chain of 2 or 3 nodes
        short_ids = np.concatenate(short)
        gap, _ = chain_nodes.query(nodes.xy[short_ids])
        absorbed = np.concatenate([absorbed, short_ids[gap <= SHORT_CHAIN_REACH * radius]])
    if len(absorbed):  # beside a contour, not beside a chain too short to be one
        gap, host = chain_nodes.query(nodes.xy[absorbed])
        near = gap <= SIDE_CHAIN_REACH * nodes.reach
        node_ids = np.concatenate([node_ids, absorbed[near]])
        owner = np.concatenate([owner, owner[host[near]]])
    dist, nearest = nearest_site(pts, nodes.xy[node_ids], MEMBER_REACH * radius)
    chain_of_point = np.where(np.isfinite(dist), owner[np.minimum(nearest, len(owner) - 1)], -1)
    order = np.argsort(chain_of_point, kind="stable")
    bounds = np.searchsorted(chain_of_point[order], np.arange(len(chains) + 1))
    contours: list[OrderedContour] = []
    outliers = [np.flatnonzero(chain_of_point < 0)]
    first_node = np.concatenate([[0], np.cumsum([len(c) for c in chains])])
    outlier_gap = (MEMBER_REACH if clean else 1.0) * radius
    corner_gap = CORNER_GAP * radius if corner_gap is None else corner_gap
    for c, chain in enumerate(chains):
        seq, closed = chain.nodes, chain.closed
        members = order[bounds[c]:bounds[c + 1]]
        xy = sharpen_corners(nodes.xy[seq], closed, tree, radius)
        if not closed:
            xy = _extend_ends(xy, pts[members], radius)
        # a member within CORNER_GAP radii of a node that is still a vertex needs no measuring:
        # it only counts among the points of the segments beside that vertex
        at = nearest[members] - first_node[c]
        own = (at >= 0) & (at < len(seq))  # not an absorbed node
        vertex = np.full(len(members), -1)
        vertex[own] = _vertex_index(nodes.xy[seq], xy)[at[own]]
        sure = (vertex >= 0) & (dist[members] <= corner_gap)
        unsure = np.flatnonzero(~sure)
        bends_only = not clean and _dense(xy, closed, len(members), radius)
        xy, far = _cover_cut_corners(xy, pts[members[unsure]], closed, radius, vertex[sure],
                                     outlier_gap, corner_gap=corner_gap, bends_only=bends_only)
        inside = np.ones(len(members), dtype=bool)
        inside[unsure[far]] = False
        outliers.append(members[~inside])
        rings = split_kissing_rings(xy, radius) if closed else [untangle(xy, closed)]
        if closed and clean:
            rings = [r for ring in rings for r in split_at_waists(ring, radius)]
        if len(rings) == 1:
            contours.append(OrderedContour(rings[0], closed, members[inside]))  # sorted
        else:
            contours += share_members(rings, members[inside], pts, closed=True)
    outliers = np.sort(np.concatenate(outliers)).astype(np.intp)
    if clean:  # on a noisy scan a group beyond a corner may as well be clutter
        contours, outliers = extend_tips(contours, outliers, pts, radius, outlier_gap)
    contours = merge_overlapping_rings(swap_crossed_stretches(contours, pts))
    contours = split_at_crossings(contours, pts)
    # on a noisy scan (a laser map) a room's wall and a short wall meeting it are lines
    if stems and clean:
        contours, outliers = close_gaps(close_outlines(contours, pts, radius), pts, radius,
                                        outliers)
        contours = _split_off_holes(_untangled(contours), pts, radius)
        contours = _split_grown(contours, join_through_mouths(
            rejoin_split_tips(contours, radius, pts), pts, radius), pts, radius)
        contours = join_through_necks(contours, pts, radius)
        if any(not c.closed for c in contours):  # the outlines closed since take their tips
            contours, outliers = extend_tips(contours, outliers, pts, radius, outlier_gap)
    if clean:
        contours = split_annuli(cut_detours(unfold_rings(contours, pts, radius), pts, radius),
                                pts, radius)
    return contours, outliers


def _split_grown(before: list[OrderedContour], after: list[OrderedContour],
                 pts: FloatArray, radius: float) -> list[OrderedContour]:
    """The contours ``after`` their tips were rejoined (`split_tips`, `mouths`), each outline
    that grew by thin rings alone split at its waists (`waists`): where the march swapped
    between two rings closer than the neighbourhoods at two places, it closed thin loops of
    half of one and half of the other, which join as each other's tips into one ring
    pinched where the two come close. An outline that a wide ring joined (a hole a slit
    reaches, a limb closed on itself) is left whole."""
    kept, now = {id(c) for c in before}, {id(c) for c in after}
    gone = [c for c in before if c.closed and id(c) not in now]
    # a ring that joined an outline lends it its first member (-1: a ring with none)
    firsts = np.array([g.members[0] if len(g.members) else -1 for g in gone], dtype=np.intp)
    out: list[OrderedContour] = []
    for c in after:
        if id(c) in kept or not c.closed:
            out.append(c)
            continue
        grown_by = np.flatnonzero((firsts < 0) | np.isin(firsts, c.members))
        if not all(thin_ring(gone[k].points, radius) for k in grown_by):
            out.append(c)
            continue
        rings = split_at_waists(c.points, radius)
        out += [c] if len(rings) == 1 else share_members(rings, c.members, pts, closed=True)
    return out


def _untangled(contours: list[OrderedContour]) -> list[OrderedContour]:
    """Closed outlines that cross themselves, untangled (`untangle`): on a noisy scan the
    two passes of a stem's walk, each along one wall of a slit narrower than the scatter,
    cross each other where the walls' points mingle."""
    return [OrderedContour(untangle(c.points, True), True, c.members)
            if c.closed and not shapely.LinearRing(c.points).is_simple else c
            for c in contours]


def _split_off_holes(contours: list[OrderedContour], pts: FloatArray, radius: float
                     ) -> list[OrderedContour]:
    """Outlines closed from open pieces that ran into a hole where it nearly touches them,
    each split into the outline and the hole (`waists`), their members shared."""
    out: list[OrderedContour] = []
    for c in contours:
        rings = split_at_waists(c.points, radius, holes_only=True) if c.closed else [c.points]
        out += [c] if len(rings) == 1 else share_members(rings, c.members, pts, closed=True)
    return out


def clean_scan(noise: float, radius: float, per_radius: float = np.inf,
               scatter: float = np.inf) -> bool:
    """Is a scan with this spread about its curves over a neighbourhood (``noise``), this
    scatter of its own (``scatter``, over a few scatters' window) and ``per_radius`` points
    per radius along them, a clean sampling (`CLEAN_NOISE`, `SPARSE_CLEAN_NOISE`)?

    On a curve sampled with fewer than `DENSE_CURVE` points per radius, the spread over a
    neighbourhood also holds the curve's bend; the points' own scatter within `CLEAN_NOISE`
    radii is then a clean sampling too (small shapes: a disk 5 tolerances across, traced from
    a bitmap and sampled with noise ε / 4, spreads 0.34-0.37 radii over a neighbourhood)."""
    if per_radius >= DENSE_CURVE:
        return noise <= CLEAN_NOISE * radius
    return noise <= SPARSE_CLEAN_NOISE * radius or scatter <= CLEAN_NOISE * radius


def _vertex_index(chain: FloatArray, xy: FloatArray) -> IntArray:
    """Index in ``xy`` of each point of ``chain`` that is (exactly) a vertex of it, else -1."""
    key, chain_key = xy[:, 0] + 1j * xy[:, 1], chain[:, 0] + 1j * chain[:, 1]
    order = np.argsort(key)
    at = np.minimum(np.searchsorted(key[order], chain_key), len(xy) - 1)
    return np.where(key[order][at] == chain_key, order[at], -1)


def _cover_cut_corners(xy: FloatArray, members: FloatArray, closed: bool, radius: float,
                       near_vertex: IntArray | None = None, outlier_gap: float | None = None,
                       rounds: int = CORNER_ROUNDS, corner_gap: float | None = None,
                       bends_only: bool = False) -> tuple[FloatArray, IntArray]:
    """Insert member points where a group of them lies off the chain (a corner it cut).

    Where `CORNER_GROUP` points tied to one chain segment are farther than ``corner_gap``
    (default `CORNER_GAP` radii) from the chain, and make up `CORNER_SHARE` of its points
    (`_cut_corner`), the farthest of them is inserted into that segment; a few rounds of
    this put a point on a corner that neighbourhood averaging rounded off. Lone noisy points
    never qualify, nor does a halo of strays about a dense wall (a few points among the many
    of each stretch); with ``bends_only`` (a dense curve, `DENSE_CURVE`), nor does a group
    beside a stretch the chain runs straight through (`STRAIGHT_TURN`) as it came: a vertex
    inserted at a bend beside it does not make it a bend (a ghost wall starting at a corner
    was reached from every vertex along it, round by round).
    ``near_vertex`` holds, for further points of the chain not in ``members``, the vertex each
    lies within the gap of: they count half to each segment beside it.
    Returns the new chain and the members still farther than ``outlier_gap`` (default: the
    radius) from it.
    """
    near_vertex = np.empty(0, dtype=np.intp) if near_vertex is None else near_vertex
    ring = closed and len(xy) >= 3
    gap = CORNER_GAP * radius if corner_gap is None else corner_gap
    # straight as the chain came: a vertex inserted beside a stretch must not make it a bend
    straight = _straight_segments(xy, ring) if bends_only else np.zeros(len(xy), dtype=bool)
    for round_ in range(rounds + 1):
        seg, dist = nearest_segment(members, xy, ring)
        far = np.flatnonzero(dist > gap)
        segs = np.empty(0, dtype=np.intp)
        if len(far) >= CORNER_GROUP and round_ < rounds:
            worst = np.full(len(xy), -1)
            order = far[np.argsort(dist[far])]
            worst[seg[order]] = order  # the last write per segment is its farthest point
            total = np.bincount(seg, minlength=len(xy)) + _beside(near_vertex, len(xy), ring)
            counts = np.bincount(seg[far], minlength=len(xy))
            segs = np.flatnonzero(_cut_corner(counts, total) & ~straight)
        if not len(segs):
            return xy, far[dist[far] > (radius if outlier_gap is None else outlier_gap)]
        near_vertex = near_vertex + np.searchsorted(segs + 1, near_vertex, side="right")
        xy = np.insert(xy, segs + 1, members[worst[segs]], axis=0)
        straight = np.insert(straight, segs + 1, straight[segs])
    raise AssertionError("unreachable")  # pragma: no cover


def _dense(xy: FloatArray, closed: bool, n_members: int, radius: float) -> bool:
    """Whether a chain with ``n_members`` points is a dense curve (`DENSE_CURVE`)."""
    return n_members * radius >= DENSE_CURVE * max(polyline_length(xy, closed), radius)


def _straight_segments(xy: FloatArray, ring: bool) -> np.ndarray:
    """Which segments (vertex i to i + 1) the chain runs straight through (`STRAIGHT_TURN`):
    the direction over the two segments before vertex i against that over the two after
    vertex i + 1."""
    n = len(xy)
    if n < 2:
        return np.zeros(n, dtype=bool)
    idx = np.arange(n)
    if ring:
        a0, a1, b0, b1 = xy[(idx - 2) % n], xy[idx], xy[(idx + 1) % n], xy[(idx + 3) % n]
    else:
        a0, a1 = xy[np.maximum(idx - 2, 0)], xy[idx]
        b0, b1 = xy[np.minimum(idx + 1, n - 1)], xy[np.minimum(idx + 3, n - 1)]
    da, db = a1 - a0, b1 - b0
    norm = np.linalg.norm(da, axis=1) * np.linalg.norm(db, axis=1)
    cos = np.einsum("ij,ij->i", da, db) / np.where(norm > 0, norm, 1.0)
    return (norm > 0) & (cos > np.cos(np.radians(STRAIGHT_TURN)))


def _beside(vertex: IntArray, n: int, ring: bool) -> FloatArray:
    """Points per segment of an ``n``-vertex chain from points at ``vertex``: half to each
    segment beside it (the one segment at an end of an open chain gets all)."""
    if not ring:  # segment i joins vertices i and i + 1; the last vertex starts none
        before, after = np.maximum(vertex - 1, 0), np.minimum(vertex, max(n - 2, 0))
    else:
        before, after = (vertex - 1) % n, vertex
    return 0.5 * (np.bincount(before, minlength=n) + np.bincount(after, minlength=n))[:n]


def _cut_corner(far: IntArray, members: IntArray) -> np.ndarray:
    """Which segments, with ``far`` of their ``members`` beyond the gap, cut a corner: a group
    of at least `CORNER_GROUP` that is at least `CORNER_SHARE` of the segment's points."""
    return (far >= CORNER_GROUP) & (far >= CORNER_SHARE * members)


def _extend_ends(xy: FloatArray, members: FloatArray, radius: float) -> FloatArray:
    """Move an open chain's end points out, within one radius, to its farthest member point."""
    out = xy.copy()
    for end, inner in ((0, 1), (-1, -2)):
        direction = out[end] - out[inner]
        length = np.linalg.norm(direction)
        if length == 0:
            continue
        direction /= length
        reach = (members - out[end]) @ direction
        lateral = np.abs((members - out[end]) @ np.array([-direction[1], direction[0]]))
        ahead = (reach > 0) & (reach <= radius) & (lateral < max(length, radius / 2))
        if ahead.any():
            out[end] = out[end] + direction * reach[ahead].max()
    return out


def sharpen_corners(xy: FloatArray, closed: bool, pts_tree: cKDTree, radius: float
                    ) -> FloatArray:
    """Replace each run of turning points by the intersection of the straight legs beside it,
    where that corner lies within a radius of the run and half a radius of the data. A closed
    chain whose corners would enclose no area is left as it is."""
    n = len(xy)
    if n < MIN_CORNER_NODES:
        return xy
    corner = turning(xy, closed) >= CORNER_TURN
    if not corner.any() or corner.all():
        return xy
    shifted = np.roll(corner, 1) if closed else np.concatenate([[False], corner[:-1]])
    starts = np.flatnonzero(corner & ~shifted)
    keep = np.ones(n, dtype=bool)
    new_xy = xy.copy()
    for s in starts:
        length = 1
        while length < n and corner[(s + length) % n] and (closed or s + length < n):
            length += 1
        run = (s + np.arange(length)) % n
        e = run[-1]
        before, after = [s - 2, s - 1], [e + 1, e + 2]
        if not closed and (before[0] < 0 or after[1] >= n):
            continue
        before, after = [i % n for i in before], [i % n for i in after]
        point = _intersect(xy[before[0]], xy[before[1]], xy[after[0]], xy[after[1]])
        if point is None:
            continue
        near_run = np.min(np.linalg.norm(xy[run] - point, axis=1)) <= radius
        has_data = pts_tree.query(point)[0] <= radius / 2
        if near_run and has_data:
            keep[run] = False
            keep[run[0]] = True
            new_xy[run[0]] = point
    sharp = new_xy[keep]
    if closed and not abs(Contour(sharp, True).signed_area) > 0:
        return xy  # a small ring all corners: its runs met at one point, which holds nothing
    return sharp


def _intersect(a0, a1, b0, b1) -> FloatArray | None:
    """Intersection of line a0a1 with line b0b1 if they cross at more than `MIN_LEG_ANGLE` (a
    leg of no length crosses nothing)."""
    da, db = a1 - a0, b1 - b0
    cross = da[0] * db[1] - da[1] * db[0]
    if not abs(cross) > np.sin(np.radians(MIN_LEG_ANGLE)) * np.linalg.norm(da) * np.linalg.norm(db):
        return None
    t = ((b0 - a0)[0] * db[1] - (b0 - a0)[1] * db[0]) / cross
    return a0 + t * da
