"""Neighbourhood summaries for the ordering (paper §2): weighted cell atoms, the moments of the
points within a radius of a centre, and the regression line (principal axis) through them.

Dense clouds enter the sums as one weighted atom per cell of radius / `ATOM_DIVISIONS`
(`cell_atoms`), so that a neighbourhood's moments are the same sums over far fewer terms.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from ..kernels import neighbourhood_sums
from ..types import FloatArray, IntArray
from ..validate import column_bounds

#: Cells of radius / ATOM_DIVISIONS summarize dense points (`cell_atoms`): fine enough that a
#: disc's rim is decided per cell with an error of 1/8 radius at most.
ATOM_DIVISIONS = 8
#: An atom per cell pays off only with at least this many points per cell on average.
MIN_PER_CELL = 2.0
#: A parabola's normal equations (along-line coordinates in reaches, so within [-1, 1]) are
#: singular below this determinant per cubed weight: all points at one or two stations.
SINGULAR = 1e-9


@dataclass(frozen=True)
class Nodes:
    """Neighbourhood summaries: position (centroid), unit tangent, shape of the scatter."""

    xy: FloatArray
    tangent: FloatArray
    ratio: FloatArray  # smaller / larger principal variance
    spread: FloatArray  # perpendicular RMS distance of the neighbourhood's points
    reach: float  # radius of the neighbourhoods (the radius, or wider for noisy scans)
    noise: float  # typical perpendicular spread of the points about their curve


#: Cell keys are ranked by a table when their range is at most this many times the number of
#: items (linear time, memory like the items'), else by a sort.
DENSE_KEYS = 4


def cells(cell: IntArray, weight: FloatArray | None = None) -> tuple[IntArray, FloatArray]:
    """Index of each item's cell among the occupied ones, and the weight in each cell."""
    cell = cell - column_bounds(cell)[0]
    key = cell[:, 0] * (int(cell[:, 1].max()) + 1) + cell[:, 1]
    span = int(key.max(initial=0)) + 1
    if span <= DENSE_KEYS * max(len(key), 1):  # a table over the keys instead of a sort
        occupied = np.zeros(span, dtype=bool)
        occupied[key] = True
        inverse = (np.cumsum(occupied) - 1)[key]
    else:
        _, inverse = np.unique(key, return_inverse=True)
        inverse = inverse.ravel()
    return inverse, np.bincount(inverse, weight).astype(float)


@dataclass
class Atoms:
    """Weighted points for the neighbourhood moments: position, weight, scatter (xx, xy, yy),
    and the cell of radius / `ATOM_DIVISIONS` that each lies in."""

    xy: FloatArray
    weight: FloatArray
    scatter: FloatArray
    cell: IntArray

    @cached_property
    def tree(self) -> cKDTree:
        return cKDTree(self.xy)


def cell_atoms(pts: FloatArray, radius: float, min_per_cell: float = MIN_PER_CELL) -> Atoms:
    """The points themselves, or where they are dense, one atom per cell of radius / 8 (of the
    neighbourhoods' radius).

    An atom is the centroid of its cell's points, weighted by their number and carrying their
    scatter, so a neighbourhood's moments are the same sums over far fewer terms; only the
    membership at the rim of the disc is decided per cell instead of per point.
    """
    cell = np.floor(pts / (radius / ATOM_DIVISIONS)).astype(np.int64)
    inverse, counts = cells(cell)
    if len(counts) > len(pts) / min_per_cell:  # too few points per cell: little gain
        return Atoms(pts, np.ones(len(pts)), np.zeros((len(pts), 3)), cell)
    return _merged(Atoms(pts, np.ones(len(pts)), np.zeros((len(pts), 3)), cell), cell,
                   inverse, counts)


def coarser_atoms(atoms: Atoms, factor: int) -> Atoms:
    """The atoms merged into cells ``factor`` x as wide (`cell_atoms` at ``factor`` x its
    radius, summed from the atoms instead of the points): the same moments over a wide
    window from far fewer terms."""
    if factor <= 1:
        return atoms
    cell = atoms.cell // factor
    inverse, weight = cells(cell, atoms.weight)
    return _merged(atoms, cell, inverse, weight)


def _merged(atoms: Atoms, cell: IntArray, inverse: IntArray, weight: FloatArray) -> Atoms:
    """The ``atoms`` merged by their ``cell`` (``inverse``: each one's index among the
    occupied cells, ``weight``: each cell's total): weighted centroid, scatter about it."""
    w = atoms.weight
    centre = np.column_stack([np.bincount(inverse, w * atoms.xy[:, k]) for k in range(2)])
    centre /= weight[:, None]
    d = atoms.xy - centre[inverse]
    scatter = np.column_stack([np.bincount(inverse, atoms.scatter[:, k] + w * d[:, i] * d[:, j])
                               for k, (i, j) in enumerate([(0, 0), (0, 1), (1, 1)])])
    first = np.zeros(len(weight), dtype=np.intp)
    first[inverse[::-1]] = np.arange(len(w))[::-1]  # any member of each cell names its cell
    return Atoms(centre, weight, scatter, cell[first])


