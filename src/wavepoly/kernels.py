"""Compiled inner loops (numba), where a loop over points is the algorithm itself.

Each kernel has a NumPy reference beside the code that calls it, and the tests compare them
on random cases. Kernels take and return plain arrays, so they know nothing of the records.

References
----------
.. [1] W. S. Chan and F. Chin, "Approximation of polygonal curves with minimum number of line
   segments or minimum error", Int. J. Comput. Geom. Appl. 6(1), 1996, pp. 59-77 (the cones).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def _wrap(angle: float) -> float:  # pragma: no cover - compiled
    return (angle + math.pi) % (2 * math.pi) - math.pi


@njit(cache=True, nogil=True)
def sweep_cones(v: np.ndarray, at: np.ndarray, pts: np.ndarray, rows: np.ndarray,
                last: np.ndarray, limit: float, slack: float
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # pragma: no cover - compiled
    """Chan & Chin's cone test from each vertex ``a`` in ``rows``: for targets b = a+1 ..
    ``last[i]``, is b inside the cone of directions from a that pass within ``limit`` of every
    point ``pts[at[a]:at[b]]`` farther than ``limit`` (the points between them)? Each row stops
    where its cone closes. Returns the flat (a, b, ok) of every target examined.
    """
    total = 0
    for i in range(len(rows)):
        total += max(0, last[i] - rows[i])
    out_a = np.empty(total, dtype=np.intp)
    out_b = np.empty(total, dtype=np.intp)
    out_ok = np.empty(total, dtype=np.bool_)
    k = 0
    for i in range(len(rows)):
        a = rows[i]
        lo, hi, ref, have_ref = -np.inf, np.inf, 0.0, False
        p = at[a]
        ax, ay = v[a, 0], v[a, 1]
        for b in range(a + 1, last[i] + 1):
            while p < at[b]:
                dx, dy = pts[p, 0] - ax, pts[p, 1] - ay
                r = math.hypot(dx, dy)
                if r > limit:
                    theta = math.atan2(dy, dx)
                    if not have_ref:
                        ref, have_ref = theta, True
                    rel = _wrap(theta - ref)
                    half = math.asin(min(limit / r, 1.0))
                    lo, hi = max(lo, rel - half), min(hi, rel + half)
                p += 1
            if lo > hi:
                break  # the cone is closed: every later target is outside it
            rel_t = _wrap(math.atan2(v[b, 1] - ay, v[b, 0] - ax) - ref)
            out_a[k], out_b[k] = a, b
            out_ok[k] = (rel_t >= lo - slack) and (rel_t <= hi + slack)
            k += 1
    return out_a[:k], out_b[:k], out_ok[:k]


@njit(cache=True, nogil=True)
def _segment_distance(px: float, py: float, ax: float, ay: float, bx: float, by: float
                      ) -> float:  # pragma: no cover - compiled
    ux, uy, wx, wy = bx - ax, by - ay, px - ax, py - ay
    denom = ux * ux + uy * uy
    t = (wx * ux + wy * uy) / (denom if denom > 0 else 1.0)
    t = min(max(t, 0.0), 1.0)
    dx, dy = wx - t * ux, wy - t * uy
    return math.sqrt(dx * dx + dy * dy)


#: A bound on the grid's size: a long thin polyline would otherwise get a grid of mostly empty
#: cells over its bounding box.
MAX_CELLS_PER_SEGMENT = 8


def segment_grid(a: np.ndarray, b: np.ndarray, per_cell: float = 2.0):
    """A uniform grid over segments: each segment listed in every cell its bounding box
    touches, cells about ``per_cell`` median segment lengths wide but never more cells than
    `MAX_CELLS_PER_SEGMENT` per segment (CSR arrays)."""
    lo = np.minimum(a, b).min(axis=0)
    hi = np.maximum(a, b).max(axis=0)
    length = np.hypot(*(b - a).T)
    area = float(np.prod(np.maximum(hi - lo, 1e-300)))
    cell = max(per_cell * float(np.median(length)),
               np.sqrt(area / (MAX_CELLS_PER_SEGMENT * len(a))), 1e-300)
    shape = np.maximum(np.ceil((hi - lo) / cell).astype(np.intp), 1)
    c0 = np.clip(((np.minimum(a, b) - lo) / cell).astype(np.intp), 0, shape - 1)
    c1 = np.clip(((np.maximum(a, b) - lo) / cell).astype(np.intp), 0, shape - 1)
    return (lo, cell, shape, *_fill_cells(c0, c1, shape[0], shape[1]))


@njit(cache=True)
def _fill_cells(c0, c1, nx, ny):  # pragma: no cover - compiled
    count = np.zeros(nx * ny + 1, dtype=np.intp)
    for s in range(len(c0)):
        for i in range(c0[s, 0], c1[s, 0] + 1):
            for j in range(c0[s, 1], c1[s, 1] + 1):
                count[i * ny + j + 1] += 1
    start = np.cumsum(count)
    fill = start[:-1].copy()
    items = np.empty(start[-1], dtype=np.intp)
    for s in range(len(c0)):
        for i in range(c0[s, 0], c1[s, 0] + 1):
            for j in range(c0[s, 1], c1[s, 1] + 1):
                items[fill[i * ny + j]] = s
                fill[i * ny + j] += 1
    return start, items


@njit(cache=True, nogil=True)
def nearest_in_grid(points, a, b, lo, cell, shape, start, items, limit
                    ) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover - compiled
    """Nearest segment of each point (ties: the lowest index) and the distance, exact: rings
    of cells are searched outwards until no unsearched cell can hold a nearer segment, or
    until none can hold one nearer than ``limit[p]`` (then the value returned is only known
    to be at least the limit; -1 as the segment when none was found)."""
    nx, ny = shape[0], shape[1]
    seg = np.empty(len(points), dtype=np.intp)
    dist = np.empty(len(points))
    for p in range(len(points)):
        px, py = points[p, 0], points[p, 1]
        cx = min(max(int((px - lo[0]) / cell), 0), nx - 1)
        cy = min(max(int((py - lo[1]) / cell), 0), ny - 1)
        best, best_s, ring = np.inf, -1, 0
        while True:
            i0, i1, j0, j1 = cx - ring, cx + ring, cy - ring, cy + ring
            for i in range(max(i0, 0), min(i1, nx - 1) + 1):
                for j in range(max(j0, 0), min(j1, ny - 1) + 1):
                    if ring and i0 < i < i1 and j0 < j < j1:
                        continue  # searched in an earlier ring
                    for k in range(start[i * ny + j], start[i * ny + j + 1]):
                        s = items[k]
                        d = _segment_distance(px, py, a[s, 0], a[s, 1], b[s, 0], b[s, 1])
                        if d < best or (d == best and s < best_s):
                            best, best_s = d, s
            bound = np.inf  # the nearest point of any cell not yet searched
            if i0 > 0:
                bound = min(bound, px - (lo[0] + i0 * cell))
            if i1 < nx - 1:
                bound = min(bound, lo[0] + (i1 + 1) * cell - px)
            if j0 > 0:
                bound = min(bound, py - (lo[1] + j0 * cell))
            if j1 < ny - 1:
                bound = min(bound, lo[1] + (j1 + 1) * cell - py)
            if best < bound or bound == np.inf or bound >= limit[p]:
                break
            ring += 1
        seg[p], dist[p] = best_s, best
    return seg, dist


@njit(cache=True, nogil=True)
def neighbour_distances(points: np.ndarray, owner: np.ndarray, coeffs: np.ndarray,
                        closed: bool) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover
    """Distance of each point to the control-polygon segments before and after the
    coefficient it belongs to (eq. 8); inf where an open polygon has no such segment."""
    m, n = len(coeffs), len(points)
    d_prev, d_next = np.full(n, np.inf), np.full(n, np.inf)
    for p in range(n):
        o = owner[p]
        prev, nxt = o - 1, o + 1
        if closed:
            prev, nxt = prev % m, nxt % m
        px, py = points[p, 0], points[p, 1]
        if prev >= 0:
            d_prev[p] = _segment_distance(px, py, coeffs[prev, 0], coeffs[prev, 1],
                                          coeffs[o, 0], coeffs[o, 1])
        if nxt < m:
            d_next[p] = _segment_distance(px, py, coeffs[o, 0], coeffs[o, 1],
                                          coeffs[nxt, 0], coeffs[nxt, 1])
    return d_prev, d_next


@njit(cache=True, nogil=True)
def thin_blocks(points: np.ndarray, starts: np.ndarray, ends: np.ndarray, dirs: np.ndarray,
                keep: np.ndarray) -> None:  # pragma: no cover - compiled
    """Akl & Toussaint's filter on each block ``points[starts[i]:ends[i]]``: clear ``keep`` of
    the points strictly inside the polygon of the block's extreme points in the directions
    ``dirs`` (2, d), measured in the frame of the block's chord (see `hull_candidates`)."""
    nd = dirs.shape[1]
    corner = np.empty((nd, 2))
    extreme = np.empty(nd, dtype=np.intp)
    for blk in range(len(starts)):
        s, e = starts[blk], ends[blk]
        cx, cy = points[e - 1, 0] - points[s, 0], points[e - 1, 1] - points[s, 1]
        norm = math.hypot(cx, cy)
        ax, ay = (cx / norm, cy / norm) if norm > 0 else (1.0, 0.0)
        ox, oy = points[s, 0], points[s, 1]
        for k in range(nd):
            best = -np.inf
            for q in range(s, e):
                dx, dy = points[q, 0] - ox, points[q, 1] - oy
                x, y = dx * ax + dy * ay, dy * ax - dx * ay
                proj = x * dirs[0, k] + y * dirs[1, k]
                if proj > best:
                    best, extreme[k] = proj, q
                    corner[k, 0], corner[k, 1] = x, y
        for q in range(s, e):
            dx, dy = points[q, 0] - ox, points[q, 1] - oy
            x, y = dx * ax + dy * ay, dy * ax - dx * ay
            inside = True
            for k in range(nd):
                k2 = (k + 1) % nd
                ex, ey = corner[k2, 0] - corner[k, 0], corner[k2, 1] - corner[k, 1]
                length2 = ex * ex + ey * ey
                if length2 <= 0:
                    continue  # a degenerate edge tells nothing
                c = ex * corner[k, 1] - ey * corner[k, 0]
                c += 1e-12 * (length2 + abs(c))  # a margin: on the edge is not inside
                if not y * ex - x * ey > c:
                    inside = False
                    break
            if inside:
                for k in range(nd):
                    if extreme[k] == q:
                        inside = False
            if inside:
                keep[q] = False
