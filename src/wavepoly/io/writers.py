"""Polygon writers: GeoJSON, SVG, DXF and CSV, each written atomically.

Slice stacks (`SliceResult`) also go to the Common Layer Interface (``.cli``) and STL; see
`wavepoly.io.layers`.
"""

from __future__ import annotations

import csv
import json
import os
import re
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..errors import DataError, EngineError, ParameterError
from ..geometry import nesting_depth
from ..types import Contour, FitResult, Ordering
from .atomic import atomic_path, write_lines_atomic, write_text_atomic
from .streams import is_stream, path_for_stream
from .units import unit_of

POLYGON_FORMATS = ("geojson", "json", "svg", "dxf", "csv", "gpkg")


def write_polygons(path, result: FitResult, format: str | None = None, *,
                   fmt: str | None = None, units: str = "unitless",
                   crs: str | None = None) -> None:
    """Write the contours of ``result`` to ``path``; the format comes from the extension.

    ``path`` may be a file object (text or binary), then ``format`` names the format.
    GeoJSON (RFC 7946): a FeatureCollection, closed contours as Polygons with their holes,
    open ones as LineStrings. SVG: one path per contour, y up. DXF: one LWPOLYLINE per
    contour. CSV: rows of ``contour,vertex,x,y,closed``. GeoPackage (``.gpkg``, with the
    ``gis`` extra): one feature per outer polygon or polyline, in ``crs`` (e.g.
    ``"EPSG:25832"``) for georeferenced scans. ``units`` (`UNITS`) are written where the
    format has them: DXF's $INSUNITS, SVG's width and height.
    """
    fmt = fmt or format
    if is_stream(path):
        with path_for_stream(path, fmt) as tmp:
            write_polygons(tmp, result, fmt=fmt, units=units)
        return
    fmt = (fmt or Path(path).suffix.lstrip(".")).lower()
    unit_of(units)
    writer = {"geojson": write_geojson, "json": write_geojson, "svg": write_svg,
              "dxf": write_dxf, "csv": write_csv, "gpkg": write_gpkg}.get(fmt)
    if crs is not None and fmt != "gpkg":
        raise ParameterError(f"{path}: a CRS is written to GeoPackage (.gpkg) only; GeoJSON "
                             "is WGS 84 longitude/latitude by RFC 7946")
    if writer is None:
        raise DataError(f"{path}: unknown polygon format '.{fmt}' "
                        f"(known: {', '.join(POLYGON_FORMATS)})")
    check_valid(path, [result])
    if fmt in ("svg", "dxf"):
        writer(path, [result], units=units)
    elif fmt == "gpkg":
        writer(path, [result], crs=crs)
    else:
        writer(path, [result])


def check_valid(path: str | Path, results: Sequence[FitResult]) -> None:
    """Refuse to write geometry that a CAD tool, a slicer or a GIS would reject or misread."""
    for k, r in enumerate(results):
        if r.validity is not None and not r.validity.valid:
            where = f" (layer {k})" if len(results) > 1 else ""
            raise DataError(f"{path}: not written: the result is not valid geometry{where}: "
                            f"{r.validity.problems[0]}")


def _ring(vertices: np.ndarray) -> list[list[float]]:
    pts = vertices.tolist()
    return pts + pts[:1]


def geojson_features(result: FitResult, extra: dict | None = None) -> list[dict]:
    """GeoJSON features of one fit: outer polygons with their holes, and open polylines."""
    parents = result.parents or [-1] * len(result.contours)
    depth = nesting_depth(parents)
    features = []
    for i, c in enumerate(result.contours):
        props = {"contour": i, "closed": c.closed, "vertices": c.n_vertices,
                 "max_error": c.max_error, "mean_error": c.mean_error}
        if result.z is not None:
            props["z"] = result.z
        props.update(extra or {})
        if not c.closed:
            geom = {"type": "LineString", "coordinates": c.vertices.tolist()}
        elif depth[i] % 2 == 1:
            continue  # a hole: written inside its parent polygon
        else:
            holes = [_ring(h.vertices) for j, h in enumerate(result.contours)
                     if parents[j] == i and h.closed]
            geom = {"type": "Polygon", "coordinates": [_ring(c.vertices), *holes]}
            props["holes"] = len(holes)
        features.append({"type": "Feature", "geometry": geom, "properties": props})
    return features


def write_geojson(path: str | Path, results: Sequence[FitResult],
                  extras: Sequence[dict] | None = None) -> None:
    """A FeatureCollection of the results' features, written result by result (the text of
    ``json.dumps`` of the whole collection, without making it)."""
    def pieces():
        yield '{"type": "FeatureCollection", "features": ['
        first = True
        for k, r in enumerate(results):
            for feature in geojson_features(r, extras[k] if extras else None):
                yield ("" if first else ", ") + json.dumps(feature)
                first = False
        yield "]}"

    write_lines_atomic(path, pieces())


def _svg_path(c: Contour) -> str:
    pts = " L ".join(f"{x:.6g},{y:.6g}" for x, y in c.vertices)
    return f"M {pts}{' Z' if c.closed else ''}"


