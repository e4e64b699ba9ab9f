"""Validity of a result's geometry, checked like the tolerance: what a CAD tool, a slicer or a GIS
would reject.

A result is valid when every closed contour is a simple polygon (GEOS ``is_valid``), every
open contour is simple (``is_simple``), no two contours cross, closed contours do not touch one
another, and open contours meet others only at their own end points (a junction of strokes).
Holes then lie inside their parents and outer contours outside each other, since closed
contours neither cross nor touch.

`segment_hits` is the primitive that the fewest-vertex selection uses to keep its chords from
crossing other edges (valid by construction); `check_contours` is the final, independent check.
"""

from __future__ import annotations

import numpy as np
import shapely

from .types import Contour, FloatArray, IntArray, Problem, Validity

#: Two end points closer than this (relative to the extent of the geometry) are one point:
#: a junction of open strokes, not a crossing.
JUNCTION_SLACK = 1e-9


def segment_hits(starts: FloatArray, ends: FloatArray, tree: shapely.STRtree
                 ) -> tuple[IntArray, IntArray]:
    """Pairs (i, j): segment ``starts[i] -> ends[i]`` meets the ``j``-th geometry of ``tree``.

    Meeting includes touching; callers exclude the pairs that share an end point on purpose
    (the neighbouring edges of a chord).
    """
    if not len(starts):
        return np.empty(0, np.intp), np.empty(0, np.intp)
    chords = shapely.linestrings(np.stack([starts, ends], axis=1))
    i, j = tree.query(chords, predicate="intersects")
    return i.astype(np.intp), j.astype(np.intp)


def contour_segments(contour: Contour) -> tuple[FloatArray, FloatArray]:
    """Start and end points of every edge of a contour (a closed one includes the last edge)."""
    v = contour.vertices
    if contour.closed and len(v) >= 3:
        return v, np.roll(v, -1, axis=0)
    return v[:-1], v[1:]


def _geometry(contour: Contour) -> shapely.Geometry:
    v = contour.vertices
    if contour.closed:
        return shapely.polygons(v) if len(v) >= 3 else shapely.linestrings(np.vstack([v, v]))
    return shapely.linestrings(v) if len(v) >= 2 else shapely.points(v[0])


def _where(geom: shapely.Geometry) -> tuple[float, float]:
    point = shapely.get_coordinates(shapely.point_on_surface(geom))
    return (float(point[0, 0]), float(point[0, 1])) if len(point) else (np.nan, np.nan)


def _own_problems(k: int, contour: Contour) -> list[Problem]:
    """A closed contour that is not a valid polygon, or an open one that is not simple."""
    geom = _geometry(contour)
    if contour.closed:
        if len(contour.vertices) < 3:
            return [Problem("degenerate polygon", (k,), _where(geom))]
        if not shapely.is_valid(geom):
            reason = shapely.is_valid_reason(geom)
            where = _reason_point(reason) or _where(geom)
            return [Problem("self-intersection", (k,), where)]
        if shapely.area(geom) <= 0.0:
            return [Problem("degenerate polygon", (k,), _where(geom))]
        return []
    if shapely.is_simple(geom):
        return []
    noded = shapely.node(geom)
    ends = shapely.get_coordinates(shapely.boundary(shapely.get_parts(noded)))
    uniq, counts = np.unique(np.round(ends, 12), axis=0, return_counts=True)
    multiple = uniq[counts > 2] if (counts > 2).any() else uniq[:1]
    return [Problem("self-intersection", (k,), (float(multiple[0, 0]), float(multiple[0, 1])))]


def _reason_point(reason: str) -> tuple[float, float] | None:
    if "[" not in reason:
        return None
    try:
        x, y = reason[reason.index("[") + 1:reason.index("]")].split()[:2]
        return float(x), float(y)
    except ValueError:
        return None


