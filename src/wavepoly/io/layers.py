"""Layer-model writers: Common Layer Interface (.cli), SVG, GeoJSON and STL, written atomically.

Contours are written in the layers' plane coordinates (see `SliceResult.basis`); for slicing
along z these are the cloud's own x, y.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np

from ..errors import DataError, ParameterError
from ..geometry import nesting_depth
from ..types import SliceResult
from .atomic import atomic_path, write_lines_atomic, write_text_atomic
from .streams import is_stream, path_for_stream
from .units import unit_of
from .writers import check_valid, svg_document, write_geojson, write_gpkg

LAYER_FORMATS = ("cli", "svg", "geojson", "json", "stl", "gpkg")


def write_layers(path, result: SliceResult, format: str | None = None, *,
                 fmt: str | None = None, units: str | float = "unitless",
                 separate: bool = False, crs: str | None = None) -> None:
    """Write a layer model; the format comes from the extension (`LAYER_FORMATS`).

    ``path`` may be a file object, then ``format`` names the format. ``units`` is a unit's
    name (`wavepoly.io.units.UNITS`: the CLI header's $$UNITS in mm, the SVG's size) or the
    length of one coordinate unit in millimetres; ``separate`` writes an STL of one closed
    body per layer instead of their union.
    """
    fmt = fmt or format
    if is_stream(path):
        with path_for_stream(path, fmt) as tmp:
            write_layers(tmp, result, fmt=fmt, units=units, separate=separate, crs=crs)
        return
    fmt = (fmt or Path(path).suffix.lstrip(".")).lower()
    if crs is not None and fmt != "gpkg":
        raise ParameterError(f"{path}: a CRS is written to GeoPackage (.gpkg) only")
    named = isinstance(units, str)
    millimetres = unit_of(units).millimetres if named else float(units)
    if fmt in LAYER_FORMATS:
        check_valid(path, [la.fit for la in result.layers])
    if fmt == "cli":
        write_lines_atomic(path, cli_lines(result, units=millimetres))
    elif fmt == "svg":
        groups = [(f"layer-{k}-z{la.top:.6g}", la.fit.contours)
                  for k, la in enumerate(result.layers)]
        write_text_atomic(path, svg_document(groups, units=units if named else "unitless"))
    elif fmt in ("geojson", "json", "gpkg"):
        extras = [{"layer": k, "z": la.z, "bottom": la.bottom, "thickness": la.thickness}
                  for k, la in enumerate(result.layers)]
        if fmt == "gpkg":
            write_gpkg(path, [la.fit for la in result.layers], extras, crs=crs)
        else:
            write_geojson(path, [la.fit for la in result.layers], extras)
    elif fmt == "stl":
        mesh = layer_mesh(result, separate=separate)
        with atomic_path(path) as tmp:
            mesh.export(tmp, file_type="stl")
    else:
        raise DataError(f"{path}: unknown layer format '.{fmt}' (known: "
                        f"{', '.join(LAYER_FORMATS)})")


def build_plate_offset(result: SliceResult) -> float:
    """The shift along the axis that puts the part's lowest layer on the build plate (0)."""
    return -min((la.bottom for la in result.layers), default=0.0)


def cli_document(result: SliceResult, *, units: float = 1.0) -> str:
    """The layers as an ASCII Common Layer Interface file (`cli_lines`, joined)."""
    return "".join(cli_lines(result, units=units))


