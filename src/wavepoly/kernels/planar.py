"""Compiled inner loops over planar points and polylines (numba).

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
    # the bounds hold on a degenerate set too (sites in a line: the area is 0)
    cell = max(per_cell * float(np.median(length)),
               np.sqrt(area / (MAX_CELLS_PER_SEGMENT * len(a))),
               float((hi - lo).max()) / (MAX_CELLS_PER_SEGMENT * len(a)), 1e-300)
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
def thin_blocks(points: np.ndarray, index: np.ndarray, starts: np.ndarray, ends: np.ndarray,
                axes: np.ndarray, dirs: np.ndarray, keep: np.ndarray
                ) -> None:  # pragma: no cover - compiled
    """Akl & Toussaint's filter on each block ``points[index[starts[i]:ends[i]]]``: clear
    ``keep`` of the points strictly inside the polygon of the block's extreme points in the
    directions ``dirs`` (2, d), measured in the frame whose x axis is the block's unit
    ``axes[i]`` (see `hull_candidates`)."""
    nd = dirs.shape[1]
    corner = np.empty((nd, 2))
    line = np.empty((nd, 3))
    extreme = np.empty(nd, dtype=np.intp)
    longest = 0
    for blk in range(len(starts)):
        longest = max(longest, ends[blk] - starts[blk])
    xs, ys = np.empty(longest), np.empty(longest)  # a block in its own frame, gathered once
    for blk in range(len(starts)):
        s, e = starts[blk], ends[blk]
        ax, ay = axes[blk, 0], axes[blk, 1]
        ox, oy = points[index[s], 0], points[index[s], 1]
        for q in range(s, e):
            dx, dy = points[index[q], 0] - ox, points[index[q], 1] - oy
            xs[q - s], ys[q - s] = dx * ax + dy * ay, dy * ax - dx * ay
        for k in range(nd):
            best = -np.inf
            for q in range(e - s):
                proj = xs[q] * dirs[0, k] + ys[q] * dirs[1, k]
                if proj > best:
                    best, extreme[k] = proj, q
            corner[k, 0], corner[k, 1] = xs[extreme[k]], ys[extreme[k]]
        edges = 0  # the polygon's edge lines: p is strictly left of one when ex*y - ey*x > c
        for k in range(nd):
            k2 = (k + 1) % nd
            ex, ey = corner[k2, 0] - corner[k, 0], corner[k2, 1] - corner[k, 1]
            length2 = ex * ex + ey * ey
            if length2 <= 0:
                continue  # a degenerate edge tells nothing
            c = ex * corner[k, 1] - ey * corner[k, 0]
            line[edges, 0], line[edges, 1] = ex, ey
            line[edges, 2] = c + 1e-12 * (length2 + abs(c))  # a margin: on it is not inside
            edges += 1
        for q in range(e - s):
            x, y = xs[q], ys[q]
            inside = True
            for k in range(edges):
                if not y * line[k, 0] - x * line[k, 1] > line[k, 2]:
                    inside = False
                    break
            if inside:
                for k in range(nd):
                    if extreme[k] == q:
                        inside = False
            if inside:
                keep[index[s + q]] = False


@njit(cache=True, nogil=True)
def group_order(group: np.ndarray, n_groups: int
                ) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover - compiled
    """Counting sort: the (stable) order that lists the points group by group, and where each
    group's run starts in it (``n_groups + 1`` entries)."""
    start = np.zeros(n_groups + 1, dtype=np.intp)
    for g in group:
        start[g + 1] += 1
    for g in range(n_groups):
        start[g + 1] += start[g]
    fill = start[:-1].copy()
    order = np.empty(len(group), dtype=np.intp)
    for p in range(len(group)):
        order[fill[group[p]]] = p
        fill[group[p]] += 1
    return order, start


