"""Marching (paper §2): thinned neighbourhoods linked along their tangents into chains.

A random (seeded) maximal set of neighbourhood centres at least radius / 2 apart is kept
(`thin`, Luby's parallel rounds), so consecutive ordered points are radius / 2 .. radius apart,
as one marching step would place them. Each node links to the nearest node ahead and the nearest
behind along its tangent (`link_nodes`); mutual links form chains, free ends are joined
(`wavepoly.ordering.joining`), and a chain that comes back to its start is closed. Short chains
alongside longer ones (noise split off a wall, a notch's tip) are absorbed (`drop_side_chains`).

References
----------
.. [1] M. Luby, "A simple parallel algorithm for the maximal independent set problem", SIAM J.
   Comput. 15(4), 1986, pp. 1036-1053.
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.ndimage import maximum_filter1d
from scipy.sparse import coo_matrix, csr_matrix
from scipy.sparse.csgraph import connected_components, depth_first_order
from scipy.spatial import cKDTree

from ..geometry import curve_line
from ..types import Chain, FloatArray, IntArray
from .joining import Support, join_ends
from .neighbourhoods import Nodes

#: Turning angle (degrees, measured over two ordered points each side) that marks a corner.
CORNER_TURN = 30.0
#: Perpendicular RMS spread (in radii) above which a straight neighbourhood is two merged walls.
MERGE_SPREAD = 0.35
#: Neighbours examined per node for its links ahead and behind: thinned nodes are at least
#: radius / 2 apart, so within `LINK_REACH` radii there are rarely more than a dozen.
LINK_NEIGHBOURS = 12
#: A node links to nodes within this many radii (a march's step is at most one radius).
LINK_REACH = 2.0
#: A neighbour is ahead (behind) when its direction is within 60 degrees of the tangent.
AHEAD_COS = 0.5
#: Chains of fewer nodes than this, all of them beside a longer chain, are side chains.
SIDE_CHAIN_NODES = 12
#: "Beside" a chain: within this many neighbourhood reaches of it.
SIDE_CHAIN_REACH = 2.5
#: Chains shorter than this have no straight stretch to measure for merged walls.
MIN_WALL_NODES = 5


def thin(xy: FloatArray, separation: float, rng: np.random.Generator) -> IntArray:
    """Indices of a random maximal subset of ``xy`` with pairwise distances >= ``separation``.

    Luby's algorithm: in each round, every undecided point whose random priority beats all its
    undecided neighbours is kept and its neighbours are dropped; O(log n) vectorized rounds.
    """
    n = len(xy)
    pairs = cKDTree(xy).query_pairs(separation, output_type="ndarray")
    a = np.concatenate([pairs[:, 0], pairs[:, 1]])
    b = np.concatenate([pairs[:, 1], pairs[:, 0]])
    priority = rng.permutation(n)
    state = np.zeros(n, dtype=np.int8)  # 0 undecided, 1 kept, -1 dropped
    while True:
        live = (state[a] == 0) & (state[b] == 0)
        a, b = a[live], b[live]
        best = np.full(n, -1)
        np.maximum.at(best, a, priority[b])
        chosen = (state == 0) & (priority > best)
        if not chosen.any():
            break
        state[chosen] = 1
        state[b[chosen[a]]] = -1
    return np.flatnonzero(state == 1)



def link_nodes(nodes: Nodes, radius: float, support: Support | None = None) -> IntArray:
    """Mutual links (pairs of node indices) between each node and its neighbours ahead/behind;
    then free ends joined (`join_ends`, wide joins along the ``support`` points when given)."""
    n = len(nodes.xy)
    k = min(LINK_NEIGHBOURS, n)
    if n < 2:
        return np.empty((0, 2), dtype=np.intp)
    dist, nbr = cKDTree(nodes.xy).query(nodes.xy, k=k, distance_upper_bound=LINK_REACH * radius)
    dist, nbr = dist[:, 1:], nbr[:, 1:]
    valid = np.isfinite(dist)
    nbr_safe = np.where(valid, nbr, 0)
    direction = (nodes.xy[nbr_safe] - nodes.xy[:, None, :]) / np.where(valid, dist, 1.0)[..., None]
    along = np.einsum("nkd,nd->nk", direction, nodes.tangent)
    ahead = _first(valid & (along > AHEAD_COS))
    behind = _first(valid & (along < -AHEAD_COS))
    pick = np.column_stack([ahead, behind])
    partner = np.where(pick >= 0, nbr_safe[np.arange(n)[:, None], np.maximum(pick, 0)], -1)
    cand = np.column_stack([np.repeat(np.arange(n), 2), partner.ravel()])
    cand = cand[cand[:, 1] >= 0]
    key_fwd = cand[:, 0] * n + cand[:, 1]
    key_rev = cand[:, 1] * n + cand[:, 0]
    mutual = np.isin(key_fwd, key_rev) & (cand[:, 0] < cand[:, 1])
    return join_ends(nodes, cand[mutual], support)


def _first(mask: np.ndarray) -> IntArray:
    """Column of the first True in each row of ``mask`` (neighbours are sorted by distance), -1."""
    idx = np.argmax(mask, axis=1)
    return np.where(mask.any(axis=1), idx, -1)

def chains_of(links: IntArray, n: int) -> list[Chain]:
    """Node sequences of each connected chain, and whether it closes on itself."""
    graph = coo_matrix((np.ones(len(links)), (links[:, 0], links[:, 1])), shape=(n, n)).tocsr()
    graph = graph + graph.T
    ncomp, comp = connected_components(graph, directed=False)
    degree = np.diff(graph.indptr)
    order = np.argsort(comp, kind="stable")
    bounds = np.searchsorted(comp[order], np.arange(ncomp + 1))
    local = np.zeros(n, dtype=np.intp)
    out = []
    for c in range(ncomp):
        members = order[bounds[c]:bounds[c + 1]]
        ends = members[degree[members] <= 1]
        closed = len(ends) == 0 and len(members) >= 3
        start = ends[0] if len(ends) else members[0]
        out.append(Chain(_walk(graph, members, start, local), bool(closed)))
    return out


def _walk(graph: csr_matrix, members: IntArray, start: int, local: IntArray) -> IntArray:
    """The depth-first order of one component (sorted ``members``) from ``start``, on its own
    rows of ``graph``: over the whole graph each walk cost the graph's size and kept a buffer
    of it (a noisy reading of the Freiburg map with 900,000 nodes died there at 15 GB).
    ``local``: scratch of the graph's size for the renumbering."""
    if len(members) == 1:
        return members.copy()
    rows = graph[members]
    local[members] = np.arange(len(members))
    own = csr_matrix((rows.data, local[rows.indices], rows.indptr),
                     shape=(len(members), len(members)))
    seq = depth_first_order(own, int(local[start]), directed=False, return_predecessors=False)
    return members[seq]