def moments(centres: FloatArray, atoms: Atoms, radius: float
             ) -> tuple[FloatArray, FloatArray]:
    """Centroid and covariance (xx, xy, yy) of the points within ``radius`` of each centre
    (the sums run compiled: `wavepoly.kernels.neighbourhood_sums`)."""
    pairs = cKDTree(centres).sparse_distance_matrix(atoms.tree, radius, output_type="ndarray")
    sums = neighbourhood_sums(pairs["i"], pairs["j"], centres, atoms.xy, atoms.weight,
                              atoms.scatter, len(centres))
    return _moments_from_sums(centres, sums)


def _moments_from_sums(centres: FloatArray, sums: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Centroid and covariance from the (k, 6) sums about each centre (`moments`); an empty
    neighbourhood keeps its centre."""
    count = sums[:, 0].copy()
    empty = count == 0
    count[empty] = 1.0
    mean = sums[:, 1:3] / count[:, None]
    sxx = sums[:, 3] / count - mean[:, 0] ** 2
    sxy = sums[:, 4] / count - mean[:, 0] * mean[:, 1]
    syy = sums[:, 5] / count - mean[:, 1] ** 2
    centroid = centres + mean
    centroid[empty] = centres[empty]
    return centroid, np.column_stack([sxx, sxy, syy])


def _moments_reference(centres: FloatArray, atoms: Atoms, radius: float
                       ) -> tuple[FloatArray, FloatArray]:
    """`moments` with NumPy sums, the reference of the compiled kernel for the tests."""
    pairs = cKDTree(centres).sparse_distance_matrix(atoms.tree, radius, output_type="ndarray")
    owner, idx = pairs["i"], pairs["j"]
    k = len(centres)
    w = atoms.weight[idx]
    local = atoms.xy[idx] - centres[owner]  # moments about the centre: no cancellation
    scatter = atoms.scatter[idx]
    sums = np.column_stack([
        np.bincount(owner, w, k), np.bincount(owner, w * local[:, 0], k),
        np.bincount(owner, w * local[:, 1], k),
        np.bincount(owner, w * local[:, 0] ** 2 + scatter[:, 0], k),
        np.bincount(owner, w * local[:, 0] * local[:, 1] + scatter[:, 1], k),
        np.bincount(owner, w * local[:, 1] ** 2 + scatter[:, 2], k)])
    return _moments_from_sums(centres, sums)


def principal_axes(cov: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Unit principal direction (the regression line), variance ratio and perpendicular RMS."""
    sxx, sxy, syy = cov.T
    half_trace = 0.5 * (sxx + syy)
    disc = np.sqrt(np.maximum(0.25 * (sxx - syy) ** 2 + sxy**2, 0.0))
    big, small = half_trace + disc, np.maximum(half_trace - disc, 0.0)
    angle = 0.5 * np.arctan2(2 * sxy, sxx - syy)
    tangent = np.column_stack([np.cos(angle), np.sin(angle)])
    ratio = np.where(big > 0, small / np.where(big > 0, big, 1.0), 1.0)
    return tangent, ratio, np.sqrt(small)


def regression_step(xy: FloatArray, atoms: Atoms, reach: float
                     ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Each centre moved onto the regression line of its neighbourhood (across the curve,
    never along it), with the line's direction, variance ratio and perpendicular spread."""
    centroid, cov = moments(xy, atoms, reach)
    tangent, ratio, spread = principal_axes(cov)
    along = np.einsum("nd,nd->n", xy - centroid, tangent)
    return centroid + along[:, None] * tangent, tangent, ratio, spread


def nodes_with_points(nodes: Nodes, atoms: Atoms, min_points: float, typical: float) -> Nodes:
    """The nodes whose neighbourhoods (of ``nodes.reach``) hold at least ``min_points``
    points, where the median neighbourhood holds at least ``typical`` (else all of them)."""
    pairs = cKDTree(nodes.xy).sparse_distance_matrix(atoms.tree, nodes.reach,
                                                      output_type="ndarray")
    weight = np.bincount(pairs["i"], atoms.weight[pairs["j"]], len(nodes.xy))
    if not len(weight) or np.median(weight) < typical:
        return nodes
    keep = weight >= min_points
    return Nodes(nodes.xy[keep], nodes.tangent[keep], nodes.ratio[keep], nodes.spread[keep],
                 nodes.reach, nodes.noise)


@dataclass(frozen=True)
class Offsets:
    """The points within a reach of each line (centre, tangent): for each pair, the line it
    belongs to (``owner``), the atom (``atom``), the atom's weight and its offset across."""

    owner: IntArray
    atom: IntArray
    weight: FloatArray
    offset: FloatArray
    lines: int


def perpendicular_offsets(centre: FloatArray, tangent: FloatArray, atoms: Atoms, reach: float
                          ) -> Offsets:
    """Offsets across each line (``centre``, ``tangent``) of the atoms within ``reach``."""
    pairs = cKDTree(centre).sparse_distance_matrix(atoms.tree, reach, output_type="ndarray")
    owner, idx = pairs["i"], pairs["j"]
    normal = np.column_stack([-tangent[:, 1], tangent[:, 0]])
    offset = np.einsum("nd,nd->n", atoms.xy[idx] - centre[owner], normal[owner])
    return Offsets(owner, idx, atoms.weight[idx], offset, len(centre))


def perpendicular_kurtosis(centre: FloatArray, tangent: FloatArray, atoms: Atoms,
                            reach: float, offsets: Offsets | None = None) -> FloatArray:
    """Kurtosis (m4 / m2**2) of the offsets across each line (``centre``, ``tangent``) of the
    points within ``reach`` of its centre: 3 for Gaussian scatter, 1.8 for a flat band, 1 for
    two sharp walls side by side. ``offsets``: those offsets, when already measured."""
    o = perpendicular_offsets(centre, tangent, atoms, reach) if offsets is None else offsets
    owner, offset, w, k = o.owner, o.offset, o.weight, o.lines
    total = np.maximum(np.bincount(owner, w, k), 1e-300)
    m2 = np.bincount(owner, w * offset**2, k) / total
    m4 = np.bincount(owner, w * offset**4, k) / total
    return np.divide(m4, m2**2, out=np.zeros_like(m4), where=m2**2 > 0)


def inner_scatter(o: Offsets, tangent: FloatArray, atoms: Atoms) -> FloatArray:
    """Each atom's own scatter (summed over its points) across its line."""
    sc = atoms.scatter[o.atom]
    n = np.column_stack([-tangent[o.owner, 1], tangent[o.owner, 0]])
    return n[:, 0] ** 2 * sc[:, 0] + 2 * n[:, 0] * n[:, 1] * sc[:, 1] + n[:, 1] ** 2 * sc[:, 2]


def bend_free_spread(centre: FloatArray, tangent: FloatArray, atoms: Atoms, reach: float,
                     offsets: Offsets) -> FloatArray:
    """RMS offset of the points within ``reach`` of each line (``centre``, ``tangent``) about
    the parabola through them, ``offset ~ a + b t + c t**2`` along the line (weighted least
    squares, one 3 x 3 system per line): the scatter across the curve without the curve's own
    bend, which a line's spread (`principal_axes`) counts as scatter. Where the system is
    singular (points on fewer than 3 stations along the line) the spread is about the mean."""
    o, k = offsets, offsets.lines
    t = np.einsum("nd,nd->n", atoms.xy[o.atom] - centre[o.owner], tangent[o.owner]) / reach
    w, y = o.weight, o.offset
    tp = [np.bincount(o.owner, w * t**p, k) for p in range(5)]
    normal = np.stack([np.stack([tp[i + j] for j in range(3)], -1) for i in range(3)], -2)
    rhs = np.stack([np.bincount(o.owner, w * y * t**p, k) for p in range(3)], -1)
    solvable = np.abs(np.linalg.det(normal)) > SINGULAR * np.maximum(tp[0], 1.0) ** 3
    coef = np.zeros((k, 3))
    coef[solvable] = np.linalg.solve(normal[solvable], rhs[solvable][..., None])[..., 0]
    coef[~solvable, 0] = rhs[~solvable, 0] / np.maximum(tp[0][~solvable], 1e-300)
    residual = y - (coef[o.owner, 0] + coef[o.owner, 1] * t + coef[o.owner, 2] * t**2)
    total = np.maximum(np.bincount(o.owner, w, k), 1e-300)
    inner = np.bincount(o.owner, inner_scatter(o, tangent, atoms), k)
    # an atom of points on one line has an inner scatter across it of zero, give or take
    # rounding
    return np.sqrt(np.maximum(np.bincount(o.owner, w * residual**2, k) + inner, 0.0) / total)


def point_clusters(xy: FloatArray, reach: float) -> IntArray:
    """Label of each point's cluster: points within ``reach`` of one another, chained."""
    n = len(xy)
    pairs = cKDTree(xy).query_pairs(reach, output_type="ndarray")
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    return connected_components(graph, directed=False)[1]


def group_extents(xy: FloatArray, label: IntArray) -> FloatArray:
    """The diagonal of each labelled group's bounding box (labels 0..k-1)."""
    lo = np.full((label.max(initial=-1) + 1, 2), np.inf)
    hi = -lo
    np.minimum.at(lo, label, xy)
    np.maximum.at(hi, label, xy)
    return np.linalg.norm(hi - lo, axis=1)
