"""Where the scanned surface crosses a layer's mid-plane, from the points of its slab.

A layer-based model stands for the object's cross-section at each layer's mid-plane (§1, §5);
the slab's points spread over a band where the slab cuts a sloped surface, and a contour that
keeps every one of them within ε zigzags through that band. Instead, each point is moved
*along the surface* to the mid-plane: its 3D neighbourhood gives the local tangent plane (the
principal axes of the neighbourhood, whose smallest is the normal), and the point slides
within that plane, along the steepest direction, until it reaches the mid-plane. The point is
first projected onto the local quadric of its neighbourhood (a moving least-squares surface),
which divides the scan's noise by about the root of the neighbourhood's size before the slide
carries it into the plane. On a vertical wall it does not move sideways; on a slope of angle
φ to the axis it moves by ``|Δh| · cot φ``. Where the tangent plane lies within
`MIN_STEEPNESS` of the plane, its tilt is about the noise's, and the section would be placed no
better than the noise times cot φ: there the surface is fitted again as a height field over
`WIDE_FACTOR` times the neighbours, and gives points only where its slope stands
`MIN_SLOPE_SCORE` standard errors out of the noise (a dome's shallow crossing, not a face
lying in the plane), and only a short way, along the height field's bend rather than its
tangent (a shallow surface curves within its slide: the tangent of a ridge's flank reaches
a plane that the ridge's crest stays below, and joined an ear to the bunny's head). A point is only
moved where its own neighbourhood straddles the mid-plane (the surface it stands for is known
there), so a cap or a ledge inside the slab that does not cross the mid-plane gives no section
points, and nothing is extrapolated past an end of the object. Beside an edge (a box's
vertical corner, a step's rim) a point's neighbourhood lies on two faces and its plane is
neither: such a point takes the plane of a flatter neighbourhood nearby that it lies on, so
that the section runs into the corner instead of cutting it (Fleishman et al.); a shallow
point whose wider height field spans an edge, or comes out steep, gives no section point (it
would slide along the edge's tilt). Where the object's wall is thinner than a neighbourhood
(a tube, a hollow shell), the neighbourhood holds both faces and its plane lies mid-wall: each
point is then fitted to its own face alone (`wavepoly.sheets`), so that the section has the
wall's two sides and not one line down its middle, which would fill the tube. Thus a band
becomes a line of points with the scan's noise, which the fit turns into the section within
ε.

This was chosen over weighting the points nearest to the mid-plane because it uses every
point whose surface crosses the plane, corrects the first-order offset of sloped
surfaces exactly, and needs no choice of a band width beyond the neighbourhood's own.

References
----------
.. [1] H. Hoppe, T. DeRose, T. Duchamp, J. McDonald and W. Stuetzle, "Surface reconstruction
   from unorganized points", SIGGRAPH 1992 (tangent planes from neighbourhood PCA).
.. [2] M. Alexa, J. Behr, D. Cohen-Or, S. Fleishman, D. Levin and C. T. Silva, "Computing
   and rendering point set surfaces", IEEE TVCG 9(1), 2003, pp. 3-15 (projection onto the
   local least-squares plane).
.. [3] Y. F. Wu, Y. S. Wong, H. T. Loh and Y. F. Zhang, "Modelling cloud data using an
   adaptive slicing approach", Computer-Aided Design 36(3), 2004, pp. 231-240.
.. [4] S. Fleishman, D. Cohen-Or and C. T. Silva, "Robust moving least-squares fitting with
   sharp features", ACM Trans. Graphics 24(3), 2005, pp. 544-552.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy.spatial import cKDTree

from .sheets import own_principal, own_sheet, principal
from .types import FloatArray, IntArray, SurfaceSamples

#: Neighbours of each point for its tangent plane: enough for a stable normal under noise
#: (16 tilted flat faces' normals by 20 degrees at 0.1 % noise), few enough that the
#: neighbourhood stays on one face near an edge (40 mixed the faces of a block's corners).
SURFACE_NEIGHBOURS = 24
#: Points whose normals are estimated together (bounds the memory of the neighbour arrays).
CHUNK = 200_000
#: Surfaces flatter than this to the plane (the sine of the normal's angle to the axis) give
#: no section points: a height error e moves their section by e / tan(angle), so a face at
#: 30 degrees to the plane places it only to 1.7 x the noise, and a face lying in the plane (a
#: cap at the mid-plane) would scatter its points over the face; the normals of a flat face
#: scanned with noise tilt by up to 20 degrees.
MIN_STEEPNESS = np.sin(np.radians(30.0))
#: A neighbourhood's flatness under noise alone is about (2 sigma / radius)^2: in a scan sampled
#: densely beside its noise, the k nearest points span too little to show the surface. It is
#: then thinned to every 2nd, 4th... point until the median flatness is at most this (each
#: halving widens the neighbourhood by the root of 2); a clean scan keeps every point.
NOISE_FLATNESS = 0.2
#: Points whose flatness decides the thinning: the median of a few thousand is stable.
FLATNESS_SAMPLE = 2000
#: A cloud is never thinned below this many points (a small band keeps its points).
MIN_NODES = 2000
#: Ridge of the local quadric fits, relative to the trace of their normal equations: keeps a
#: degenerate neighbourhood (collinear points) solvable without moving a regular one.
QUADRIC_RIDGE = 1e-9
#: A shallow surface is fitted again over this many times the neighbours: its slope is small
#: beside the noise, and the wider fit's slope error is several times smaller.
WIDE_FACTOR = 4
#: Shallow points fitted together (bounds the memory of the wide neighbourhoods' arrays).
WIDE_CHUNK = 20_000
#: A shallow surface gives section points only where its slope is this many standard errors
#: from 0: the noise tilts a flat face's fitted slope by about one, and a cap that lies in
#: the plane must give no section (a slope of 5 errors arises from noise once in 10^5 points).
MIN_SLOPE_SCORE = 5.0
#: Largest slide of a shallow point, in its (wider) neighbourhood's radii.
MAX_SHALLOW_SLIDE = 1.0
#: A shallow point's height field whose residual variance exceeds this many times the median
#: of all shallow points' spans an edge (a cap and a wall), and gives no section point.
EDGE_RESIDUAL = 4.0
#: Section points whose line is fitted to decide whether one is a stray.
STRAY_NEIGHBOURS = 64
#: A section point this many times farther off its neighbours' line than their median is a
#: stray (a slide that went wrong), not the section.
STRAY_FACTOR = 4.0
#: Section end points closer than this (relative to the coordinates) are the same point.
SNAP = 1e-9
#: Neighbourhoods whose smallest principal variance exceeds this fraction of the middle one
#: are not planar (they straddle an edge of the object, where the normal is an average of the
#: faces'): their points would slide the wrong way, so they give no section points. Noise alone
#: gives about (2 sigma / radius)^2, 0.1 at 0.1 % noise.
MAX_FLATNESS = 0.25
#: A steep point whose neighbourhood's flatness is over this many times what its noise alone
#: gives may take a flatter neighbour's plane (`_shifted`). Beside an edge the ratio is large
#: (the stepped block of the tests, noise ε / 5: within a quarter of a radius of an edge 4.7 in
#: the median, within half a radius 2.5); on a noisy face it is about 1.2 (95 % below 1.9).
#: Taking the flatter plane there too does no harm, as the point must lie on it within the
#: noise, and the block's sections, fitted, have 5.3 vertices on average (a square has 4) at
#: 1, 5.9 at 1.5, 7.8 at 2 and 20 with no point taking another's plane; the bunny's uniform
#: layers' 95th-percentile Hausdorff distance is 1.06 ε at 1, 1.25 at 1.5 (a quarter of the
#: bunny's points and 28 % of the turbine blade's take a neighbour's plane at 1).
EDGE_FLATNESS = 1.0
#: A point takes a neighbour's plane only where that neighbourhood's flatness is below this
#: share of its own (the block's sections are the same from 0.3 to 0.7).
SHIFT_FLATNESS = 0.5
#: ... and where it lies on that plane, within this many of the noise (the residuals of the
#: neighbour's quadric): a point on the other face of an edge lies off it by its distance
#: from the edge (the block's sections are the same from 2 to 4).
ON_PLANE = 3.0
#: Largest slide along the surface, in neighbourhood radii: the tangent plane is a fair model
#: of the surface over about its neighbourhood, not much farther.
MAX_SLIDE = 2.0


def surface_samples(uvh: FloatArray, k: int = SURFACE_NEIGHBOURS,
                    rows: slice | None = None) -> SurfaceSamples:
    """Tangent planes and neighbourhood extents of a cloud in plane coordinates (u, v, height).

    Each tangent plane is fitted to the ``k`` nearest neighbours of a point (Hoppe et al.).
    A steep point less planar than its noise explains (most of all near an edge of the
    object, where its neighbourhood straddles two faces) takes the tangent plane of the
    flattest neighbourhood among its neighbours' that it lies on (`_shifted`): one on its own
    face. A shallow one is fitted again as a height field over more neighbours. A scan
    sampled more densely than its noise allows (its median neighbourhood is not planar, see
    `NOISE_FLATNESS`) is thinned first to every 2nd, 4th... point (in the given order), and
    only the points kept are described: the density its noise supports.

    Parameters
    ----------
    uvh : (N, 3) points; the third column is the height along the slicing axis.
    k : neighbours per point for its tangent plane.
    rows : the points to describe (default: all); their neighbours are sought among all of
        ``uvh``.

    References
    ----------
    .. [1] S. Fleishman, D. Cohen-Or and C. T. Silva, "Robust moving least-squares fitting
       with sharp features", ACM Trans. Graphics 24(3), 2005, pp. 544-552 (a point near an
       edge takes the fit of a neighbourhood that lies on one side of it).
    """
    k = max(3, min(k, len(uvh)))
    step, tree = node_step(uvh, k)
    nodes = uvh[::step]
    own = np.arange(len(uvh))[rows if rows is not None else slice(None)]
    own = own[own % step == 0] // step
    k = min(k, len(nodes))
    near = _neighbours(nodes, tree, own, k)
    # the points and their neighbours are fitted, each from its own neighbours (known for
    # the points, sought for the rest)
    fitted, where = np.unique(np.append(near.ravel(), own), return_inverse=True)
    mine = where[near.size:]
    fitted_near = np.empty((len(fitted), k), dtype=np.intp)
    fitted_near[mine] = near
    rest = np.setdiff1d(np.arange(len(fitted)), mine)
    fitted_near[rest] = _neighbours(nodes, tree, fitted[rest], k)
    fits = _fits(nodes, fitted, fitted_near)
    planes, support = _shifted(nodes[own], fits, mine, where[:near.size].reshape(near.shape),
                               nodes[fitted, 2])
    score, bend = _refine_shallow(nodes, tree, own, planes, min(WIDE_FACTOR * k, len(nodes)))
    support = np.maximum(support, planes[3])
    return SurfaceSamples(nodes[own], *planes, score, bend, support)


def node_step(uvh: FloatArray, k: int = SURFACE_NEIGHBOURS) -> tuple[int, cKDTree]:
    """Every how many points a tangent plane is fitted, and the KD-tree of those points: 1,
    or a power of 2 whose nodes' median flatness is at most `NOISE_FLATNESS` (judged on a
    sample of them). Noise flatness falls as the inverse of the step (the neighbourhood's
    area grows with it), so the first guess is the step that this predicts."""
    step, tree = 1, cKDTree(uvh)
    flatness = _median_flatness(uvh, tree, k)
    if flatness > NOISE_FLATNESS:
        guess = 2 ** int(np.ceil(np.log2(flatness / NOISE_FLATNESS)))
        step = max(1, min(guess, len(uvh) // MIN_NODES))
        while step > 1:
            tree = cKDTree(uvh[::step])
            if (_median_flatness(uvh[::step], tree, k) <= NOISE_FLATNESS
                    or len(uvh) // (2 * step) < MIN_NODES):
                break
            step *= 2
    return step, tree


def _median_flatness(nodes: FloatArray, tree: cKDTree, k: int) -> float:
    sample = np.arange(0, len(nodes), max(1, len(nodes) // FLATNESS_SAMPLE))
    near = _neighbours(nodes, tree, sample, min(k, len(nodes)))
    _, _, values, _, _ = own_principal(nodes[near])  # the flatness alone: no quadric
    return float(np.median(values[:, 0] / np.maximum(values[:, 1], 1e-300)))


class _Fits(NamedTuple):
    """The local fits of some points' neighbourhoods: tangent plane (unit normal), height
    range, radius, flatness and each point's offset from its quadric (as in
    `SurfaceSamples`), the neighbourhood's centroid, and the root-mean-square of its quadric's
    residuals (the noise, where the surface is smooth)."""

    normals: FloatArray
    low: FloatArray
    high: FloatArray
    radius: FloatArray
    flatness: FloatArray
    offset: FloatArray
    centroid: FloatArray
    rms: FloatArray


def _neighbours(nodes: FloatArray, tree: cKDTree, which: IntArray, k: int) -> IntArray:
    """The ``k`` nearest nodes of ``nodes[which]``, nearest first."""
    near = np.empty((len(which), k), dtype=np.intp)
    for start in range(0, len(which), CHUNK):
        stop = min(len(which), start + CHUNK)
        near[start:stop] = tree.query(nodes[which[start:stop]], k=k)[1].reshape(-1, k)
    return near


def _fits(nodes: FloatArray, which: IntArray, near: IntArray) -> _Fits:
    """The local fits (`_Fits`) of ``nodes[which]`` from their nearest nodes ``near`` (n, k),
    nearest first."""
    n = len(which)
    normals, centroid = np.empty((n, 3)), np.empty((n, 3))
    low, high, radius, flatness, offset, rms = (np.empty(n) for _ in range(6))
    for start in range(0, n, CHUNK):
        stop = min(n, start + CHUNK)
        nbr = nodes[near[start:stop]]
        centroid[start:stop], centred, values, axes, weight = own_principal(nbr)
        normals[start:stop] = axes[:, :, 0]  # the smallest principal axis
        flatness[start:stop] = values[:, 0] / np.maximum(values[:, 1], 1e-300)
        heights = nbr[:, :, 2]
        low[start:stop] = np.where(weight > 0, heights, np.inf).min(axis=1)
        high[start:stop] = np.where(weight > 0, heights, -np.inf).max(axis=1)
        radius[start:stop] = np.linalg.norm(nbr[:, -1] - nodes[which[start:stop]], axis=1)
        coef, rms[start:stop] = _local_quadric(centred, axes, weight)
        offset[start:stop] = _above_quadric(nodes[which[start:stop]] - centroid[start:stop],
                                            axes, coef)
    return _Fits(normals, low, high, radius, flatness, offset, centroid, rms)


def _shifted(points: FloatArray, fits: _Fits, mine: IntArray, near: IntArray,
             heights: FloatArray) -> tuple[tuple[FloatArray, ...], FloatArray]:
    """The tangent planes of ``points`` (normal, height range, radius, flatness, offset):
    each point's own, or the plane of the flattest neighbourhood among its neighbours' that
    it lies on (Fleishman et al.), which beside an edge is one on the point's own face.

    ``fits`` are the fits of the points and their neighbours; ``mine`` (n,) each point's row in
    them, ``near`` (n, k) its neighbours' rows; ``heights`` the fitted points' heights. A
    steep point (a shallow one is fitted again over a wider neighbourhood,
    `_refine_shallow`) whose neighbourhood is less planar than its noise explains
    (`EDGE_FLATNESS`: one that straddles an edge is far less) takes a neighbour's plane where
    that one is clearly flatter (`SHIFT_FLATNESS`) and the point lies within its neighbourhood
    and on its plane (`ON_PLANE`): on the same face. Its offset is then its height above that
    plane. Also returns each point's support: the half-height about it of all the points its
    plane depended on (its neighbours' neighbourhoods).
    """
    planes = [a[mine].copy() for a in fits[:6]]
    normals, low, high, radius, flatness, offset = planes
    flat = fits.flatness[near]
    support = np.max(np.abs(heights[near] - points[:, 2:3]) + fits.radius[near], axis=1)
    # noise alone gives a neighbourhood the flatness 4 sigma^2 / r^2 (a disk's variance along
    # a diameter is r^2 / 4), sigma the residual of its quadric; one that bends sharply within
    # it (an edge) is far less planar than that, though a quadric follows part of the bend
    noise = 4.0 * (fits.rms[mine] / np.maximum(radius, 1e-300)) ** 2
    steep = 1.0 - normals[:, 2] ** 2 >= MIN_STEEPNESS**2  # shallow: see _refine_shallow
    rows = np.flatnonzero(steep & (flatness > EDGE_FLATNESS * noise)
                          & (flat.min(axis=1) < SHIFT_FLATNESS * flatness))
    for start in range(0, len(rows), CHUNK):
        sub = rows[start:start + CHUNK]
        nb = near[sub]
        rel = points[sub, None, :] - fits.centroid[nb]
        off = np.einsum("nki,nki->nk", rel, fits.normals[nb])  # above the neighbour's plane
        inside = np.einsum("nki,nki->nk", rel, rel) <= fits.radius[nb] ** 2
        lies = (inside & (np.abs(off) <= ON_PLANE * fits.rms[nb])
                & (flat[sub] < SHIFT_FLATNESS * flatness[sub, None]))
        best = np.argmin(np.where(lies, flat[sub], np.inf), axis=1)
        took = lies[np.arange(len(sub)), best]
        sub, q = sub[took], nb[took, best[took]]
        normals[sub], offset[sub] = fits.normals[q], off[took.nonzero()[0], best[took]]
        low[sub], high[sub] = fits.low[q], fits.high[q]
        radius[sub], flatness[sub] = fits.radius[q], fits.flatness[q]
    return tuple(planes), support


def _refine_shallow(nodes: FloatArray, tree: cKDTree, which: IntArray,
                    planes: tuple[FloatArray, ...], k: int) -> tuple[FloatArray, FloatArray]:
    """Where the tangent plane is shallow (within `MIN_STEEPNESS` of the slicing plane), fit
    the surface again as a height field over the plane, a quadric over ``k`` neighbours, and
    put its normal, offset, height range and radius in ``planes`` (in place). Returns each
    point's slope over its standard error there (inf elsewhere): a surface is known to cross
    a plane at a shallow angle only when its slope stands out of the noise; and the
    quadric's second-order term along its slope (0 elsewhere): a shallow surface bends
    within the distance that it slides (a ridge's crest, a dome's top)."""
    normals, low, high, radius, flatness, offset = planes
    score = np.full(len(which), np.inf)
    bend = np.zeros(len(which))
    shallow = np.flatnonzero(1.0 - normals[:, 2] ** 2 < MIN_STEEPNESS**2)
    if k <= 6 or not len(shallow):
        return score, bend
    residual = np.empty(len(shallow))
    for start in range(0, len(shallow), WIDE_CHUNK):
        rows = shallow[start:start + WIDE_CHUNK]
        dist, idx = tree.query(nodes[which[rows]], k=k)
        nbr = nodes[idx]
        rel = nbr - nodes[which[rows]][:, None, :]
        # across a thin shell lying near the plane, the point's own face only
        weight = own_sheet(*principal(nbr)[1:], fan=False)
        a = quadric_terms(rel[..., 0], rel[..., 1]) * weight[..., None]
        coef, inverse = quadric_fit(a, rel[..., 2] * weight)
        resid = rel[..., 2] * weight - (a @ coef[..., None])[..., 0]
        noise = np.einsum("nk,nk->n", resid, resid) / (weight.sum(axis=1) - 6)
        grad = coef[:, 1:3]
        slope = np.hypot(grad[:, 0], grad[:, 1])
        along = grad / np.maximum(slope, 1e-300)[:, None]
        bend[rows] = (coef[:, 3] * along[:, 0] ** 2 + coef[:, 4] * along[:, 0] * along[:, 1]
                      + coef[:, 5] * along[:, 1] ** 2)
        var = noise * np.einsum("ni,nij,nj->n", along, inverse[:, 1:3, 1:3], along)
        score[rows] = slope / np.sqrt(np.maximum(var, 1e-300))
        # steep: the wide fit and the tangent plane disagree (an edge), and a slide along
        # either would go astray
        torn = rows[slope > np.tan(np.arcsin(MIN_STEEPNESS))]
        score[torn], flatness[torn] = 0.0, np.inf
        residual[start:start + WIDE_CHUNK] = noise
        norm = np.sqrt(1.0 + slope**2)
        normals[rows] = np.column_stack([-grad, np.ones(len(rows))]) / norm[:, None]
        offset[rows] = -coef[:, 0] / norm
        low[rows] = np.where(weight > 0, nbr[:, :, 2], np.inf).min(axis=1)
        high[rows] = np.where(weight > 0, nbr[:, :, 2], -np.inf).max(axis=1)
        radius[rows] = dist[:, -1]
    # a height field that fits far worse than the shallow surfaces' typical one spans an edge
    # (a cap and the wall under it): its normal is the edge's, not a surface's, and gives no
    # section point
    edge = shallow[residual > EDGE_RESIDUAL * np.median(residual)]
    score[edge], flatness[edge] = 0.0, np.inf
    return score, bend


def _local_quadric(centred: FloatArray, axes: FloatArray, weight: FloatArray
                   ) -> tuple[FloatArray, FloatArray]:
    """The least-squares quadric of each neighbourhood (``centred``: (n, k, 3) about its
    centroid; ``axes``: its principal axes, the normal first; ``weight`` (n, k): 1 on the
    points fitted, 0 on the rest), as the height along the normal over the major and minor
    axes: its (n, 6) coefficients and the root-mean-square of its residuals. A quadric rather
    than the plane, so that projecting a point onto it removes the noise and not the curvature
    (the plane through the centroid of a curved wall lies about r^2 / 6R inside it)."""
    local = centred @ axes  # (normal, minor, major) coordinates
    terms = quadric_terms(local[..., 2], local[..., 1])
    height = local[..., 0]
    if weight.min(initial=1.0) < 1.0:
        terms, height = terms * weight[..., None], height * weight
    coef, _ = quadric_fit(terms, height)
    resid = height - (terms @ coef[..., None])[..., 0]
    dof = np.maximum(1.0, weight.sum(axis=1) - 6)
    return coef, np.sqrt(np.einsum("nk,nk->n", resid, resid) / dof)


def _above_quadric(rel: FloatArray, axes: FloatArray, coef: FloatArray) -> FloatArray:
    """Heights of points above quadrics (``rel``: (n, 3) each point about its quadric's
    centroid; ``axes``, ``coef`` as from `_local_quadric`), along the quadrics' normal axes."""
    local = np.einsum("ni,nij->nj", rel, axes)
    terms = quadric_terms(local[:, 2], local[:, 1])
    return local[:, 0] - np.einsum("ni,ni->n", terms, coef)


def quadric_terms(x: FloatArray, y: FloatArray) -> FloatArray:
    """The terms 1, x, y, x^2, xy, y^2 of a quadric, stacked on a last axis."""
    return np.stack([np.ones_like(x), x, y, x * x, x * y, y * y], axis=-1)


def quadric_fit(terms: FloatArray, h: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Least-squares quadric of each neighbourhood, ``h`` over its (n, k, 6) ``terms``: the
    (n, 6) coefficients and the inverses of the (ridged) normal equations, whose diagonal
    scales the coefficients' variances."""
    gram = np.swapaxes(terms, 1, 2) @ terms  # batched BLAS: einsum is 6x slower
    gram += QUADRIC_RIDGE * np.einsum("nii->n", gram)[:, None, None] * np.eye(6)
    inverse = np.linalg.inv(gram)  # 6 x 6 per point
    return (inverse @ (np.swapaxes(terms, 1, 2) @ h[..., None]))[..., 0], inverse


def section_points(surface: SurfaceSamples, rows: slice, z: float) -> FloatArray:
    """The points of ``surface[rows]`` slid along their tangent planes to the plane at height
    ``z``, as (m, 2) plane coordinates; points whose surface does not reach ``z`` are left out.
    """
    n = surface.normals[rows]
    uvh = surface.uvh[rows] - surface.offset[rows, None] * n  # onto the tangent plane
    dh = z - uvh[:, 2]
    along = 1.0 - n[:, 2] ** 2  # squared sine of the normal's angle to the axis
    radius = surface.radius[rows]
    # only neighbourhoods that straddle the plane: one that stops short of it extrapolates its
    # tangent plane, which on shallow surfaces put points 1.5-2.5 tolerances off the bunny's
    # sections (a straddling neighbourhood still leaves the section points closer together
    # than its radius, so nothing is lost but redundancy)
    reaches = (surface.low[rows] <= z) & (z <= surface.high[rows])
    steep = (along >= MIN_STEEPNESS**2) | (surface.slope_score[rows] >= MIN_SLOPE_SCORE)
    # a vertical wall's slope is capped (it slides by dh / 1e12: nothing)
    slope = np.sqrt(along) / np.maximum(np.abs(n[:, 2]), 1e-12)
    distance, crosses = _slide_distance(dh, slope, surface.bend[rows])
    up = -np.sign(n[:, 2:3]) * n[:, :2] / np.maximum(np.sqrt(along), 1e-300)[:, None]
    shift = np.where(steep[:, None], distance[:, None] * up, 0.0)
    slide = np.abs(np.where(steep, distance, 0.0))
    planar = surface.flatness[rows] <= MAX_FLATNESS
    # a shallow surface curves away from its tangent plane sooner (it turns to a wall)
    reach = np.where(np.isfinite(surface.slope_score[rows]), MAX_SHALLOW_SLIDE, MAX_SLIDE)
    keep = reaches & steep & crosses & planar & (slide <= reach * radius)
    return _without_strays(uvh[keep, :2] + shift[keep])


def _slide_distance(dh: FloatArray, slope: FloatArray, bend: FloatArray
                    ) -> tuple[FloatArray, FloatArray]:
    """How far up its slope (negative: down) each point reaches the height ``dh`` above it,
    on the surface ``slope · s + bend · s²``, and whether it does: the root nearest to the
    point (the tangent plane's ``dh / slope`` where ``bend`` is 0); a surface that turns
    before it reaches the plane (a ridge whose crest is below it) does not."""
    disc = slope**2 + 4.0 * bend * dh
    crosses = (disc >= 0) & (slope > 0)
    root = slope + np.sqrt(np.maximum(disc, 0.0))
    return np.divide(2.0 * dh, root, out=np.zeros_like(dh), where=crosses), crosses


def _without_strays(xy: FloatArray) -> FloatArray:
    """The section points less those far off the line of their nearest section points."""
    k = STRAY_NEIGHBOURS
    if len(xy) <= k:
        return xy
    _, idx = cKDTree(xy).query(xy, k=k)
    nbr = xy[idx]
    centred = nbr - nbr.mean(axis=1, keepdims=True)
    cov = np.swapaxes(centred, 1, 2) @ centred
    _, vectors = np.linalg.eigh(cov)
    normal = vectors[:, :, 0]
    off = np.abs((centred @ normal[..., None])[..., 0])
    own = off[:, 0]
    typical = np.median(off, axis=1)
    return xy[~(own > STRAY_FACTOR * np.maximum(typical, 1e-300))]


def mesh_section(mesh, basis: FloatArray, z: float) -> list[tuple[FloatArray, bool]]:
    """The exact section of a triangle mesh (trimesh) by the plane at height ``z`` along
    ``basis[2]``: polylines in plane coordinates, closed where the mesh is closed there."""
    import shapely
    import trimesh

    segments = trimesh.intersections.mesh_plane(mesh, basis[2], z * basis[2])
    if not len(segments):
        return []
    flat = segments @ basis[:2].T  # (m, 2, 2): each segment in plane coordinates
    # the two triangles of an edge compute its crossing point apart: snap to a fine grid
    grid = SNAP * max(float(np.abs(flat).max()), 1e-300)
    flat = np.round(flat / grid) * grid
    flat = flat[np.any(flat[:, 0] != flat[:, 1], axis=1)]
    merged = shapely.line_merge(shapely.multilinestrings(list(flat)))
    out = []
    for line in shapely.get_parts(merged):
        xy = shapely.get_coordinates(line)
        closed = len(xy) >= 4 and np.allclose(xy[0], xy[-1])
        out.append((xy[:-1] if closed else xy, bool(closed)))
    return out
