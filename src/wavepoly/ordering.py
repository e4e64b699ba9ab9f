"""Ordering (paper §2, "Data sorting"): unorganized planar points -> ordered, thinned contours.

The paper marches from a random start point along the least-squares tangent of a fixed-radius
neighbourhood, one neighbourhood at a time, each step summarizing the points ahead by one ordered
point. This module computes the same ingredients for every neighbourhood at once, so that no
Python loop runs over points:

1. *Neighbourhoods*: the plane is cut into cells of radius/2; every occupied cell seeds a
   neighbourhood of the fixed ``radius``, summarized by its centroid and the least-squares
   regression line through it (the tangent: the principal axis of the neighbourhood). Dense
   clouds enter these sums as one weighted atom per cell of radius/8 (`_atoms`). On a noisy
   scan (bell-shaped scatter about the curves, `_noise_level`) the neighbourhoods reach 5 x the
   noise instead, up to 4 x radius, so that the tangent follows the curve, not the scatter.
2. *Thinning*: a random (seeded) maximal set of centroids at least radius/2 apart is kept
   (Luby's parallel rounds), so consecutive ordered points are radius/2 .. radius apart, as
   one marching step would place them.
3. *Marching*: each ordered point links to the nearest point ahead and the nearest point behind
   along its tangent; mutual links form chains, a chain that comes back to its start is a closed
   contour. Chain ends that are each other's nearest free end are joined (sharp corners, where
   both neighbours lie ahead of the tangent, and gaps in the scan). Where the chain turns
   sharply, the run of turning points is replaced by the intersection of the straight legs on
   either side, so corners stay sharp instead of being rounded by the neighbourhood averaging.
   Short chains alongside longer ones (noise split off a wall, a notch's tip) are absorbed.
4. Every input point belongs to the contour of its nearest ordered point (``members``); points of
   contours too short to be curves, or farther than ``radius`` from their contour, are outliers.

All neighbour queries use `scipy.spatial.cKDTree`; the cost is O(n log n).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy.ndimage import maximum_filter1d
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components, depth_first_order
from scipy.spatial import cKDTree

from .errors import DataError, check_tolerance
from .geometry import farther_than
from .io.readers import validate_points
from .types import FloatArray, IntArray, OrderedContour, Ordering

#: Turning angle (degrees, measured over two ordered points each side) that marks a corner.
CORNER_TURN = 30.0
#: Perpendicular RMS spread (in radii) above which a straight neighbourhood is two merged walls.
MERGE_SPREAD = 0.35
#: On noisy scans the neighbourhoods reach this many times the noise level (at most 4 radii):
#: wide enough that the regression line follows the curve, not the scatter across it.
NOISE_REACH = 5.0
#: Kurtosis of the perpendicular scatter below which a wide neighbourhood is two walls, not a
#: band of points (two sharp walls: 1; a flat band: 1.8).
MERGE_KURTOSIS = 1.5
#: Kurtosis of the perpendicular scatter above which it counts as noise (a Gaussian has 3; two
#: sharp walls side by side have 1, a flat band 1.8).
NOISE_KURTOSIS = 2.2


@dataclass(frozen=True)
class _Nodes:
    """Neighbourhood summaries: position (centroid), unit tangent, shape of the scatter."""

    xy: FloatArray
    tangent: FloatArray
    ratio: FloatArray  # smaller / larger principal variance
    spread: FloatArray  # perpendicular RMS distance of the neighbourhood's points
    reach: float  # radius of the neighbourhoods (the radius, or wider for noisy scans)
    noise: float  # typical perpendicular spread of the points about their curve


def median_spacing(points: FloatArray, sample: int = 20000, seed: int = 0) -> float:
    """Median nearest-neighbour distance of ``points`` (on a random sample of ``sample``)."""
    return _neighbour_distance(points, 1, sample, seed)


def curve_spacing(points: FloatArray, sample: int = 20000, seed: int = 0) -> float:
    """Typical distance between consecutive samples along a curve.

    Half the median distance to the 4th nearest neighbour: exact for evenly spaced samples, and
    unlike the nearest-neighbour distance (the smaller of the two gaps beside a sample, about a
    third of the mean gap for random sampling) it sees the gaps that break a march.
    """
    return 0.5 * _neighbour_distance(points, 4, sample, seed)


def _spacing_bound(points: FloatArray, seed: int, subset: int = 100_000) -> float:
    """A cheap upper estimate of `curve_spacing` for big clouds, from a random subset.

    Thinning points to a fraction f stretches their spacing by 1/f along a curve and by
    1/sqrt(f) over an area, so the subset's spacing times sqrt(f) is at least the full one.
    """
    if len(points) <= 2 * subset:
        return curve_spacing(points, seed=seed)
    pick = np.random.default_rng(seed).choice(len(points), subset, replace=False)
    return curve_spacing(points[pick], seed=seed) * np.sqrt(subset / len(points))


def _neighbour_distance(points: FloatArray, k: int, sample: int, seed: int) -> float:
    tree = cKDTree(points)
    rng = np.random.default_rng(seed)
    probe = points if len(points) <= sample else points[rng.choice(len(points), sample, False)]
    dist, _ = tree.query(probe, k=min(k + 1, len(points)))
    kth = dist[:, -1][np.isfinite(dist[:, -1]) & (dist[:, -1] > 0)]
    return float(np.median(kth)) if len(kth) else 0.0


def order_points(points: FloatArray, radius: float, *, seed: int = 0, min_points: int = 4
                 ) -> Ordering:
    """Order and thin unorganized planar points into contours (paper §2).

    Parameters
    ----------
    points : (N, 2) unorganized points.
    radius : fixed neighbourhood radius, in the points' units (the paper: about the shape
        tolerance). Widened, with a note, when the median point spacing exceeds radius / 3.
    seed : seed of the random choices (which neighbourhoods are kept when thinning).
    min_points : contours with fewer ordered points than this are treated as outliers.

    Returns
    -------
    `Ordering` with the contours, the outlier indices, the radius used and notes.

    Examples
    --------
    >>> t = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    >>> circle = np.column_stack([np.cos(t), np.sin(t)])
    >>> res = order_points(circle, 0.05)
    >>> len(res.contours), res.contours[0].closed, len(res.outliers)
    (1, True, 0)
    """
    pts = validate_points(points, source="points")[:, :2]
    radius = check_tolerance(radius, "radius")
    notes = []
    spacing = _spacing_bound(pts, seed)
    if spacing > radius / 3:
        spacing = curve_spacing(pts, seed=seed)
    if spacing > radius / 3:
        new_radius = 3.0 * spacing
        notes.append(f"radius widened from {radius:.4g} to {new_radius:.4g}: the point spacing "
                     f"along the curves ({spacing:.4g}) is more than a third of it")
        radius = new_radius
    rng = np.random.default_rng(seed)
    nodes, atoms = _neighbourhoods(pts, radius)
    if nodes.reach > radius:
        notes.append(f"noisy scan (scatter {nodes.noise:.3g} about the curves): neighbourhoods "
                     f"widened from {radius:.4g} to {nodes.reach:.4g} to follow the curves")
    keep = _thin(nodes.xy, radius / 2, rng)
    nodes = _Nodes(nodes.xy[keep], nodes.tangent[keep], nodes.ratio[keep], nodes.spread[keep],
                   nodes.reach, nodes.noise)
    links = _link(nodes, radius)
    chains, absorbed = _drop_side_chains(nodes, _chains(links, len(nodes.xy)))
    wide = _wide_nodes(nodes, chains, radius)
    two_walls = _perpendicular_kurtosis(nodes.xy[wide], nodes.tangent[wide], atoms,
                                        nodes.reach) < MERGE_KURTOSIS
    merged = nodes.xy[wide[two_walls]]
    if len(merged):
        notes.append(f"{len(merged)} place(s) where two walls closer than 2 x radius "
                     "may have merged into one contour")
    if (~two_walls).any():
        notes.append(f"{int((~two_walls).sum())} place(s) where the points spread over a band "
                     "wider than the radius (a thick wall, clutter, or a slice cut along a "
                     "surface)")
    contours, outliers = _contours(pts, atoms.tree, nodes, chains, absorbed, radius,
                                   min_points)
    return Ordering(contours, outliers, radius, merged, tuple(notes))


# ---------------------------------------------------------------------------------------------
# 1. neighbourhoods


def _neighbourhoods(pts: FloatArray, radius: float) -> tuple[_Nodes, _Atoms]:
    """Centroid and principal axes of the neighbourhood of each occupied cell of radius / 2,
    and the atoms they were summed over.

    The neighbourhoods have the fixed ``radius``, or on a noisy scan `NOISE_REACH` x the noise
    level (up to 4 x radius), so that they stay longer along the curve than across it.
    """
    atoms = _atoms(pts, radius)
    inverse, counts = _cells(atoms.cell // (ATOM_DIVISIONS // 2), atoms.weight)  # radius / 2
    xy = np.column_stack([np.bincount(inverse, atoms.weight * atoms.xy[:, k])
                          for k in range(2)]) / counts[:, None]
    noise = _noise_level(xy, atoms, radius)
    reach = min(max(radius, NOISE_REACH * noise), 4 * radius)
    if reach > radius:  # coarser atoms keep the wider neighbourhoods' sums cheap
        atoms = _atoms(pts, reach, min_per_cell=1.0)
    for _ in range(3):  # later passes see a neighbourhood centred on the curve
        xy, tangent, ratio, spread = _regression_step(xy, atoms, reach)
    return _Nodes(xy, tangent, ratio, spread, reach, noise), atoms


def _regression_step(xy: FloatArray, atoms: _Atoms, reach: float
                     ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Each centre moved onto the regression line of its neighbourhood (across the curve,
    never along it), with the line's direction, variance ratio and perpendicular spread."""
    centroid, cov = _moments(xy, atoms, reach)
    tangent, ratio, spread = _principal_axes(cov)
    along = np.einsum("nd,nd->n", xy - centroid, tangent)
    return centroid + along[:, None] * tangent, tangent, ratio, spread