def drop_side_chains(nodes: Nodes, chains: list[Chain], short: int = SIDE_CHAIN_NODES
                     ) -> tuple[list[Chain], IntArray]:
    """Chains of fewer than ``short`` nodes that run alongside a longer chain, within
    `SIDE_CHAIN_REACH` neighbourhood reaches of it: noise split off a wall or the tip of a
    notch, not a contour.

    Returns the other chains, and the nodes of the dropped ones: their points go to the
    contour nearest to them (`contours_of`), which then covers them.
    """
    sizes = np.array([len(c) for c in chains])
    if len(chains) < 2 or (sizes >= short).all():
        return chains, np.empty(0, dtype=np.intp)
    node_ids = np.concatenate([c.nodes for c in chains])
    chain_of = np.repeat(np.arange(len(chains)), sizes)
    small = np.flatnonzero(sizes[chain_of] < short)  # positions of the short chains' nodes
    k = min(4 * short, len(node_ids))  # past its own nodes and a wall or two of others
    dist, nbr = cKDTree(nodes.xy[node_ids]).query(
        nodes.xy[node_ids[small]], k=k, distance_upper_bound=SIDE_CHAIN_REACH * nodes.reach)
    dist, nbr = dist.reshape(len(small), k), nbr.reshape(len(small), k)
    found = np.isfinite(dist)
    longer = found & (sizes[chain_of[np.where(found, nbr, 0)]]
                      > sizes[chain_of[small]][:, None])
    beside = np.zeros(len(chains), dtype=np.intp)
    np.add.at(beside, chain_of[small], longer.any(axis=1))
    drop = (sizes < short) & (beside == sizes)  # every node of it is beside a longer chain
    absorbed = [c.nodes for c, d in zip(chains, drop) if d]
    return ([chain for chain, d in zip(chains, drop) if not d],
            np.concatenate(absorbed) if absorbed else np.empty(0, dtype=np.intp))


