"""The layer model's 3D error: how far each cloud point is from the surface of the stacked layers.

Each layer is a solid: the region of its closed contours (holes by the even-odd rule) extruded
from its bottom to its top; open contours stand for walls of no thickness. The surface of the
stack is made of each layer's side walls and of the parts of its top and bottom faces that the
next layer does not cover (the symmetric difference of the two regions): the stair steps. A
point of a layer's slab is measured against the walls and exposed faces of its own layer and
of the layers just below and above, and, where its error reaches past them (thinner
neighbours, or a point inside a solid far from any wall), of the layers farther out until
their height alone puts them beyond it: the distance to the surface of the whole stack.
This is the staircase error that adaptive slicing keeps within ε.

References
----------
.. [1] Y. F. Wu, Y. S. Wong, H. T. Loh and Y. F. Zhang, "Modelling cloud data using an
   adaptive slicing approach", Computer-Aided Design 36(3), 2004, pp. 231-240.
"""

from __future__ import annotations

import numpy as np
import shapely

from .geometry import polyline_segments, segments_distance
from .types import Contour, FloatArray

EMPTY = shapely.GeometryCollection()


def region(contours: list[Contour]) -> shapely.Geometry:
    """The area of a layer's closed contours, holes by the even-odd rule (empty if none)."""
    rings = [shapely.polygons(c.vertices) for c in contours if c.closed and len(c.vertices) >= 3]
    out = EMPTY
    for ring in rings:
        out = shapely.symmetric_difference(out, ring)
    return out


def walls(contours: list[Contour]) -> shapely.Geometry:
    """The lines of a layer's contours (its side walls seen from above)."""
    lines = [shapely.linearrings(c.vertices) if c.closed and len(c.vertices) >= 3
             else shapely.linestrings(c.vertices) for c in contours if len(c.vertices) >= 2]
    return shapely.union_all(lines) if lines else EMPTY


def _to(geom: shapely.Geometry, xy: FloatArray, limit: FloatArray | None = None
        ) -> FloatArray:
    """In-plane distance of each point to an area or lines (0 inside an area; inf if empty):
    the distance to the nearest of its boundary's or lines' segments (a KD-tree search,
    `wavepoly.geometry.segments_distance`), 0 where an area contains the point. With a
    ``limit``, distances at or beyond it are only known to be so."""
    if shapely.is_empty(geom):
        return np.full(len(xy), np.inf)
    pieces = [polyline_segments(v, closed) for v, closed in _polylines(geom)]
    if not pieces:
        return np.full(len(xy), np.inf)
    out = segments_distance(xy, np.vstack([p[0] for p in pieces]),
                            np.vstack([p[1] for p in pieces]), limit=limit)
    if shapely.area(geom) > 0:
        out[shapely.contains_xy(geom, xy[:, 0], xy[:, 1])] = 0.0
    return out


def _polylines(geom: shapely.Geometry) -> list[tuple[FloatArray, bool]]:
    """The boundary rings of a geometry's areas and its lines, as (vertices, closed)."""
    out = []
    for part in shapely.get_parts(geom):
        if isinstance(part, shapely.Polygon):
            rings = [part.exterior, *part.interiors]
        elif isinstance(part, shapely.LineString | shapely.LinearRing):
            rings = [part]
        else:
            continue
        for ring in rings:
            xy = shapely.get_coordinates(ring)
            closed = len(xy) > 2 and bool(np.all(xy[0] == xy[-1]))
            xy = xy[:-1] if closed else xy
            if len(xy):
                out.append((xy, closed))
    return out


def outside_distances(xy: FloatArray, contours: list[Contour]) -> FloatArray:
    """In-plane distance of each point to the region of ``contours`` (0 inside; inf if the
    contours bound no region)."""
    area = region(contours)
    if shapely.is_empty(area) or shapely.area(area) == 0:
        return np.full(len(xy), np.inf)
    return _to(area, xy)


#: A layer farther out: (bottom, top, contours), or contours None for the end of the stack.
Farther = tuple[float, float, "list[Contour] | None"]


def slab_errors(uvh: FloatArray, bottom: float, top: float, contours: list[Contour],
                below: list[Contour] | None, above: list[Contour] | None,
                farther_below: tuple[Farther, ...] = (),
                farther_above: tuple[Farther, ...] = ()) -> FloatArray:
    """Distance of each slab point (u, v, height) to the surface of the layer stack near it.

    ``below`` / ``above`` are the contours of the neighbouring layers (None: no layer there,
    so the whole face is exposed); ``farther_below`` / ``farther_above`` the layers beyond
    them, outward, ending with ``(height, height, None)`` where the stack ends.
    """
    def faces(cs):
        return None if cs is None else _Faces(region(cs), walls(cs))

    def far(layers):
        return tuple((b, t, faces(cs)) for b, t, cs in layers)

    return _slab_errors(uvh, bottom, top, faces(contours), faces(below), faces(above),
                        far(farther_below), far(farther_above))