def _pair_problem(i: int, j: int, a: Contour, b: Contour, scale: float) -> Problem | None:
    """How contours ``a`` and ``b`` meet, if they may not: closed ones must not meet at all,
    open ones only at their own end points."""
    ga = shapely.linearrings(a.vertices) if a.closed and len(a.vertices) >= 3 else _geometry(a)
    gb = shapely.linearrings(b.vertices) if b.closed and len(b.vertices) >= 3 else _geometry(b)
    meet = shapely.intersection(ga, gb)
    if shapely.is_empty(meet):
        return None
    ends = [c.vertices[[0, -1]] for c in (a, b) if not c.closed]
    if ends:
        allowed = shapely.buffer(shapely.multipoints(np.concatenate(ends)),
                                 JUNCTION_SLACK * scale)
        rest = shapely.difference(meet, allowed)
        if shapely.is_empty(rest):
            return None
        meet = rest
    kind = "touching" if a.closed and b.closed and not shapely.crosses(ga, gb) else "crossing"
    return Problem(kind, (i, j), _where(meet))


def check_contours(contours: list[Contour]) -> Validity:
    """Check every rule of a valid result (see the module docstring); return what breaks."""
    problems: list[Problem] = []
    for k, c in enumerate(contours):
        problems += _own_problems(k, c)
    if len(contours) >= 2:
        lines = [_geometry(c) if not c.closed else shapely.linearrings(c.vertices)
                 if len(c.vertices) >= 3 else _geometry(c) for c in contours]
        scale = max(float(np.ptp(np.concatenate([c.vertices for c in contours]), axis=0).max()),
                    1e-300)
        tree = shapely.STRtree(lines)
        left, right = tree.query(lines, predicate="intersects")
        for i, j in zip(left, right):
            if i < j:
                problem = _pair_problem(int(i), int(j), contours[i], contours[j], scale)
                if problem is not None:
                    problems.append(problem)
    n_closed = sum(c.closed for c in contours)
    return Validity(n_closed, len(contours) - n_closed, tuple(problems))


#: Ends of a chord at an open contour's own end points are pulled in by this fraction of its
#: length before it is tested, so that a stroke may end on another (a junction).
END_PULL = 1e-9


def bad_edges(vertices: FloatArray, closed: bool, obstacles: shapely.STRtree | None = None
              ) -> np.ndarray:
    """Which edges of a polygon (closed) or polyline (open) break validity.

    An edge is bad when it meets a non-adjacent edge of the same contour, folds back onto its
    neighbour, or meets any edge of ``obstacles`` (the contours already fixed nearby). The ends
    of an open contour may touch obstacles (a junction).
    """
    m = len(vertices) if closed else len(vertices) - 1
    bad = np.zeros(max(m, 0), dtype=bool)
    if m < 1:
        return bad
    a = vertices
    b = np.roll(vertices, -1, axis=0)[:m] if closed else vertices[1:]
    a = a[:m]
    bad |= _folds(a, b, closed)
    if m >= 3 or (not closed and m >= 2):
        tree = shapely.STRtree(shapely.linestrings(np.stack([a, b], axis=1)))
        i, j = segment_hits(a, b, tree)
        adjacent = (np.abs(i - j) <= 1) | (closed & (np.abs(i - j) == m - 1))
        cross = (i != j) & ~adjacent
        bad[i[cross]] = True
    if obstacles is not None:
        bad |= obstacle_hits(vertices, closed, obstacles)
    return bad


def obstacle_hits(vertices: FloatArray, closed: bool, obstacles: shapely.STRtree
                  ) -> np.ndarray:
    """Which edges of a polygon (closed) or polyline (open) meet an edge of ``obstacles``; the
    ends of an open contour may touch them (a junction)."""
    m = len(vertices) if closed else len(vertices) - 1
    hit = np.zeros(max(m, 0), dtype=bool)
    if m < 1:
        return hit
    a, b = vertices[:m].copy(), np.roll(vertices, -1, axis=0)[:m].copy()
    if not closed:  # a stroke may end on another contour
        a[0] += END_PULL * (b[0] - a[0])
        b[-1] += END_PULL * (a[-1] - b[-1])
    hit[segment_hits(a, b, obstacles)[0]] = True
    return hit


def _folds(a: FloatArray, b: FloatArray, closed: bool) -> np.ndarray:
    """Edges that turn straight back along the previous edge (an overlap, not a corner)."""
    d = b - a
    prev = np.roll(d, 1, axis=0)
    cross = prev[:, 0] * d[:, 1] - prev[:, 1] * d[:, 0]
    dot = np.einsum("ij,ij->i", prev, d)
    scale = np.linalg.norm(prev, axis=1) * np.linalg.norm(d, axis=1)
    fold = (dot < 0) & (np.abs(cross) <= 1e-12 * np.maximum(scale, 1e-300))
    if not closed:
        fold[0] = False
    return fold | np.roll(fold, -1)  # the edge and the one before it