def svg_document(groups: Sequence[tuple[str, list[Contour]]], *, points: np.ndarray | None = None,
                 units: str = "unitless") -> str:
    """An SVG with one <g> per (label, contours) group, y axis pointing up, fitted viewBox;
    with ``units``, its width and height are the drawing's true size in them."""
    allv = [c.vertices for _, cs in groups for c in cs if len(c.vertices)]
    if points is not None:
        allv.append(points[:, :2])
    if not allv:
        raise DataError("nothing to draw: no contours")
    stack = np.concatenate(allv)
    lo, hi = stack.min(axis=0), stack.max(axis=0)
    size = float(max(hi - lo)) or 1.0
    pad = 0.02 * size
    x0, y0, w, h = lo[0] - pad, -hi[1] - pad, hi[0] - lo[0] + 2 * pad, hi[1] - lo[1] + 2 * pad
    stroke = size / 500
    unit = unit_of(units)
    scale = unit.svg_scale
    size_attrs = (f'width="{w * scale:.6g}{unit.svg}" height="{h * scale:.6g}{unit.svg}"'
                  if unit.svg else
                  f'width="800" height="{800 * h / w:.0f}"')
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="{x0:.6g} {y0:.6g} {w:.6g} {h:.6g}" '
           f'{size_attrs}>',
           f'<g transform="scale(1,-1)" fill="none" stroke-width="{stroke:.3g}" '
           'stroke-linejoin="round">']
    if points is not None:
        r = stroke * 0.8
        dots = "".join(f'<circle cx="{x:.6g}" cy="{y:.6g}" r="{r:.3g}"/>' for x, y in points[:, :2])
        out.append(f'<g fill="#999" stroke="none">{dots}</g>')
    for label, contours in groups:
        out.append(f'<g id="{label}">')
        for c in contours:
            colour = "#1f77b4" if c.closed else "#d62728"
            out.append(f'<path d="{_svg_path(c)}" stroke="{colour}"/>')
        out.append("</g>")
    out.append("</g></svg>")
    return "\n".join(out)


def write_svg(path: str | Path, results: Sequence[FitResult],
              labels: Sequence[str] | None = None, units: str = "unitless") -> None:
    groups = [(labels[k] if labels else f"slice-{k}", r.contours) for k, r in enumerate(results)]
    write_text_atomic(path, svg_document(groups, units=units))


def write_dxf(path: str | Path, results: Sequence[FitResult], units: str = "unitless") -> None:
    import ezdxf

    doc = ezdxf.new("R2010", units=unit_of(units).dxf)
    msp = doc.modelspace()
    for r in results:
        for c in r.contours:
            attribs = {"elevation": r.z} if r.z is not None else {}
            msp.add_lwpolyline(c.vertices.tolist(), close=c.closed, dxfattribs=attribs)
    with atomic_path(path) as tmp:
        doc.saveas(tmp)


def write_gpkg(path: str | Path, results: Sequence[FitResult], extras: Sequence[dict] | None = None,
               crs: str | None = None) -> None:
    """A GeoPackage of the features of `geojson_features` (pyogrio, the ``gis`` extra)."""
    try:
        from pyogrio.raw import write
    except ImportError:
        raise EngineError(f"{path}: writing GeoPackage needs the gis extra: "
                          "pip install 'wavepoly[gis]'") from None
    import shapely

    if crs is not None and not re.fullmatch(r"EPSG:\d{4,6}", crs):
        raise ParameterError(f"--crs takes EPSG:NNNN, not {crs!r}")
    feats = [f for k, r in enumerate(results)
             for f in geojson_features(r, extras[k] if extras else None)]
    if not feats:
        raise DataError(f"{path}: nothing to write: no contours")
    names = sorted({key for f in feats for key in f["properties"]})
    columns = [np.array([f["properties"].get(n, np.nan) for f in feats]) for n in names]
    wkb = shapely.to_wkb([shapely.geometry.shape(f["geometry"]) for f in feats])
    with atomic_path(path) as tmp:
        made = tmp.with_name(tmp.name + ".gpkg")  # GDAL makes it, and wants the extension
        try:
            write(str(made), wkb, columns, names, driver="GPKG", geometry_type="Unknown",
                  crs=crs, layer="contours")
            os.replace(made, tmp)
        finally:
            made.unlink(missing_ok=True)


def write_csv(path: str | Path, results: Sequence[FitResult]) -> None:
    with atomic_path(path) as tmp, open(tmp, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        header = ["contour", "vertex", "x", "y", "closed"]
        sliced = any(r.z is not None for r in results)
        w.writerow(header + (["z"] if sliced else []))
        cid = 0
        for r in results:
            for c in r.contours:
                for k, (x, y) in enumerate(c.vertices):
                    row = [cid, k, repr(float(x)), repr(float(y)), int(c.closed)]
                    w.writerow(row + ([r.z] if sliced else []))
                cid += 1


def write_ordering(path, ordering: Ordering, format: str | None = None) -> None:
    """Write the ordered contours of `wavepoly.order_points` (§2): each contour's ordered
    points as a polygon (closed) or polyline (open), in CSV, GeoJSON or SVG. They are the
    ordering's output, not fitted polygons, so they are written without the validity check."""
    contours = [Contour(c.points, c.closed) for c in ordering.contours]
    fmt = (format or (None if is_stream(path) else Path(path).suffix.lstrip("."))) or ""
    if fmt.lower() not in ("csv", "geojson", "json", "svg"):
        raise DataError(f"{path}: ordered contours are written as .csv, .geojson or .svg")
    result = FitResult(contours, float("nan"), float("nan"), float("nan"),
                       np.asarray(ordering.outliers, dtype=np.intp), 0,
                       parents=[-1] * len(contours))
    if is_stream(path):
        with path_for_stream(path, fmt) as tmp:
            write_ordering(tmp, ordering, fmt)
        return
    {"csv": write_csv, "svg": write_svg}.get(fmt.lower(), write_geojson)(path, [result])


def write_points(path: str | Path, points: np.ndarray, *, header: str = "") -> None:
    """Write points as a whitespace-separated text file (``.xy``/``.xyz``), atomically."""
    with atomic_path(path) as tmp:
        np.savetxt(tmp, points, fmt="%.6f", header=header)