def _noise_level(seeds: FloatArray, atoms: _Atoms, radius: float, sample: int = 2000) -> float:
    """Typical scatter of the points about their curve: the median perpendicular spread about
    the regression lines at a sample of the seeds, over 3 x radius (wide enough that a scatter
    of up to radius / 2 is not cut off).

    Only bell-shaped scatter is noise: where the perpendicular offsets have a kurtosis below
    `NOISE_KURTOSIS` (two walls side by side, each sharp, or a flat band) the spread is a shape
    of the data, counted as no noise, so that neighbourhoods stay narrow enough to see it.
    """
    pick = np.random.default_rng(0).choice(len(seeds), min(sample, len(seeds)), replace=False)
    xy = seeds[pick]
    for _ in range(2):
        xy, tangent, _, spread = _regression_step(xy, atoms, 3 * radius)
    kurtosis = _perpendicular_kurtosis(xy, tangent, atoms, 3 * radius)
    return float(np.median(np.where(kurtosis >= NOISE_KURTOSIS, spread, 0.0)))


def _perpendicular_kurtosis(centre: FloatArray, tangent: FloatArray, atoms: _Atoms,
                            reach: float) -> FloatArray:
    """Kurtosis (m4 / m2**2) of the offsets across each line (``centre``, ``tangent``) of the
    points within ``reach`` of its centre: 3 for Gaussian scatter, 1.8 for a flat band, 1 for
    two sharp walls side by side."""
    pairs = cKDTree(centre).sparse_distance_matrix(atoms.tree, reach, output_type="ndarray")
    owner, idx = pairs["i"], pairs["j"]
    normal = np.column_stack([-tangent[:, 1], tangent[:, 0]])
    offset = np.einsum("nd,nd->n", atoms.xy[idx] - centre[owner], normal[owner])
    w = atoms.weight[idx]
    total = np.maximum(np.bincount(owner, w, len(centre)), 1e-300)
    m2 = np.bincount(owner, w * offset**2, len(centre)) / total
    m4 = np.bincount(owner, w * offset**4, len(centre)) / total
    return np.divide(m4, m2**2, out=np.zeros_like(m4), where=m2**2 > 0)


