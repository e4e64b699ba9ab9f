"""Vectorized planar geometry: point-to-segment distances and contour nesting."""

from __future__ import annotations

import numpy as np
import shapely

from .types import Contour, FloatArray, IntArray


def segment_distance(points: FloatArray, a: FloatArray, b: FloatArray) -> FloatArray:
    """Distance of each point to the segment from ``a`` to ``b`` (row-wise, broadcasting).

    >>> segment_distance(np.array([[0.5, 1.0]]), np.array([0.0, 0.0]), np.array([1.0, 0.0]))
    array([1.])
    """
    ab = b - a
    ap = points - a
    denom = np.einsum("...i,...i->...", ab, ab)
    t = np.einsum("...i,...i->...", ap, ab) / np.where(denom > 0, denom, 1.0)
    t = np.clip(t, 0.0, 1.0)
    diff = ap - t[..., None] * ab
    return np.sqrt(np.einsum("...i,...i->...", diff, diff))


def polyline_segments(vertices: FloatArray, closed: bool) -> tuple[FloatArray, FloatArray]:
    """Start and end points of each segment of a polyline (closed: last to first too)."""
    if closed:
        return vertices, np.roll(vertices, -1, axis=0)
    return vertices[:-1], vertices[1:]


def nearest_segment(points: FloatArray, vertices: FloatArray, closed: bool
                    ) -> tuple[IntArray, FloatArray]:
    """Index of the nearest segment of a polyline for each point, and the distance to it.

    Segment i runs from vertex i to vertex i+1 (wrapping when ``closed``). Uses a shapely
    STRtree, so it is O((n + m) log m) for n points and m segments.
    """
    a, b = polyline_segments(vertices, closed)
    segs = shapely.linestrings(np.stack([a, b], axis=1))
    tree = shapely.STRtree(segs)
    (pidx, sidx), dist = tree.query_nearest(shapely.points(points), return_distance=True,
                                            all_matches=False)
    order = np.argsort(pidx, kind="stable")
    return sidx[order].astype(np.intp), dist[order]


def contour_geometry(contour: Contour) -> shapely.Geometry:
    """The contour as a shapely LinearRing boundary (closed) or LineString (open)."""
    v = contour.vertices
    if contour.closed and len(v) >= 3:
        return shapely.linearrings(v)
    return shapely.linestrings(v) if len(v) >= 2 else shapely.points(v[0])


def distance_to_contours(points: FloatArray, contours: list[Contour]) -> FloatArray:
    """Distance of each point to the nearest of ``contours`` (their boundaries, not interiors)."""
    if not contours:
        return np.full(len(points), np.inf)
    geoms = [contour_geometry(c) for c in contours]
    tree = shapely.STRtree(geoms)
    (pidx, _), dist = tree.query_nearest(shapely.points(points[:, :2]), return_distance=True,
                                         all_matches=False)
    out = np.full(len(points), np.inf)
    np.minimum.at(out, pidx, dist)
    return out


def nest_contours(contours: list[Contour]) -> list[int]:
    """For each contour, the index of the smallest closed contour that contains it, or -1.

    Containment is tested with a representative vertex, so contours must not cross.
    """
    closed = [i for i, c in enumerate(contours) if c.closed and len(c.vertices) >= 3]
    parents = [-1] * len(contours)
    if not closed:
        return parents
    polys = [shapely.polygons(contours[i].vertices) for i in closed]
    areas = shapely.area(polys)
    tree = shapely.STRtree(polys)
    probes = shapely.points(np.array([c.vertices[0] for c in contours]))
    inside, poly_idx = tree.query(probes, predicate="within")
    for k, p in zip(inside, poly_idx):
        j = closed[p]
        if j != k and (parents[k] < 0 or areas[p] < areas[closed.index(parents[k])]):
            parents[k] = j
    return parents


def nesting_depth(parents: list[int]) -> list[int]:
    """Number of enclosing closed contours of each contour (even: outer or island, odd: hole)."""
    depth = []
    for i in range(len(parents)):
        d, p = 0, parents[i]
        while p >= 0:
            d, p = d + 1, parents[p]
        depth.append(d)
    return depth


def orient_by_depth(contours: list[Contour], parents: list[int]) -> list[Contour]:
    """Make outer closed contours counter-clockwise and holes clockwise (open ones unchanged)."""
    out = []
    for c, d in zip(contours, nesting_depth(parents)):
        want_ccw = d % 2 == 0
        if c.closed and (c.signed_area > 0) != want_ccw:
            c = Contour(c.vertices[::-1].copy(), c.closed, c.max_error, c.mean_error)
        out.append(c)
    return out
