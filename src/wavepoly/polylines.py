"""Known polylines (a mesh's exact sections) to the fewest vertices within the tolerance.

When the curves are already ordered and exact, there is nothing to order or denoise: each
polyline's own vertices are the candidates, points sampled along it every tolerance / 4 are
what must stay within the tolerance, and the fewest-vertex selection (`wavepoly.simplify`)
picks the polygon, valid by construction against the polylines already fixed.
"""

from __future__ import annotations

import numpy as np
import shapely

from .geometry import nest_contours, orient_by_depth, polyline_distance, polyline_length
from .simplify import select_vertices
from .types import SLACK, Contour, FitResult, FloatArray
from .validate import check_tolerance
from .validity import check_contours, obstacle_tree, without_repeats

#: Samples per tolerance along each polyline: every point of the curve between two samples is
#: within a quarter tolerance of one, which the chord test then covers.
SAMPLES_PER_TOLERANCE = 4
#: A closed section's vertices are chosen within this share of the tolerance, and then moved
#: along their normals, by up to the rest, so that the polygon keeps the section's area
#: (`_area_kept`): a parabolic sag s takes 2/3 s of area along the chord, so 0.6 leaves room
#: for the 0.4 that balances it.
AREA_SHARE = 0.6
#: Two edge normals that (nearly) cancel mark a vertex where the outline doubles back: no
#: direction to move it in.
MIN_BISECTOR = 1e-6


def fit_polylines(polylines: list[tuple[FloatArray, bool]], tolerance: float,
                  z: float | None = None) -> FitResult:
    """The fewest-vertex polygons within ``tolerance`` of exact ``(vertices, closed)`` curves.

    Longer polylines are simplified first; each later one keeps clear of those before it.
    """
    tolerance = check_tolerance(tolerance)
    curves = [(without_repeats(np.asarray(xy, float), c), c) for xy, c in polylines]
    curves = [(xy, c and len(xy) >= 3) for xy, c in curves if len(xy) >= 2]
    contours: list[Contour | None] = [None] * len(curves)
    lengths = [polyline_length(xy, c) for xy, c in curves]
    for k in np.argsort(lengths)[::-1]:
        xy, closed = curves[k]
        fixed = [c for c in contours if c is not None]
        contours[k] = _simplify(xy, closed, tolerance, obstacle_tree(fixed))
    validity = check_contours(contours)
    parents = nest_contours(contours)
    contours = orient_by_depth(contours, parents)
    err = max((c.max_error for c in contours), default=0.0)
    n = sum(len(xy) for xy, _ in curves)
    return FitResult(contours, tolerance, err, float(np.mean([c.mean_error for c in contours]))
                     if contours else 0.0, np.empty(0, np.intp), n, parents, z=z,
                     validity=validity)


def _simplify(xy: FloatArray, closed: bool, tolerance: float, obstacles) -> Contour:
    points, s, vparams = _samples(xy, closed, tolerance)
    verts = None
    if closed:  # a tighter choice leaves room to move the vertices so that the area is kept
        verts, _ = select_vertices(xy, vparams, points, s, closed, AREA_SHARE * tolerance,
                                   backbone=np.arange(len(xy)), obstacles=obstacles)
        verts = _area_kept(verts, xy, points, tolerance, obstacles)
    if verts is None:
        verts, _ = select_vertices(xy, vparams, points, s, closed, tolerance,
                                   backbone=np.arange(len(xy)), obstacles=obstacles)
    dist = polyline_distance(points, verts, closed and len(verts) >= 3)
    return Contour(verts, closed, float(dist.max(initial=0.0)), float(dist.mean()))


