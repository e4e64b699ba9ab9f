"""Thin walls: a neighbourhood that holds both faces of a wall thinner than itself.

A point's tangent plane is fitted to its nearest neighbours (`wavepoly.sections`). Where the
object's wall is thinner than that neighbourhood (a tube, a shell, a fin), the neighbours lie
on both faces: the plane and quadric fitted to all of them lie mid-wall, every point is
projected there, and the layer's section points of the two faces fall on one curve, which the
fit draws as one outline of a solid region (a thin tube sliced comes out a filled disc). Here
such a neighbourhood is recognised by its heights across the tangent plane: they fall in two
sharp groups (the faces) on parallel planes, and each point is fitted to its own group only.

The heights are split in two (two-means, `wavepoly.kernels.sheet_sides`), and the normal
estimated again from the points with each group's mean taken out ("side-centred"), a few
rounds: the two faces' offset no longer adds to the spread across, so a wall thicker than the
noise but thinner than the neighbourhood gives its faces' own normal. The faces must lie about
8 noise levels apart (`SHEET_SHARPNESS`): a wall thinner than that is one surface to the
scan. Where the faces converge (the tip of a thin shell, a wedge's edge) or curve round (a
rounded rim), the groups are not parallel planes, or one of them holds too few points to be a
face, and the neighbourhood is left whole.

References
----------
.. [1] H. Hoppe, T. DeRose, T. Duchamp, J. McDonald and W. Stuetzle, "Surface reconstruction
   from unorganized points", SIGGRAPH 1992 (tangent planes from neighbourhood PCA; a
   neighbourhood must not span two sheets of the surface).
.. [2] S. P. Lloyd, "Least squares quantization in PCM", IEEE Trans. Information Theory
   28(2), 1982, pp. 129-137 (two-means; in one dimension the best split of sorted values is
   found exactly by trying every one).
"""

from __future__ import annotations

import numpy as np

from .kernels import sheet_sides
from .types import FloatArray

#: Each face must hold at least this many of a neighbourhood's points: enough for its own
#: quadric (6); a stray or two beside a face are not a face. (At 8, 3 % of a wall's 24-point
#: neighbourhoods hold fewer on one face by chance, and their points fall mid-wall.)
SHEET_POINTS = 6
#: The faces' own spread across (pooled RMS) must be below this share of the gap between their
#: means: two faces more than about 8 noise levels apart (Gaussian scatter split in two gives
#: 0.38, a uniform band 0.29). At 0.15, 1.5 in 10^4 neighbourhoods of a single noisy face
#: came out split by chance (47 of the bunny's 300,000 points); at 0.12 none of 300,000.
SHEET_SHARPNESS = 0.12
#: The two faces' own planes must lie within this angle: a wall of even thickness, not a
#: wedge's converging faces or the two flanks of a rounded rim.
SHEETS_PARALLEL = np.radians(15.0)
#: Rounds of splitting and estimating the normal again from the side-centred points: the
#: first split along a normal tilted by the two faces is rough, the next ones sharper (a
#: hollow ball's shell, 0.6 of a neighbourhood's radius thick: 74, 84 and 86 % of its
#: neighbourhoods split after 1, 2 and 3 rounds from `FAN_STARTS` starts; 92 % hold at
#: least `SHEET_POINTS` on each face).
SHEET_ROUNDS = 3
#: A neighbourhood whose smallest principal variance exceeds this share of the middle one is
#: thick for a face, and is split from several starts where its smallest axis gave no sharp
#: split (a noisy scan is thinned to a median of 0.2, `sections.NOISE_FLATNESS`: 13 % of the
#: bunny's noisy cloud lies above 0.3, 44 % above 0.2, each costing the starts below; the
#: shell below splits 84 % of its neighbourhoods at 0.3, 86 % at 0.2)...
WIDE_WALL_FLATNESS = 0.3
#: ... this many, fanned evenly between its two smallest axes (a hollow ball's shell 0.6 of a
#: neighbourhood's radius thick: 72 % split from those two axes, 84 % from four directions,
#: 86 % from eight).
FAN_STARTS = 4


