"""Compiled inner loops over 3D neighbourhoods (numba).

References
----------
.. [1] S. P. Lloyd, "Least squares quantization in PCM", IEEE Trans. Information Theory
   28(2), 1982, pp. 129-137 (two-means; in one dimension the best split of sorted values is
   found exactly by trying every one).
.. [2] O. K. Smith, "Eigenvalues of a symmetric 3 x 3 matrix", Comm. ACM 4(4), 1961, p. 168
   (the closed form of the smallest eigenvalue).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def _best_split(heights: np.ndarray, order: np.ndarray, min_side: int, high: np.ndarray
                ) -> float:  # pragma: no cover - compiled
    """The best two-means split of ``heights`` (k,) with at least ``min_side`` values on each
    side, tried at every place in their sorted order (``order``: a buffer): marks the high
    side in ``high`` and returns the split's sharpness (the sides' pooled spread over the gap
    between their means)."""
    k = len(heights)
    for i in range(k):  # insertion sort: a neighbourhood holds a few dozen points
        j = i
        while j > 0 and heights[order[j - 1]] > heights[i]:
            order[j] = order[j - 1]
            j -= 1
        order[j] = i
    mean = 0.0
    for i in range(k):
        mean += heights[i]
    mean /= k
    total1 = 0.0
    total2 = 0.0
    for i in range(k):
        d = heights[i] - mean
        total1 += d
        total2 += d * d
    low1 = 0.0
    low2 = 0.0
    best, best_size, best_gap = np.inf, min_side, 0.0
    for j in range(k - min_side):
        d = heights[order[j]] - mean
        low1 += d
        low2 += d * d
        size = j + 1
        if size < min_side:
            continue
        high1, high2 = total1 - low1, total2 - low2
        within = (low2 - low1 * low1 / size) + (high2 - high1 * high1 / (k - size))
        if within < best:
            best, best_size = within, size
            best_gap = high1 / (k - size) - low1 / size
    for j in range(k):
        high[order[j]] = j >= best_size
    return math.sqrt(max(best, 0.0) / k) / max(best_gap, 1e-300)


@njit(cache=True, nogil=True)
def _smallest_axis(a: np.ndarray, out: np.ndarray) -> None:  # pragma: no cover - compiled
    """The unit eigenvector of the smallest eigenvalue of the symmetric 3 x 3 ``a``, into
    ``out``: the eigenvalue in closed form (Smith), the vector as the longest cross product
    of two rows of ``a`` less it."""
    q = (a[0, 0] + a[1, 1] + a[2, 2]) / 3.0
    off = a[0, 1] ** 2 + a[0, 2] ** 2 + a[1, 2] ** 2
    p = math.sqrt(max(((a[0, 0] - q) ** 2 + (a[1, 1] - q) ** 2 + (a[2, 2] - q) ** 2
                       + 2.0 * off) / 6.0, 0.0))
    if p < 1e-300:
        out[0], out[1], out[2] = 0.0, 0.0, 1.0
        return
    b00, b11, b22 = (a[0, 0] - q) / p, (a[1, 1] - q) / p, (a[2, 2] - q) / p
    b01, b02, b12 = a[0, 1] / p, a[0, 2] / p, a[1, 2] / p
    det = (b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02)
           + b02 * (b01 * b12 - b11 * b02))
    phi = math.acos(min(1.0, max(-1.0, det / 2.0))) / 3.0
    smallest = q + 2.0 * p * math.cos(phi + 2.0 * math.pi / 3.0)
    r0 = (a[0, 0] - smallest, a[0, 1], a[0, 2])
    r1 = (a[0, 1], a[1, 1] - smallest, a[1, 2])
    r2 = (a[0, 2], a[1, 2], a[2, 2] - smallest)
    best = -1.0
    for u, v in ((r0, r1), (r0, r2), (r1, r2)):
        c0 = u[1] * v[2] - u[2] * v[1]
        c1 = u[2] * v[0] - u[0] * v[2]
        c2 = u[0] * v[1] - u[1] * v[0]
        size = c0 * c0 + c1 * c1 + c2 * c2
        if size > best:
            best = size
            out[0], out[1], out[2] = c0, c1, c2
    norm = math.sqrt(max(best, 1e-300))
    for i in range(3):
        out[i] /= norm


@njit(cache=True, nogil=True)
def _side_centred_normal(centred: np.ndarray, high: np.ndarray, scatter: np.ndarray,
                         out: np.ndarray) -> None:  # pragma: no cover - compiled
    """The smallest principal axis of a neighbourhood (k, 3) with each side's mean taken
    out, into ``out`` (``scatter``: a 3 x 3 buffer)."""
    k = centred.shape[0]
    mean = np.zeros((2, 3))
    count = np.zeros(2)
    for i in range(k):
        s = 1 if high[i] else 0
        count[s] += 1.0
        for a in range(3):
            mean[s, a] += centred[i, a]
    for s in range(2):
        for a in range(3):
            mean[s, a] /= max(count[s], 1.0)
    scatter[:] = 0.0
    for i in range(k):
        s = 1 if high[i] else 0
        d0 = centred[i, 0] - mean[s, 0]
        d1 = centred[i, 1] - mean[s, 1]
        d2 = centred[i, 2] - mean[s, 2]
        scatter[0, 0] += d0 * d0
        scatter[0, 1] += d0 * d1
        scatter[0, 2] += d0 * d2
        scatter[1, 1] += d1 * d1
        scatter[1, 2] += d1 * d2
        scatter[2, 2] += d2 * d2
    scatter[1, 0], scatter[2, 0], scatter[2, 1] = scatter[0, 1], scatter[0, 2], scatter[1, 2]
    _smallest_axis(scatter, out)


@njit(cache=True, nogil=True)
def _heights(centred: np.ndarray, direction: np.ndarray, out: np.ndarray
             ) -> np.ndarray:  # pragma: no cover - compiled
    for i in range(centred.shape[0]):
        out[i] = (centred[i, 0] * direction[0] + centred[i, 1] * direction[1]
                  + centred[i, 2] * direction[2])
    return out


@njit(cache=True, nogil=True)
def _same_split(a: np.ndarray, b: np.ndarray) -> bool:  # pragma: no cover - compiled
    """Whether two splits put the same points together (either side may be the high one)."""
    same = True
    flipped = True
    for i in range(len(a)):
        same = same and a[i] == b[i]
        flipped = flipped and a[i] != b[i]
    return same or flipped


@njit(cache=True, nogil=True)
def sheet_sides(centred: np.ndarray, starts: np.ndarray, min_side: int, rounds: int
                ) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover - compiled
    """For each neighbourhood (``centred``: (n, k, 3) about its centroid), its heights split
    in two by two-means across each start direction (``starts``: (n, c, 3)), then up to
    ``rounds`` times again across the normal of its points with each side's mean taken out
    (until the sides stay the same); the sharpest split over the starts. Returns (n, k) the
    high sides and (n,) their sharpness (as `_best_split`)."""
    n, k = centred.shape[0], centred.shape[1]
    high = np.zeros((n, k), dtype=np.bool_)
    sharpness = np.full(n, np.inf)
    side = np.zeros(k, dtype=np.bool_)
    before = np.zeros(k, dtype=np.bool_)
    heights = np.empty(k)
    order = np.empty(k, dtype=np.intp)
    scatter = np.empty((3, 3))
    direction = np.empty(3)
    for i in range(n):
        points = centred[i]
        for c in range(starts.shape[1]):
            direction[:] = starts[i, c]
            sharp = _best_split(_heights(points, direction, heights), order, min_side, side)
            for _ in range(rounds):
                before[:] = side
                _side_centred_normal(points, side, scatter, direction)
                sharp = _best_split(_heights(points, direction, heights), order, min_side,
                                    side)
                if _same_split(side, before):
                    break  # the same sides give the same normal: settled
            if sharp < sharpness[i]:
                sharpness[i] = sharp
                high[i] = side
    return high, sharpness
