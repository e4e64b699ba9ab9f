"""A stem walked out along one wall and back along the other: two walls the march merged.

Where two walls run closer than the radius, the march follows them as one chain (a stem: a
slit, a thin limb or hole). Drawn as a polygon, the chain is walked out and back, the two
passes apart by the walls' measured half-width, so that the polygon has an inside.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..types import FloatArray

#: Half the width between a stem's two walls, in radii: at least this, so that the polygon has
#: an inside where the walls converge...
MIN_HALF_WIDTH = 0.05
#: ... and at most this: the walls were merged because they lie within a radius.
MAX_HALF_WIDTH = 0.5
#: A stem whose path zigzags between walls 1-2 radii apart is read again along its path
#: averaged over this many nodes each side (walked out and back without crossing itself, and
#: measured along its length, not the zigzag's).
SMOOTH_NODES = 2


def out_and_back(stem: FloatArray, side: float, members: cKDTree, radius: float
                 ) -> FloatArray:
    """A stem from its root to its tip and back, the passes ``side`` x its half-width to
    either side (the tip once)."""
    normal = left_normals(stem)
    half = half_widths(stem, normal, members, radius)
    out = stem[:-1] + side * half[:-1, None] * normal[:-1]
    back = (stem[:-1] - side * half[:-1, None] * normal[:-1])[::-1]
    return np.vstack([out, stem[-1:], back])


def left_normals(path: FloatArray) -> FloatArray:
    """The unit normal to the left of a path at each of its points (from its central
    differences)."""
    tangent = np.gradient(path, axis=0)
    tangent /= np.maximum(np.linalg.norm(tangent, axis=1, keepdims=True), 1e-300)
    return np.column_stack([-tangent[:, 1], tangent[:, 0]])


def half_widths(stem: FloatArray, normal: FloatArray, members: cKDTree, radius: float
                ) -> FloatArray:
    """Half the distance between a stem's walls at each of its points: the median offset of
    the points within a radius across it, within [`MIN_HALF_WIDTH`, `MAX_HALF_WIDTH`] radii."""
    half = np.full(len(stem), MIN_HALF_WIDTH * radius)
    for i, near in enumerate(members.query_ball_point(stem, radius)):
        if near:
            off = np.abs((members.data[near] - stem[i]) @ normal[i])
            half[i] = np.median(off)
    return np.clip(half, MIN_HALF_WIDTH * radius, MAX_HALF_WIDTH * radius)


def smoothed(stem: FloatArray) -> FloatArray:
    """A stem's path averaged over `SMOOTH_NODES` nodes each side (its root and tip stay)."""
    if len(stem) < 3:
        return stem
    k = SMOOTH_NODES
    padded = np.vstack([np.repeat(stem[:1], k, axis=0), stem, np.repeat(stem[-1:], k, axis=0)])
    kernel = np.ones(2 * k + 1) / (2 * k + 1)
    out = np.column_stack([np.convolve(padded[:, d], kernel, mode="valid") for d in range(2)])
    out[0], out[-1] = stem[0], stem[-1]
    return out