@njit(cache=True, nogil=True)
def nearly_uniform_search(grid: np.ndarray, values: np.ndarray
                          ) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover - compiled
    """``np.searchsorted(grid, values, "left")`` and ``"right"`` for a sorted ``grid`` whose
    values are spread about evenly (curve parameters): each search starts where a uniform grid
    would hold the value and steps from there, O(1) per value instead of a binary search's
    cache misses on unsorted values. Exact for any sorted grid (only slower when uneven)."""
    n = len(grid)
    left = np.empty(len(values), dtype=np.intp)
    right = np.empty(len(values), dtype=np.intp)
    if n == 0:
        left[:] = 0
        right[:] = 0
        return left, right
    lo, span = grid[0], grid[-1] - grid[0]
    for p in range(len(values)):
        v = values[p]
        j = 0
        if span > 0 and v > lo:
            j = min(int((v - lo) / span * (n - 1)), n)
        while j > 0 and grid[j - 1] >= v:
            j -= 1
        while j < n and grid[j] < v:
            j += 1
        k = j
        while k < n and grid[k] <= v:
            k += 1
        left[p], right[p] = j, k
    return left, right


@njit(cache=True, nogil=True)
def order_within_groups(values: np.ndarray, group: np.ndarray, n_groups: int
                        ) -> np.ndarray:  # pragma: no cover - compiled
    """``np.argsort(values, kind="stable")`` when ``group`` (0 .. n_groups-1) never decreases
    as ``values`` increase: a counting sort by group, then a stable sort of each group's few
    values (a full sort's cache misses on a large unsorted array are avoided)."""
    order, start = group_order(group, n_groups)
    for g in range(n_groups):
        s, e = start[g], start[g + 1]
        if e - s > 1:
            sub = order[s:e].copy()
            order[s:e] = sub[np.argsort(values[sub], kind="mergesort")]
    return order


@njit(cache=True, nogil=True)
def edge_distances(points: np.ndarray, edge: np.ndarray, vertices: np.ndarray
                   ) -> np.ndarray:  # pragma: no cover - compiled
    """Distance of each point to the polygon edge ``edge[i]`` (vertex e to vertex e+1, the last
    to the first), in one pass and without gathering the edges' ends."""
    k = len(vertices)
    dist = np.empty(len(points))
    for p in range(len(points)):
        e = edge[p]
        f = e + 1 if e + 1 < k else 0
        dist[p] = _segment_distance(points[p, 0], points[p, 1], vertices[e, 0], vertices[e, 1],
                                    vertices[f, 0], vertices[f, 1])
    return dist


@njit(cache=True, nogil=True)
def fewest_edges(flat: np.ndarray, offset: np.ndarray, start: int, end: int, min_edges: int
                 ) -> np.ndarray:  # pragma: no cover - compiled
    """Fewest-edge path from ``start`` to ``end`` over forward chords, with at least
    ``min_edges`` edges; an empty array when there is none.

    Chord (a, a + 1 + j) is feasible when ``flat[offset[a] + j]`` (j < offset[a + 1] -
    offset[a]). The first ``min_edges`` edges are taken breadth first (each vertex keeps the
    first vertex that reaches it), then one pass in vertex order relaxes every chord: the
    chords run forward, so that order is topological.
    """
    n = end + 1
    big = np.iinfo(np.int64).max // 4
    layers = np.full((max(min_edges, 1), n), -1, dtype=np.int64)
    reached = np.zeros(n, dtype=np.bool_)
    reached[start] = True
    for layer in range(min_edges):
        nxt = np.zeros(n, dtype=np.bool_)
        for a in range(n):
            if not reached[a]:
                continue
            for j in range(min(offset[a + 1] - offset[a], end - a)):
                b = a + 1 + j
                if flat[offset[a] + j] and layers[layer, b] < 0:
                    layers[layer, b] = a
                    nxt[b] = True
        reached = nxt
    count = np.full(n, big, dtype=np.int64)
    parent = np.full(n, -1, dtype=np.int64)
    first = n
    for a in range(n):
        if reached[a]:
            count[a] = min_edges
            first = min(first, a)
    for a in range(first, end):
        if count[a] >= big:
            continue
        for j in range(min(offset[a + 1] - offset[a], end - a)):
            b = a + 1 + j
            if flat[offset[a] + j] and count[a] + 1 < count[b]:
                count[b] = count[a] + 1
                parent[b] = a
    if count[end] >= big:
        return np.empty(0, dtype=np.int64)
    path = np.empty(count[end] + 1, dtype=np.int64)
    at, i = end, count[end]
    while parent[at] >= 0:
        path[i] = at
        at = parent[at]
        i -= 1
    for layer in range(min_edges - 1, -1, -1):
        path[i] = at
        at = layers[layer, at]
        i -= 1
    path[i] = at
    return path