def without_repeats(vertices: FloatArray, closed: bool) -> FloatArray:
    """The same polyline without vertices that repeat the one before them (zero-length edges
    hide folds from the checks and mean nothing to a CAD tool), nor an open end that runs
    straight back over the edge before it."""
    v = vertices
    if len(v) < 2:
        return v
    eps = REPEAT * max(float(np.abs(v).max()), float(np.ptp(v, axis=0).max()), 1e-300)
    same = np.all(np.abs(v[1:] - v[:-1]) <= eps, axis=1)
    v = v[np.concatenate([[True], ~same])]
    if closed and len(v) > 1 and np.all(np.abs(v[0] - v[-1]) <= eps):
        v = v[:-1]
    while not closed and len(v) >= 3 and _retraces(v[-3], v[-2], v[-1], eps):
        v = v[:-1]
    while not closed and len(v) >= 3 and _retraces(v[2], v[1], v[0], eps):
        v = v[1:]
    return v


#: Vertices closer than this (relative to the coordinates' magnitude) are one: round-off.
REPEAT = 1e-12


def _retraces(a: FloatArray, b: FloatArray, c: FloatArray, eps: float) -> bool:
    """c lies on segment a-b (within ``eps``): the edge b -> c runs back over a -> b."""
    ab, bc = b - a, c - b
    cross = ab[0] * bc[1] - ab[1] * bc[0]
    length = float(np.hypot(*ab))
    return bool(abs(cross) <= eps * max(length, 1e-300) and ab @ bc < 0
                and bc @ bc <= ab @ ab + eps)


def obstacle_tree(contours: list[Contour]) -> shapely.STRtree | None:
    """An index of every edge of ``contours`` (None when there are none)."""
    segs = [np.stack(contour_segments(c), axis=1) for c in contours if len(c.vertices) >= 2]
    if not segs:
        return None
    return shapely.STRtree(shapely.linestrings(np.concatenate(segs)))


def split_at_crossings_of(lines: list[FloatArray], closed: list[bool], *,
                          between_only: bool = False) -> dict[int, list[FloatArray]]:
    """Polylines cut where they properly cross one another (or themselves): for each polyline
    that crosses, its open pieces, each ending on a crossing point (or on its own ends).

    The crossing point becomes a vertex of every polyline through it, so the pieces meet only
    at their end points (a junction) and draw exactly the same lines. ``between_only`` leaves
    a polyline's meetings with itself alone.
    """
    cuts = _crossing_cuts(lines, closed, between_only)
    return {k: _pieces(lines[k], closed[k], c) for k, c in cuts.items()}


def _crossing_cuts(chains: list[FloatArray], closed: list[bool], between_only: bool = False
                   ) -> dict[int, list[tuple[int, float, FloatArray]]]:
    """For each chain that meets another (or itself) other than at an open end: (edge,
    position along it, meeting point) of each meeting; a position of 0 or 1 is a vertex."""
    a, b, owner, edge, m_of = [], [], [], [], []
    for k, (xy, c) in enumerate(zip(chains, closed)):
        m = len(xy) if c and len(xy) >= 3 else len(xy) - 1
        m_of.append(max(m, 0))
        if m < 1:
            continue
        a.append(xy[:m])
        b.append(np.roll(xy, -1, axis=0)[:m] if c and len(xy) >= 3 else xy[1:])
        owner.append(np.full(m, k))
        edge.append(np.arange(m))
    if not a:
        return {}
    a, b = np.concatenate(a), np.concatenate(b)
    owner, edge = np.concatenate(owner), np.concatenate(edge)
    segs = shapely.linestrings(np.stack([a, b], axis=1))
    i, j = shapely.STRtree(segs).query(segs, predicate="intersects")
    same = owner[i] == owner[j]
    gap = np.abs(edge[i] - edge[j])
    adjacent = same & ((gap <= 1) | (gap == np.asarray(m_of)[owner[i]] - 1))
    keep = (i < j) & ~adjacent & ~(same & between_only)
    ends = np.concatenate([chains[k][[0, -1]] for k in range(len(chains)) if not closed[k]]
                          ) if not all(closed) else np.empty((0, 2))
    cuts: dict[int, list[tuple[int, float, FloatArray]]] = {}
    for s, t in zip(i[keep], j[keep]):
        x = _line_crossing(a[s], b[s], a[t], b[t])
        if x is None or (len(ends) and np.any(np.all(ends == x, axis=1))):
            continue  # a collinear overlap (no one point), or a stroke ending on a line
        for seg in (s, t):
            d = b[seg] - a[seg]
            pos = float(np.clip((x - a[seg]) @ d / max(float(d @ d), 1e-300), 0.0, 1.0))
            if np.all(x == a[seg]):
                pos = 0.0
            elif np.all(x == b[seg]):
                pos = 1.0
            cuts.setdefault(int(owner[seg]), []).append((int(edge[seg]), pos, x))
    return cuts