def _samples(xy: FloatArray, closed: bool, tolerance: float
             ) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Points every tolerance / `SAMPLES_PER_TOLERANCE` along a polyline, their parameters
    (arc length over the total) and the parameters of its vertices."""
    ring = np.vstack([xy, xy[:1]]) if closed else xy
    seg = np.linalg.norm(np.diff(ring, axis=0), axis=1)
    arc = np.concatenate([[0.0], np.cumsum(seg)])
    total = max(arc[-1], 1e-300)
    step = tolerance / SAMPLES_PER_TOLERANCE
    s = np.arange(0.0, arc[-1], step) if arc[-1] > step else arc[:1]
    points = np.column_stack([np.interp(s, arc, ring[:, 0]), np.interp(s, arc, ring[:, 1])])
    if not closed:
        points = np.vstack([points, xy[-1:]])
        s = np.append(s, arc[-1])
    return points, s / total, arc[:len(xy)] / total


def _area_kept(verts: FloatArray, section: FloatArray, points: FloatArray, tolerance: float,
               obstacles) -> FloatArray | None:
    """``verts`` (chosen within `AREA_SHARE` x tolerance of the section) moved along their
    normals by the one offset that gives the polygon the section's area, at most the rest of
    the tolerance; None when the moved polygon would be invalid, meet an obstacle or leave a
    sample beyond the tolerance.

    A fewest-vertex polygon with its vertices on the section cuts inside every convex stretch
    (a chord's sag), so a stack of such layers loses volume (a thin blade: 6 %). Each point of
    an edge moves by at most the offset, so the samples stay within the tolerance.
    """
    if len(verts) < 3:
        return None
    signed = Contour(verts, True).signed_area
    perimeter = polyline_length(verts, True)
    if signed == 0 or perimeter == 0:
        return None
    room = (1 - AREA_SHARE) * tolerance
    target = abs(Contour(section, True).signed_area)
    offset = float(np.clip((target - abs(signed)) / perimeter, -room, room))
    edge = np.roll(verts, -1, axis=0) - verts
    normal = np.column_stack([edge[:, 1], -edge[:, 0]]) * np.sign(signed)  # outward
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
    bisector = normal + np.roll(normal, 1, axis=0)  # of the edges before and after each vertex
    length = np.linalg.norm(bisector, axis=1, keepdims=True)
    if np.any(length < MIN_BISECTOR):  # a vertex where the outline turns back on itself
        return None
    moved = verts + offset * bisector / length
    polygon = shapely.Polygon(moved)
    if not shapely.is_valid(polygon):
        return None
    if obstacles is not None and len(obstacles.query(polygon.exterior, predicate="intersects")):
        return None
    if polyline_distance(points, moved, True).max() > tolerance * (1 + SLACK):
        return None
    return moved


def close_gaps(contours: list[Contour], max_gap: float) -> tuple[list[Contour], int]:
    """Open contours joined end to end across gaps of at most ``max_gap``, nearest ends
    first; a contour whose two ends meet becomes closed. A bridge that would cross or touch
    another contour is not made. Returns the contours and the number of bridges.

    A section of a closed surface is closed: its open pieces are where the scan left too few
    points (a sharp vertical edge, a surface nearly in the plane), and a layer must be closed
    to be printed. A bridge adds a straight edge where there were no points, so every point
    keeps its distance to the contours.
    """
    pieces = [c.vertices for c in contours if not c.closed]
    done = [c for c in contours if c.closed]
    bridges = 0
    while pieces:
        best = _nearest_ends(pieces, max_gap, done)
        if best is None:
            break
        i, end_i, j, end_j = best
        a = pieces[i] if end_i == 1 else pieces[i][::-1]  # a runs into the gap
        if i == j:
            done.append(Contour(a, True))
            pieces.pop(i)
        else:
            b = pieces[j] if end_j == 0 else pieces[j][::-1]  # b runs out of the gap
            pieces = [p for k, p in enumerate(pieces) if k not in (i, j)] + [np.vstack([a, b])]
        bridges += 1
    errors = {id(c.vertices): c for c in contours}
    out = [Contour(c.vertices, c.closed, c.max_error, c.mean_error) for c in done]
    out += [Contour(p, False, *(_errors(errors.get(id(p))))) for p in pieces]
    return out, bridges


def _errors(contour: Contour | None) -> tuple[float, float]:
    return (contour.max_error, contour.mean_error) if contour is not None else (0.0, 0.0)


def _nearest_ends(pieces: list[FloatArray], max_gap: float, fixed: list[Contour]
                  ) -> tuple[int, int, int, int] | None:
    """The closest pair of open ends within ``max_gap`` whose bridge meets no other line."""
    import shapely

    ends = np.array([p[[0, -1]] for p in pieces]).reshape(-1, 2)  # piece k: rows 2k, 2k + 1
    d = np.linalg.norm(ends[:, None] - ends[None], axis=2)
    np.fill_diagonal(d, np.inf)
    for k, p in enumerate(pieces):  # a piece closes on itself only with a real loop
        if len(p) < 3:
            d[2 * k, 2 * k + 1] = d[2 * k + 1, 2 * k] = np.inf
    lines = [shapely.linestrings(p) for p in pieces]
    lines += [shapely.linearrings(c.vertices) for c in fixed if len(c.vertices) >= 3]
    for flat in np.argsort(d, axis=None):
        r, s = np.unravel_index(flat, d.shape)
        if d[r, s] > max_gap:
            return None
        bridge = shapely.linestrings(ends[[r, s]])
        own = (r // 2, s // 2)
        if not any(shapely.crosses(bridge, g) or (k not in own and shapely.intersects(bridge, g))
                   for k, g in enumerate(lines)):
            return int(r // 2), int(r % 2), int(s // 2), int(s % 2)
    return None
