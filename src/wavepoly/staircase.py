"""The layer model's 3D error: how far each cloud point is from the surface of the stacked layers.

Each layer is a solid: the region of its closed contours (holes by the even-odd rule) extruded
from its bottom to its top; open contours stand for walls of no thickness. The surface of the
stack is made of each layer's side walls and of the parts of its top and bottom faces that the
next layer does not cover (the symmetric difference of the two regions): the stair steps. A
point of a layer's slab is measured against the walls and exposed faces of its own layer and
of the layers just below and above, which hold the nearest surface whenever the error is below
a layer's thickness. This is the staircase error that adaptive slicing keeps within ε.

References
----------
.. [1] Y. F. Wu, Y. S. Wong, H. T. Loh and Y. F. Zhang, "Modelling cloud data using an
   adaptive slicing approach", Computer-Aided Design 36(3), 2004, pp. 231-240.
"""

from __future__ import annotations

import numpy as np
import shapely

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


def _to(geom: shapely.Geometry, xy: FloatArray) -> FloatArray:
    """In-plane distance of each point to an area or lines (0 inside an area; inf if empty)."""
    if shapely.is_empty(geom):
        return np.full(len(xy), np.inf)
    return shapely.distance(shapely.points(xy), geom)


def slab_errors(uvh: FloatArray, bottom: float, top: float, contours: list[Contour],
                below: list[Contour] | None, above: list[Contour] | None) -> FloatArray:
    """Distance of each slab point (u, v, height) to the surface of the layer stack near it.

    ``below`` / ``above`` are the contours of the neighbouring layers (None: no layer there,
    so the whole face is exposed).
    """
    def faces(cs):
        return None if cs is None else _Faces(region(cs), walls(cs))

    return _slab_errors(uvh, bottom, top, faces(contours), faces(below), faces(above))


class _Faces:
    """A layer's area and wall lines, made once for its own slab and its neighbours'."""

    def __init__(self, area: shapely.Geometry, lines: shapely.Geometry):
        self.area, self.lines = area, lines


def _slab_errors(uvh: FloatArray, bottom: float, top: float, own: _Faces,
                 below: _Faces | None, above: _Faces | None) -> FloatArray:
    if not len(uvh):
        return np.empty(0)
    xy, h = uvh[:, :2], uvh[:, 2]
    err = _to(own.lines, xy)
    for other, dz in ((above, top - h), (below, h - bottom)):
        exposed = own.area if other is None else shapely.symmetric_difference(own.area,
                                                                              other.area)
        np.minimum(err, np.hypot(dz, _to(exposed, xy)), out=err)
        if other is not None:  # the neighbour's own walls, one face away
            np.minimum(err, np.hypot(dz, _to(other.lines, xy)), out=err)
    return err


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
        out.append(float(_slab_errors(uvh[s0:s1], b, t, faces[k], below, above).max()))
    return out