def cli_lines(result: SliceResult, *, units: float = 1.0) -> Iterator[str]:
    """The lines of an ASCII Common Layer Interface file, layer by layer, standing on the
    build plate (a writer streams them: no copy of the whole model is made).

    Heights start at 0: every layer is written at its top height plus `build_plate_offset`,
    which the header states in a comment (and the slice report holds). Closed contours repeat
    their first point, with direction 1 for outer (counter-clockwise) and 0 for holes
    (clockwise); open ones have 2.
    """
    offset = build_plate_offset(result)
    for line in ("$$HEADERSTART", "$$ASCII", f"$$UNITS/{units:.6g}", "$$VERSION/200",
                 "$$LABEL/1,wavepoly", f"$$LAYERS/{len(result.layers)}",
                 f"//heights shifted by {offset:+.6f} so that the part stands on the build "
                 "plate//", "$$HEADEREND", "$$GEOMETRYSTART"):
        yield line + "\n"
    for layer in result.layers:
        yield f"$$LAYER/{layer.top + offset:.6f}\n"
        depth = nesting_depth(layer.fit.parents or [-1] * len(layer.fit.contours))
        for c, d in zip(layer.fit.contours, depth):
            v = np.vstack([c.vertices, c.vertices[:1]]) if c.closed else c.vertices
            direction = (1 if d % 2 == 0 else 0) if c.closed else 2
            coords = ",".join(f"{x:.6f},{y:.6f}" for x, y in v)
            yield f"$$POLYLINE/1,{direction},{len(v)},{coords}\n"
    yield "$$GEOMETRYEND\n"


def layer_mesh(result: SliceResult, *, separate: bool = False):
    """The stair-step model as a printable triangle mesh (trimesh).

    Each layer's closed contours (holes by the even-odd rule) are extruded from its bottom to
    its top with manifold3d; the union of all layer prisms is one watertight,
    winding-consistent solid per connected part of the object (``separate=False``), or each
    layer stays a closed body of its own, sharing no faces with the next (``separate=True``:
    every prism is shrunk by a hair along the axis so that neighbours do not touch). Open
    contours bound no area and are left out; the union's enclosed cavities narrower than the
    tolerance are filled (`VOID_FILL`).
    """
    import trimesh
    from manifold3d import CrossSection, FillRule, Manifold, OpType

    prisms = []
    for layer in result.layers:
        rings = [c.vertices for c in layer.fit.contours if c.closed and len(c.vertices) >= 3]
        if not rings:
            continue
        section = CrossSection([np.asarray(r, float) for r in rings], FillRule.EvenOdd)
        if section.is_empty():
            continue
        gap = SEPARATION * layer.thickness if separate else -OVERLAP * layer.thickness
        prism = Manifold.extrude(section, layer.thickness - 2 * gap)
        prisms.append(prism.translate((0.0, 0.0, layer.bottom + gap)))
    if not prisms:
        raise DataError("the layer model has no closed contour to extrude")
    if separate:
        meshes = [_to_trimesh(p, result) for p in prisms]
        return trimesh.util.concatenate(meshes)
    solid = Manifold.batch_boolean(prisms, OpType.Add)
    return _to_trimesh(_small_voids_filled(solid, result), result)


def _small_voids_filled(solid, result: SliceResult):
    """The union without its enclosed cavities smaller than `VOID_FILL`: a layer's hole that
    the layers above and below cover, narrower than the tolerance resolves (at the zippered
    bunny's base holes, the mesh's own loops of half a tolerance), would print as a separate
    shell of no use; larger cavities (a hollow part) stay."""
    from manifold3d import Manifold

    parts = solid.decompose()
    thickest = max(la.thickness for la in result.layers)
    limit = VOID_FILL * (2.0 * result.tolerance) ** 2 * thickest
    kept = [p for p in parts if p.volume() >= 0 or -p.volume() > limit]
    return solid if len(kept) == len(parts) else Manifold.compose(kept)


#: Enclosed cavities of the union smaller than this many (2 tolerances)^2 x the thickest layer
#: (a hole 2 tolerances wide through one layer) are filled; larger ones are kept.
VOID_FILL = 1.0
#: For the union, each prism reaches this fraction of its thickness into its neighbours, so
#: that a top and the next bottom that differ by round-off still fuse into one solid.
OVERLAP = 1e-4
#: With separate bodies, each prism loses this fraction of its thickness at either face, so
#: that no two bodies share a face (a slicer would merge or reject touching shells).
SEPARATION = 1e-4


def _to_trimesh(solid, result: SliceResult):
    import trimesh

    mesh = solid.to_mesh()
    verts = np.asarray(mesh.vert_properties)[:, :3] @ result.basis  # plane -> world
    return trimesh.Trimesh(verts, np.asarray(mesh.tri_verts), process=True)