def _cells(cell: IntArray, weight: FloatArray | None = None) -> tuple[IntArray, FloatArray]:
    """Index of each item's cell among the occupied ones, and the weight in each cell."""
    cell = cell - cell.min(axis=0)
    key = cell[:, 0] * (int(cell[:, 1].max()) + 1) + cell[:, 1]
    _, inverse = np.unique(key, return_inverse=True)
    inverse = inverse.ravel()
    return inverse, np.bincount(inverse, weight).astype(float)


@dataclass
class _Atoms:
    """Weighted points for the neighbourhood moments: position, weight, scatter (xx, xy, yy),
    and the cell of radius / `ATOM_DIVISIONS` that each lies in."""

    xy: FloatArray
    weight: FloatArray
    scatter: FloatArray
    cell: IntArray

    @cached_property
    def tree(self) -> cKDTree:
        return cKDTree(self.xy)


#: Cells of radius / ATOM_DIVISIONS summarize dense points (`_atoms`).
ATOM_DIVISIONS = 8


def _atoms(pts: FloatArray, radius: float, min_per_cell: float = 2.0) -> _Atoms:
    """The points themselves, or where they are dense, one atom per cell of radius / 8 (of the
    neighbourhoods' radius).

    An atom is the centroid of its cell's points, weighted by their number and carrying their
    scatter, so a neighbourhood's moments are the same sums over far fewer terms; only the
    membership at the rim of the disc is decided per cell instead of per point.
    """
    cell = np.floor(pts / (radius / ATOM_DIVISIONS)).astype(np.int64)
    inverse, counts = _cells(cell)
    if len(counts) > len(pts) / min_per_cell:  # too few points per cell: little gain
        return _Atoms(pts, np.ones(len(pts)), np.zeros((len(pts), 3)), cell)
    centre = np.column_stack([np.bincount(inverse, pts[:, k]) for k in range(2)]) / counts[:, None]
    d = pts - centre[inverse]
    scatter = np.column_stack([np.bincount(inverse, d[:, 0] * d[:, 0]),
                               np.bincount(inverse, d[:, 0] * d[:, 1]),
                               np.bincount(inverse, d[:, 1] * d[:, 1])])
    first = np.zeros(len(counts), dtype=np.intp)
    first[inverse[::-1]] = np.arange(len(pts))[::-1]  # any point of each cell names its cell
    return _Atoms(centre, counts, scatter, cell[first])


