"""Layer-model writers: Common Layer Interface (.cli), SVG, GeoJSON and STL, written atomically.

Contours are written in the layers' plane coordinates (see `SliceResult.basis`); for slicing
along z these are the cloud's own x, y.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import DataError
from ..geometry import nesting_depth
from ..types import SliceResult
from .atomic import atomic_path, write_text_atomic
from .writers import check_valid, svg_document, write_geojson

LAYER_FORMATS = ("cli", "svg", "geojson", "json", "stl")


def write_layers(path: str | Path, result: SliceResult, *, fmt: str | None = None,
                 units: float = 1.0) -> None:
    """Write a layer model; the format comes from the extension (`LAYER_FORMATS`).

    ``units`` is the length of one coordinate unit in millimetres (the CLI header's $$UNITS).
    """
    fmt = (fmt or Path(path).suffix.lstrip(".")).lower()
    if fmt in LAYER_FORMATS:
        check_valid(path, [la.fit for la in result.layers])
    if fmt == "cli":
        write_text_atomic(path, cli_document(result, units=units))
    elif fmt == "svg":
        groups = [(f"layer-{k}-z{la.top:.6g}", la.fit.contours)
                  for k, la in enumerate(result.layers)]
        write_text_atomic(path, svg_document(groups))
    elif fmt in ("geojson", "json"):
        extras = [{"layer": k, "z": la.z, "bottom": la.bottom, "thickness": la.thickness}
                  for k, la in enumerate(result.layers)]
        write_geojson(path, [la.fit for la in result.layers], extras)
    elif fmt == "stl":
        mesh = layer_mesh(result)
        with atomic_path(path) as tmp:
            mesh.export(tmp, file_type="stl")
    else:
        raise DataError(f"{path}: unknown layer format '.{fmt}' (known: "
                        f"{', '.join(LAYER_FORMATS)})")


def cli_document(result: SliceResult, *, units: float = 1.0) -> str:
    """The layers as an ASCII Common Layer Interface file.

    Each layer is written at its top height; closed contours repeat their first point, with
    direction 1 for outer (counter-clockwise) and 0 for holes (clockwise); open ones have 2.
    """
    lines = ["$$HEADERSTART", "$$ASCII", f"$$UNITS/{units:.6g}", "$$VERSION/200",
             "$$LABEL/1,wavepoly", f"$$LAYERS/{len(result.layers)}", "$$HEADEREND",
             "$$GEOMETRYSTART"]
    for layer in result.layers:
        lines.append(f"$$LAYER/{layer.top:.6f}")
        depth = nesting_depth(layer.fit.parents or [-1] * len(layer.fit.contours))
        for c, d in zip(layer.fit.contours, depth):
            v = np.vstack([c.vertices, c.vertices[:1]]) if c.closed else c.vertices
            direction = (1 if d % 2 == 0 else 0) if c.closed else 2
            coords = ",".join(f"{x:.6f},{y:.6f}" for x, y in v)
            lines.append(f"$$POLYLINE/1,{direction},{len(v)},{coords}")
    lines.append("$$GEOMETRYEND")
    return "\n".join(lines) + "\n"


def layer_mesh(result: SliceResult):
    """The stair-step model: each layer's closed contours extruded by its thickness (trimesh).

    Each layer is a watertight solid of its own (manifold3d's extrusion, holes by the
    even-odd rule); open contours bound no area and are left out.
    """
    import trimesh
    from manifold3d import CrossSection, FillRule

    parts = []
    for layer in result.layers:
        rings = [c.vertices for c in layer.fit.contours if c.closed and len(c.vertices) >= 3]
        if not rings:
            continue
        solid = CrossSection([np.asarray(r, float) for r in rings], FillRule.EvenOdd)
        if solid.is_empty():
            continue
        mesh = solid.extrude(layer.thickness).translate((0.0, 0.0, layer.bottom)).to_mesh()
        verts = np.asarray(mesh.vert_properties)[:, :3] @ result.basis  # plane -> world
        parts.append(trimesh.Trimesh(verts, np.asarray(mesh.tri_verts), process=True))
    if not parts:
        raise DataError("the layer model has no closed contour to extrude")
    return trimesh.util.concatenate(parts)