class _Faces:
    """A layer's area and wall lines, made once for its own slab and its neighbours'."""

    def __init__(self, area: shapely.Geometry, lines: shapely.Geometry):
        self.area, self.lines = area, lines


def _slab_errors(uvh: FloatArray, bottom: float, top: float, own: _Faces,
                 below: _Faces | None, above: _Faces | None, farther_below: tuple = (),
                 farther_above: tuple = ()) -> FloatArray:
    if not len(uvh):
        return np.empty(0)
    xy, h = uvh[:, :2], uvh[:, 2]
    err = _to(own.lines, xy)
    for other, dz in ((above, top - h), (below, h - bottom)):
        exposed = own.area if other is None else shapely.symmetric_difference(own.area,
                                                                              other.area)
        _lower(err, dz, exposed, xy)
        if other is not None:  # the neighbour's own walls, one face away
            _lower(err, dz, other.lines, xy)
    for near, layers, sign in ((above, farther_above, 1.0), (below, farther_below, -1.0)):
        for b, t, faces in layers:  # outward: the face between near and it, then its walls
            if near is None:
                break
            dz = sign * ((b if sign > 0 else t) - h)
            _lower(err, dz, near.area if faces is None else
                   shapely.symmetric_difference(near.area, faces.area), xy)
            if faces is not None:
                _lower(err, dz, faces.lines, xy)
            near = faces
    return err


def farther_layers(k: int, reach: float, bottoms: FloatArray, tops: FloatArray,
                   contours: list) -> tuple[tuple[Farther, ...], tuple[Farther, ...]]:
    """The layers beyond layer ``k``'s neighbours whose faces come within ``reach`` of its slab
    in height, below and above (outward), each side ending with the end of the stack when it
    is within reach: what its points must be measured against for errors up to ``reach``
    (none for an infinite one: a layer with points and nothing to measure them against)."""
    if not np.isfinite(reach):
        return (), ()
    n = len(bottoms)
    above: list[Farther] = []
    for j in range(k + 2, n + 1) if k + 1 < n else ():
        if j == n:
            if tops[n - 1] - tops[k] < reach:
                above.append((float(tops[n - 1]), float(tops[n - 1]), None))
            break
        if bottoms[j] - tops[k] >= reach:
            break
        above.append((float(bottoms[j]), float(tops[j]), contours[j]))
    below: list[Farther] = []
    for j in range(k - 2, -2, -1) if k >= 1 else ():
        if j == -1:
            if bottoms[k] - bottoms[0] < reach:
                below.append((float(bottoms[0]), float(bottoms[0]), None))
            break
        if bottoms[k] - tops[j] >= reach:
            break
        below.append((float(bottoms[j]), float(tops[j]), contours[j]))
    return tuple(below), tuple(above)


def _lower(err: FloatArray, dz: FloatArray, geom: shapely.Geometry, xy: FloatArray) -> None:
    """``err`` lowered in place to the distance to ``geom`` across a face ``dz`` away, where
    that is nearer. Only the points it can lower are measured, each only as far as it can."""
    limit = np.sqrt(np.maximum(err**2 - dz**2, 0.0))
    need = np.flatnonzero(limit > 0)
    if len(need):
        d = np.hypot(dz[need], _to(geom, xy[need], limit[need]))
        err[need] = np.minimum(err[need], d)


def layer_errors(uvh: FloatArray, bottoms: FloatArray, tops: FloatArray,
                 contours: list[list[Contour]]) -> list[float]:
    """The largest staircase error of each layer's slab (``uvh`` sorted by height); inf for a
    layer with points and no contour, 0 for one without points."""
    faces = [_Faces(region(cs), walls(cs)) for cs in contours]
    out = []
    for k, (b, t) in enumerate(zip(bottoms, tops)):
        s0, s1 = np.searchsorted(uvh[:, 2], [b, t])
        if s1 <= s0:
            out.append(0.0)
            continue
        below = faces[k - 1] if k > 0 else None
        above = faces[k + 1] if k + 1 < len(faces) else None
        err = float(_slab_errors(uvh[s0:s1], b, t, faces[k], below, above).max())
        far_below, far_above = farther_layers(k, err, bottoms, tops, faces)
        if far_below or far_above:  # the error reaches past the neighbours
            err = float(_slab_errors(uvh[s0:s1], b, t, faces[k], below, above, far_below,
                                     far_above).max())
        out.append(err)
    return out