def drop_crossing_loops(nodes: Nodes, chains: list[Chain], absorbed: IntArray,
                        short: int = SIDE_CHAIN_NODES) -> tuple[list[Chain], IntArray]:
    """Closed chains of fewer than ``short`` nodes that cross a longer chain: a loop the march
    made through strays beside a curve (sparse noisy samples), not a ring, for no ring of a
    slice crosses another's outline. Kept, it was split with the curve at the crossings, and
    a closed outline came out as open pieces. Their nodes join ``absorbed``.
    """
    sizes = np.array([len(c) for c in chains])
    loops = [k for k, c in enumerate(chains) if c.closed and 3 <= len(c) < short]
    if not loops or len(chains) < 2:
        return chains, absorbed
    lines = [curve_line(nodes.xy[c.nodes], c.closed) for c in chains]
    tree = shapely.STRtree(lines)
    drop = set()
    for k in loops:
        hits = tree.query(lines[k], predicate="intersects")
        if (sizes[hits] > sizes[k]).any():
            drop.add(k)
    if not drop:
        return chains, absorbed
    dropped = [chains[k].nodes for k in sorted(drop)]
    return ([c for k, c in enumerate(chains) if k not in drop],
            np.concatenate([absorbed, *dropped]).astype(np.intp))


def turning(xy: FloatArray, closed: bool, step: int = 2) -> FloatArray:
    """Turning angle (degrees) at each point between the chords to the points ``step`` away."""
    n = len(xy)
    if closed:
        prev, nxt = np.roll(xy, step, axis=0), np.roll(xy, -step, axis=0)
    else:
        idx = np.arange(n)
        prev, nxt = xy[np.maximum(idx - step, 0)], xy[np.minimum(idx + step, n - 1)]
    a, b = xy - prev, nxt - xy
    norm = np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1)
    cos = np.einsum("ij,ij->i", a, b) / np.where(norm > 0, norm, 1.0)
    turn = np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))
    return np.where(norm > 0, turn, 0.0)


def wide_nodes(nodes: Nodes, chains: list[Chain], radius: float) -> IntArray:
    """Nodes on straight stretches whose neighbourhood is as wide as two nearby walls (or a
    band of points as wide: `perpendicular_kurtosis` tells them apart).

    Two walls a distance d apart, each with the scan's noise, spread sqrt(noise**2 + d**2 / 4)
    about one regression line; the excess over the noise marks them when d / 2 is over
    `MERGE_SPREAD` x radius and over the noise (closer walls are lost in the noise).
    """
    out = []
    excess = np.sqrt(np.maximum(nodes.spread**2 - nodes.noise**2, 0.0))
    for chain in chains:
        seq, closed = chain.nodes, chain.closed
        if len(seq) < MIN_WALL_NODES:
            continue
        # a neighbourhood that reaches a corner spreads over both of its legs
        bend = turning(nodes.xy[seq], closed) >= CORNER_TURN
        width = 2 * int(np.ceil(2 * nodes.reach / radius)) + 1
        near_bend = maximum_filter1d(bend, width, mode="wrap" if closed else "nearest")
        wide = ~near_bend & (excess[seq] > max(MERGE_SPREAD * radius, nodes.noise))
        # walls run side by side for a while; a lone wide node is the noise of the estimate
        before, after = np.roll(wide, 1), np.roll(wide, -1)
        if not closed:
            before[0] = after[-1] = False
        out.append(seq[wide & (before | after)])
    return np.concatenate(out) if out else np.empty(0, dtype=np.intp)