def _moments(centres: FloatArray, atoms: _Atoms, radius: float
             ) -> tuple[FloatArray, FloatArray]:
    """Centroid and covariance (xx, xy, yy) of the points within ``radius`` of each centre."""
    pairs = cKDTree(centres).sparse_distance_matrix(atoms.tree, radius, output_type="ndarray")
    owner, idx = pairs["i"], pairs["j"]
    k = len(centres)
    w = atoms.weight[idx]
    count = np.bincount(owner, w, minlength=k)
    empty = count == 0
    count[empty] = 1.0
    local = atoms.xy[idx] - centres[owner]  # moments about the centre: no cancellation
    mean = np.column_stack([np.bincount(owner, w * local[:, d], k) for d in range(2)])
    mean /= count[:, None]
    scatter = atoms.scatter[idx]
    sxx = np.bincount(owner, w * local[:, 0] ** 2 + scatter[:, 0], k) / count - mean[:, 0] ** 2
    sxy = (np.bincount(owner, w * local[:, 0] * local[:, 1] + scatter[:, 1], k) / count
           - mean[:, 0] * mean[:, 1])
    syy = np.bincount(owner, w * local[:, 1] ** 2 + scatter[:, 2], k) / count - mean[:, 1] ** 2
    centroid = centres + mean
    centroid[empty] = centres[empty]
    return centroid, np.column_stack([sxx, sxy, syy])