def noded_pieces(lines: list[FloatArray], closed: list[bool]) -> list[FloatArray]:
    """The linework of ``lines`` cut wherever two of its edges meet, a stretch drawn twice
    (an edge folding back over another, which `split_at_crossings_of` cannot cut at one
    point) drawn once, then joined again through every point where only two pieces meet.

    The pieces draw the same point set, so every point keeps its distance to them; they
    meet only at their end points, and each is simple (one whose ends meet is a loop).
    """
    geoms = [shapely.linestrings(np.vstack([xy, xy[:1]]) if c and len(xy) >= 3 else xy)
             for xy, c in zip(lines, closed) if len(xy) >= 2]
    merged = shapely.line_merge(shapely.unary_union(geoms))
    pieces = [without_repeats(shapely.get_coordinates(g), False)
              for g in shapely.get_parts(merged)]
    return [p for p in pieces if len(p) >= 2]


def _line_crossing(a0: FloatArray, a1: FloatArray, b0: FloatArray, b1: FloatArray
                   ) -> FloatArray | None:
    """Where two segments that meet do so: a shared end point exactly, else the crossing of
    their lines; None when they are parallel (an overlap)."""
    for p in (a0, a1):
        if np.all(p == b0) or np.all(p == b1):
            return p.copy()
    da, db = a1 - a0, b1 - b0
    cross = da[0] * db[1] - da[1] * db[0]
    if cross == 0:
        return None
    ta = ((b0 - a0)[0] * db[1] - (b0 - a0)[1] * db[0]) / cross
    tb = ((b0 - a0)[0] * da[1] - (b0 - a0)[1] * da[0]) / cross
    for t, p0, p1 in ((ta, a0, a1), (tb, b0, b1)):  # a vertex on the other's edge: itself
        if t <= 0.0:
            return p0.copy()
        if t >= 1.0:
            return p1.copy()
    return a0 + ta * da


def _pieces(xy: FloatArray, closed: bool, cuts: list[tuple[int, float, FloatArray]]
            ) -> list[FloatArray]:
    """The chain cut at its meeting points: each piece starts and ends on one (or on the
    chain's own ends). A meeting at a vertex cuts there; one inside an edge is inserted."""
    n = len(xy)
    at_vertex = {(e + int(pos >= 1.0)) % n for e, pos, _ in cuts if pos <= 0.0 or pos >= 1.0}
    inside = sorted((c for c in cuts if 0.0 < c[1] < 1.0), key=lambda c: (c[0], c[1]))
    verts, at = [], []
    c = 0
    for e in range(n):
        if e in at_vertex:
            at.append(len(verts))
        verts.append(xy[e])
        while c < len(inside) and inside[c][0] == e:
            at.append(len(verts))
            verts.append(inside[c][2])
            c += 1
    line = np.asarray(verts)
    if closed:  # start at the first cut, go round to it again
        line = np.vstack([line[at[0]:], line[:at[0] + 1]])
        bounds = [p - at[0] for p in at] + [len(line) - 1]
    else:
        bounds = sorted({0, *at, len(line) - 1})
    pieces = [without_repeats(line[s:e + 1], False) for s, e in zip(bounds[:-1], bounds[1:])]
    return [p for p in pieces if len(p) >= 2]  # a piece of one point (round-off) is no line