@njit(cache=True, nogil=True)
def two_means_sides(owner: np.ndarray, offset: np.ndarray, weight: np.ndarray,
                    inner: np.ndarray, k: int, rounds: int
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                               np.ndarray]:  # pragma: no cover - compiled
    """Two-means in one dimension for each of ``k`` groups of weighted offsets (``owner``
    names each offset's group; ``inner``: each item's own scatter across, added to its side's
    variance): split at the group's mean, then ``rounds`` times halfway between the sides'
    means. Returns each group's low and high side means, their RMS spreads, the share of the
    weight on the high side, and the share within a quarter of the gap of the split."""
    n = len(owner)
    total = np.zeros(k)
    split = np.zeros(k)
    for i in range(n):
        total[owner[i]] += weight[i]
        split[owner[i]] += weight[i] * offset[i]
    for g in range(k):
        total[g] = max(total[g], 1e-300)
        split[g] /= total[g]
    mean = np.zeros((2, k))
    spread = np.zeros((2, k))
    side_weight = np.zeros((2, k))
    for _ in range(rounds + 1):
        mean[:] = 0.0
        spread[:] = 0.0
        side_weight[:] = 0.0
        for i in range(n):
            s = 1 if offset[i] > split[owner[i]] else 0
            side_weight[s, owner[i]] += weight[i]
            mean[s, owner[i]] += weight[i] * offset[i]
        for s in range(2):
            for g in range(k):
                side_weight[s, g] = max(side_weight[s, g], 1e-300)
                mean[s, g] /= side_weight[s, g]
        for i in range(n):
            s = 1 if offset[i] > split[owner[i]] else 0
            d = offset[i] - mean[s, owner[i]]
            spread[s, owner[i]] += weight[i] * (d * d) + inner[i]
        for s in range(2):
            for g in range(k):
                spread[s, g] = math.sqrt(max(spread[s, g] / side_weight[s, g], 0.0))
        for g in range(k):
            split[g] = 0.5 * (mean[0, g] + mean[1, g])
    middle = np.zeros(k)
    for i in range(n):
        g = owner[i]
        if abs(offset[i] - split[g]) < 0.25 * (mean[1, g] - mean[0, g]):
            middle[g] += weight[i]
    return (mean[0], mean[1], spread[0], spread[1], side_weight[1] / total, middle / total)


@njit(cache=True, nogil=True)
def neighbourhood_sums(owner: np.ndarray, atom: np.ndarray, centres: np.ndarray,
                       xy: np.ndarray, weight: np.ndarray, scatter: np.ndarray, k: int
                       ) -> np.ndarray:  # pragma: no cover - compiled
    """Weighted sums over each of ``k`` neighbourhoods of its atoms (the pairs ``owner[i]``,
    ``atom[i]``), about its centre: weight, first moments (x, y) and second moments (xx, xy,
    yy, each with the atoms' own scatter added). Returns a (k, 6) array, summed in the pairs'
    order."""
    out = np.zeros((k, 6))
    for i in range(len(owner)):
        o, a = owner[i], atom[i]
        w = weight[a]
        lx = xy[a, 0] - centres[o, 0]
        ly = xy[a, 1] - centres[o, 1]
        out[o, 0] += w
        out[o, 1] += w * lx
        out[o, 2] += w * ly
        out[o, 3] += w * (lx * lx) + scatter[a, 0]
        out[o, 4] += w * lx * ly + scatter[a, 1]
        out[o, 5] += w * (ly * ly) + scatter[a, 2]
    return out