def _principal_axes(cov: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Unit principal direction (the regression line), variance ratio and perpendicular RMS."""
    sxx, sxy, syy = cov.T
    half_trace = 0.5 * (sxx + syy)
    disc = np.sqrt(np.maximum(0.25 * (sxx - syy) ** 2 + sxy**2, 0.0))
    big, small = half_trace + disc, np.maximum(half_trace - disc, 0.0)
    angle = 0.5 * np.arctan2(2 * sxy, sxx - syy)
    tangent = np.column_stack([np.cos(angle), np.sin(angle)])
    ratio = np.where(big > 0, small / np.where(big > 0, big, 1.0), 1.0)
    return tangent, ratio, np.sqrt(small)


# ---------------------------------------------------------------------------------------------
# 2. thinning


def _thin(xy: FloatArray, separation: float, rng: np.random.Generator) -> IntArray:
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


# ---------------------------------------------------------------------------------------------
# 3. marching: links along the tangents, chains, corners


def _link(nodes: _Nodes, radius: float) -> IntArray:
    """Mutual links (pairs of node indices) between each node and its neighbours ahead/behind."""
    n = len(nodes.xy)
    k = min(12, n)
    if n < 2:
        return np.empty((0, 2), dtype=np.intp)
    dist, nbr = cKDTree(nodes.xy).query(nodes.xy, k=k, distance_upper_bound=2.0 * radius)
    dist, nbr = dist[:, 1:], nbr[:, 1:]
    valid = np.isfinite(dist)
    nbr_safe = np.where(valid, nbr, 0)
    direction = (nodes.xy[nbr_safe] - nodes.xy[:, None, :]) / np.where(valid, dist, 1.0)[..., None]
    along = np.einsum("nkd,nd->nk", direction, nodes.tangent)
    cos60 = 0.5
    ahead = _first(valid & (along > cos60))
    behind = _first(valid & (along < -cos60))
    pick = np.column_stack([ahead, behind])
    partner = np.where(pick >= 0, nbr_safe[np.arange(n)[:, None], np.maximum(pick, 0)], -1)
    cand = np.column_stack([np.repeat(np.arange(n), 2), partner.ravel()])
    cand = cand[cand[:, 1] >= 0]
    key_fwd = cand[:, 0] * n + cand[:, 1]
    key_rev = cand[:, 1] * n + cand[:, 0]
    mutual = np.isin(key_fwd, key_rev) & (cand[:, 0] < cand[:, 1])
    return _join_ends(nodes, cand[mutual])


def _first(mask: np.ndarray) -> IntArray:
    """Column of the first True in each row of ``mask`` (neighbours are sorted by distance), -1."""
    idx = np.argmax(mask, axis=1)
    return np.where(mask.any(axis=1), idx, -1)


def _join_ends(nodes: _Nodes, links: IntArray) -> IntArray:
    """Join free ends (and lone nodes) that are each other's nearest free node.

    With R the neighbourhood reach (the radius, or wider on noisy scans), ends join within 4 R
    whatever their directions (sharp corners, where both neighbours of the corner node lie ahead
    of its tangent, and the tip of a notch whose walls merged), and across a gap of up to 5 R
    when each end faces the other (a gap in the scan). A chain's two ends join only when the
    chain is long enough to close on itself and one end points at the other. The joining
    repeats, so a lone node can bridge a gap.
    """
    reach = nodes.reach
    n = len(nodes.xy)
    for _ in range(8):
        degree = np.bincount(links.ravel(), minlength=n) if len(links) else np.zeros(n, int)
        free = np.flatnonzero(degree < 2)
        if len(free) < 2:
            break
        comp = _components(links, n)
        size = np.bincount(comp)
        outward = _outward(nodes.xy, links, free, degree)
        k = min(5, len(free))
        dist, nbr = cKDTree(nodes.xy[free]).query(nodes.xy[free], k=k,
                                                  distance_upper_bound=5.0 * reach)
        best = np.full(len(free), -1)
        for col in range(1, k):
            cand = np.minimum(nbr[:, col], len(free) - 1)
            ok = np.isfinite(dist[:, col]) & (best < 0)
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
            long_close = (size[comp[free]] >= 16) & (dist[:, col] <= 3.0 * reach)
            ok &= ~same | ((size[comp[free]] >= 4) & (facing_one | long_close))
            # a march never turns back: a lone node joins a chain's end only ahead of it (lone
            # nodes between two walls of a sharp notch would otherwise hook the end round)
            lone, lone_other = degree[free] == 0, degree[free[cand]] == 0
            ok &= ~(lone & ~lone_other & (ahead_other <= 0))
            ok &= ~(lone_other & ~lone & (ahead <= 0))
            facing = (ahead > 0.7 * dist[:, col]) & (ahead_other > 0.7 * dist[:, col])
            ok &= (dist[:, col] <= 4.0 * reach) | facing
            best[ok] = cand[ok]
        mutual = (best >= 0) & (best[np.maximum(best, 0)] == np.arange(len(free)))
        pairs = np.column_stack([free[mutual], free[best[mutual]]])
        pairs = pairs[pairs[:, 0] < pairs[:, 1]]
        if not len(pairs):
            break
        links = np.vstack([links, pairs])
    return links


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


def _chains(links: IntArray, n: int) -> list[tuple[IntArray, bool]]:
    """Node sequences of each connected chain, and whether it closes on itself."""
    graph = coo_matrix((np.ones(len(links)), (links[:, 0], links[:, 1])), shape=(n, n)).tocsr()
    graph = graph + graph.T
    ncomp, comp = connected_components(graph, directed=False)
    degree = np.diff(graph.indptr)
    order = np.argsort(comp, kind="stable")
    bounds = np.searchsorted(comp[order], np.arange(ncomp + 1))
    out = []
    for c in range(ncomp):
        members = order[bounds[c]:bounds[c + 1]]
        ends = members[degree[members] <= 1]
        closed = len(ends) == 0 and len(members) >= 3
        start = ends[0] if len(ends) else members[0]
        seq = depth_first_order(graph, start, directed=False, return_predecessors=False)
        out.append((seq, closed))
    return out


def _drop_side_chains(nodes: _Nodes, chains: list[tuple[IntArray, bool]], short: int = 12
                      ) -> tuple[list[tuple[IntArray, bool]], IntArray]:
    """Chains of fewer than ``short`` nodes that run alongside a longer chain, within 2.5 x the
    neighbourhood reach of it: noise split off a wall or the tip of a notch, not a contour.

    Returns the other chains, and the nodes of the dropped ones: their points go to the
    contour nearest to them (`_contours`), which then covers them.
    """
    sizes = np.array([len(seq) for seq, _ in chains])
    if len(chains) < 2 or (sizes >= short).all():
        return chains, np.empty(0, dtype=np.intp)
    node_ids = np.concatenate([seq for seq, _ in chains])
    chain_of = np.repeat(np.arange(len(chains)), sizes)
    small = np.flatnonzero(sizes[chain_of] < short)  # positions of the short chains' nodes
    k = min(4 * short, len(node_ids))  # past its own nodes and a wall or two of others
    dist, nbr = cKDTree(nodes.xy[node_ids]).query(nodes.xy[node_ids[small]], k=k,
                                                  distance_upper_bound=2.5 * nodes.reach)
    dist, nbr = dist.reshape(len(small), k), nbr.reshape(len(small), k)
    found = np.isfinite(dist)
    longer = found & (sizes[chain_of[np.where(found, nbr, 0)]]
                      > sizes[chain_of[small]][:, None])
    beside = np.zeros(len(chains), dtype=np.intp)
    np.add.at(beside, chain_of[small], longer.any(axis=1))
    drop = (sizes < short) & (beside == sizes)  # every node of it is beside a longer chain
    absorbed = [seq for (seq, _), d in zip(chains, drop) if d]
    return ([chain for chain, d in zip(chains, drop) if not d],
            np.concatenate(absorbed) if absorbed else np.empty(0, dtype=np.intp))


def _turning(xy: FloatArray, closed: bool, step: int = 2) -> FloatArray:
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


def _wide_nodes(nodes: _Nodes, chains: list[tuple[IntArray, bool]], radius: float
                ) -> IntArray:
    """Nodes on straight stretches whose neighbourhood is as wide as two nearby walls (or a
    band of points as wide: `_perpendicular_kurtosis` tells them apart).

    Two walls a distance d apart, each with the scan's noise, spread sqrt(noise**2 + d**2 / 4)
    about one regression line; the excess over the noise marks them when d / 2 is over
    `MERGE_SPREAD` x radius and over the noise (closer walls are lost in the noise).
    """
    out = []
    excess = np.sqrt(np.maximum(nodes.spread**2 - nodes.noise**2, 0.0))
    for seq, closed in chains:
        if len(seq) < 5:
            continue
        # a neighbourhood that reaches a corner spreads over both of its legs
        bend = _turning(nodes.xy[seq], closed) >= CORNER_TURN
        width = 2 * int(np.ceil(2 * nodes.reach / radius)) + 1
        near_bend = maximum_filter1d(bend, width, mode="wrap" if closed else "nearest")
        wide = ~near_bend & (excess[seq] > max(MERGE_SPREAD * radius, nodes.noise))
        # walls run side by side for a while; a lone wide node is the noise of the estimate
        before, after = np.roll(wide, 1), np.roll(wide, -1)
        if not closed:
            before[0] = after[-1] = False
        out.append(seq[wide & (before | after)])
    return np.concatenate(out) if out else np.empty(0, dtype=np.intp)


def _sharpen_corners(xy: FloatArray, closed: bool, pts_tree: cKDTree, radius: float
                     ) -> FloatArray:
    """Replace each run of turning points by the intersection of the straight legs beside it."""
    n = len(xy)
    if n < 6:
        return xy
    corner = _turning(xy, closed) >= CORNER_TURN
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
    return new_xy[keep]


def _intersect(a0, a1, b0, b1) -> FloatArray | None:
    """Intersection of line a0a1 with line b0b1 if they cross at more than 25 degrees."""
    da, db = a1 - a0, b1 - b0
    cross = da[0] * db[1] - da[1] * db[0]
    if abs(cross) < np.sin(np.radians(25)) * np.linalg.norm(da) * np.linalg.norm(db):
        return None
    t = ((b0 - a0)[0] * db[1] - (b0 - a0)[1] * db[0]) / cross
    return a0 + t * da


# ---------------------------------------------------------------------------------------------
# 4. contours and their members


def _contours(pts: FloatArray, tree: cKDTree, nodes: _Nodes,
              chains: list[tuple[IntArray, bool]], absorbed: IntArray, radius: float,
              min_points: int) -> tuple[list[OrderedContour], IntArray]:
    """Contours from chains of at least ``min_points`` nodes, each with its member points.

    A point belongs to the contour of its nearest node among those contours (within 2 x radius;
    farther points, and the points of shorter chains that no contour is near, are outliers).
    The ``absorbed`` nodes of dropped side chains count as nodes of the contour nearest them.
    """
    chains = [(seq, closed) for seq, closed in chains if len(seq) >= min_points]
    if not chains:
        return [], np.arange(len(pts), dtype=np.intp)
    node_ids = np.concatenate([seq for seq, _ in chains])
    owner = np.repeat(np.arange(len(chains)), [len(seq) for seq, _ in chains])
    if len(absorbed):
        _, host = cKDTree(nodes.xy[node_ids]).query(nodes.xy[absorbed])
        node_ids, owner = np.concatenate([node_ids, absorbed]), np.concatenate([owner,
                                                                                 owner[host]])
    dist, nearest = cKDTree(nodes.xy[node_ids]).query(pts, distance_upper_bound=2.0 * radius)
    chain_of_point = np.where(np.isfinite(dist), owner[np.minimum(nearest, len(owner) - 1)], -1)
    order = np.argsort(chain_of_point, kind="stable")
    bounds = np.searchsorted(chain_of_point[order], np.arange(len(chains) + 1))
    contours: list[OrderedContour] = []
    outliers = [np.flatnonzero(chain_of_point < 0)]
    first_node = np.concatenate([[0], np.cumsum([len(seq) for seq, _ in chains])])
    for c, (seq, closed) in enumerate(chains):
        members = order[bounds[c]:bounds[c + 1]]
        xy = _sharpen_corners(nodes.xy[seq], closed, tree, radius)
        if not closed:
            xy = _extend_ends(xy, pts[members], radius)
        # a member within 0.6 x radius of a node that is still a vertex needs no measuring
        at = nearest[members] - first_node[c]
        own = (at >= 0) & (at < len(seq))  # not an absorbed node
        kept = np.zeros(len(members), dtype=bool)
        kept[own] = _still_vertices(nodes.xy[seq], xy)[at[own]]
        unsure = np.flatnonzero(~(kept & (dist[members] <= _CORNER_GAP * radius)))
        xy, far = _cover_cut_corners(xy, pts[members[unsure]], closed, radius)
        inside = np.ones(len(members), dtype=bool)
        inside[unsure[far]] = False
        outliers.append(members[~inside])
        contours.append(OrderedContour(xy, closed, members[inside]))  # sorted: stable argsort
    return contours, np.sort(np.concatenate(outliers)).astype(np.intp)


def _still_vertices(chain: FloatArray, xy: FloatArray) -> np.ndarray:
    """Which points of ``chain`` are (exactly) vertices of ``xy``."""
    return np.isin(chain[:, 0] + 1j * chain[:, 1], xy[:, 0] + 1j * xy[:, 1])


#: Members farther than this (in radii) from the chain mark a corner it cut.
_CORNER_GAP = 0.6


def _cover_cut_corners(xy: FloatArray, members: FloatArray, closed: bool, radius: float,
                       rounds: int = 4) -> tuple[FloatArray, IntArray]:
    """Insert member points where a group of them lies off the chain (a corner it cut).

    Where at least 3 points tied to one chain segment are farther than 0.6 x radius from the
    chain, the farthest of them is inserted into that segment; a few rounds of this put a point
    on a corner that neighbourhood averaging rounded off. Lone noisy points never qualify.
    Returns the new chain and the members still farther than ``radius`` from it.
    """
    for round_ in range(rounds + 1):
        far, seg, dist = farther_than(members, xy, closed and len(xy) >= 3,
                                      _CORNER_GAP * radius)
        segs = np.empty(0, dtype=np.intp)
        if len(far) >= 3 and round_ < rounds:
            counts = np.bincount(seg, minlength=len(xy))
            worst = np.full(len(xy), -1)
            order = np.argsort(dist)
            worst[seg[order]] = far[order]  # the last write per segment is its farthest point
            segs = np.flatnonzero((counts >= 3) & (worst >= 0))
        if not len(segs):
            return xy, far[dist > radius]
        xy = np.insert(xy, segs + 1, members[worst[segs]], axis=0)
    raise AssertionError("unreachable")  # pragma: no cover


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


def ordering_summary(ordering: Ordering, n_points: int) -> str:
    """One line: contours (closed/open), ordered points, outliers, radius."""
    if n_points <= 0:
        raise DataError("no points")
    n_closed = sum(c.closed for c in ordering.contours)
    ordered = sum(len(c.points) for c in ordering.contours)
    return (f"{n_points} points -> {len(ordering.contours)} contours ({n_closed} closed, "
            f"{len(ordering.contours) - n_closed} open), {ordered} ordered points, "
            f"{len(ordering.outliers)} outliers, radius {ordering.radius:.4g}")