def own_principal(nbr: FloatArray) -> tuple[FloatArray, ...]:
    """`principal` of each neighbourhood in ``nbr`` (n, k, 3), of the point's own face where
    it spans both faces of a thin wall (`own_sheet`), and the (n, k) weights: 1 on the
    points fitted."""
    centroid, centred, values, axes = principal(nbr)
    weight = own_sheet(centred, values, axes)
    split = np.flatnonzero(weight.min(axis=1) == 0)
    if len(split):
        (centroid[split], centred[split], values[split],
         axes[split]) = principal(nbr[split], weight[split])
    return centroid, centred, values, axes, weight


def principal(nbr: FloatArray, weight: FloatArray | None = None) -> tuple[FloatArray, ...]:
    """Centroid, centred points, principal variances (ascending) and axes of each (k, 3)
    neighbourhood in ``nbr`` (n, k, 3), of the points of ``weight`` (n, k) 1 where given."""
    if weight is None:
        centroid = nbr.mean(axis=1)
        centred = nbr - centroid[:, None]
        values, axes = np.linalg.eigh(np.swapaxes(centred, 1, 2) @ centred)
        return centroid, centred, values, axes
    centroid = (weight[:, None, :] @ nbr)[:, 0] / weight.sum(axis=1)[:, None]
    centred = nbr - centroid[:, None]
    own = centred * weight[..., None]
    values, axes = np.linalg.eigh(np.swapaxes(own, 1, 2) @ own)
    return centroid, centred, values, axes


def own_sheet(centred: FloatArray, values: FloatArray, axes: FloatArray, *, fan: bool = True
              ) -> FloatArray:
    """Which points of each neighbourhood lie on the face of its first point (the point
    itself, nearest first).

    Parameters
    ----------
    centred : (n, k, 3) neighbourhoods about their centroids.
    values, axes : (n, 3) their principal variances, ascending, and (n, 3, 3) axes (columns),
        as from `numpy.linalg.eigh`.
    fan : split thick neighbourhoods from several starts (below); a wide neighbourhood, whose
        faces lie well within its radius, needs none.

    Returns
    -------
    (n, k) weights: 1.0 on the point's own face, 0.0 on the other one; all 1.0 where the
    neighbourhood is one face.

    Notes
    -----
    The heights are first split across the smallest axis. Where the faces lie almost a
    neighbourhood's radius apart, the two together are nearly as thick as they are wide, and
    their smallest axis is as often one along the wall: where that split is not sharp and
    the neighbourhood is less flat than `WIDE_WALL_FLATNESS`, it is split again from
    `FAN_STARTS` directions fanned between the two smallest axes.
    """
    n, k, _ = centred.shape
    weight = np.ones((n, k))
    if k < 2 * SHEET_POINTS:
        return weight
    high, sharpness = _sides(centred, axes[:, None, :, 0])
    wide = np.flatnonzero(fan & (sharpness >= SHEET_SHARPNESS)
                          & (values[:, 0] > WIDE_WALL_FLATNESS * values[:, 1]))
    if len(wide):
        angle = np.arange(FAN_STARTS) * np.pi / FAN_STARTS
        starts = (np.cos(angle)[None, :, None] * axes[wide, None, :, 0]
                  + np.sin(angle)[None, :, None] * axes[wide, None, :, 1])
        high[wide], sharpness[wide] = _sides(centred[wide], starts)
    rows = np.flatnonzero(sharpness < SHEET_SHARPNESS)
    rows = rows[_parallel(centred[rows], high[rows])]
    weight[rows] = (high[rows] == high[rows, :1]).astype(float)  # the point's own face
    return weight


def _sides(centred: FloatArray, starts: FloatArray) -> tuple[np.ndarray, FloatArray]:
    """`wavepoly.kernels.sheet_sides` of the neighbourhoods from their (n, c, 3) ``starts``."""
    return sheet_sides(np.ascontiguousarray(centred, dtype=float),
                       np.ascontiguousarray(starts, dtype=float), SHEET_POINTS, SHEET_ROUNDS)


def sheet_sides_reference(centred: FloatArray, starts: FloatArray
                          ) -> tuple[np.ndarray, FloatArray]:
    """NumPy reference of `wavepoly.kernels.sheet_sides` (for the tests): the sharpest split
    of each neighbourhood over its (n, c, 3) ``starts``, each refined `SHEET_ROUNDS` times
    across the side-centred normal."""
    n, k, _ = centred.shape
    high = np.zeros((n, k), dtype=bool)
    sharpness = np.full(n, np.inf)
    for c in range(starts.shape[1]):
        side, sharp = _two_faces((centred @ starts[:, c, :, None])[..., 0])
        for _ in range(SHEET_ROUNDS):
            across = _side_centred_normal(centred, side)
            side, sharp = _two_faces((centred @ across[..., None])[..., 0])
        better = sharp < sharpness
        high[better], sharpness[better] = side[better], sharp[better]
    return high, sharpness


def _two_faces(heights: FloatArray) -> tuple[np.ndarray, FloatArray]:
    """The best two-means split of each row of ``heights`` (n, k) with at least
    `SHEET_POINTS` on each side, found exactly over the sorted values: which values lie on
    the high side, and the split's sharpness: the sides' pooled spread over the gap between
    their means (compared with `SHEET_SHARPNESS`)."""
    n, k = heights.shape
    order = np.argsort(heights, axis=1)
    ranked = np.take_along_axis(heights, order, axis=1)
    ranked = ranked - ranked.mean(axis=1, keepdims=True)  # sums of squares stay accurate
    first, second = np.cumsum(ranked, axis=1), np.cumsum(ranked**2, axis=1)
    low_size = np.arange(SHEET_POINTS, k - SHEET_POINTS + 1)
    low1, low2 = first[:, low_size - 1], second[:, low_size - 1]
    high1, high2 = first[:, -1:] - low1, second[:, -1:] - low2
    within = (low2 - low1**2 / low_size) + (high2 - high1**2 / (k - low_size))
    best = np.argmin(within, axis=1)
    size = low_size[best]
    rows = np.arange(n)
    gap = high1[rows, best] / (k - size) - low1[rows, best] / size
    spread = np.sqrt(np.maximum(within[rows, best], 0.0) / k)
    rank = np.argsort(order, axis=1)
    return rank >= size[:, None], spread / np.maximum(gap, 1e-300)


def _side_centred_normal(centred: FloatArray, high: np.ndarray) -> FloatArray:
    """The smallest principal axis of each neighbourhood with each face's mean taken out."""
    side = high[..., None]
    count_high = np.maximum(high.sum(axis=1), 1)[:, None]
    count_low = np.maximum((~high).sum(axis=1), 1)[:, None]
    mean_high = np.where(side, centred, 0.0).sum(axis=1) / count_high
    mean_low = np.where(side, 0.0, centred).sum(axis=1) / count_low
    local = centred - np.where(side, mean_high[:, None], mean_low[:, None])
    _, axes = np.linalg.eigh(np.swapaxes(local, 1, 2) @ local)
    return axes[:, :, 0]


def _parallel(centred: FloatArray, high: np.ndarray) -> np.ndarray:
    """Whether each neighbourhood's two faces (``high`` marks one) have planes within
    `SHEETS_PARALLEL` of each other."""
    normals = []
    for side in (high, ~high):
        w = side[..., None].astype(float)
        mean = (w * centred).sum(axis=1) / np.maximum(w.sum(axis=1), 1.0)
        local = (centred - mean[:, None]) * w
        _, axes = np.linalg.eigh(np.swapaxes(local, 1, 2) @ local)
        normals.append(axes[:, :, 0])
    cosine = np.abs(np.einsum("ni,ni->n", *normals))
    return cosine >= np.cos(SHEETS_PARALLEL)
