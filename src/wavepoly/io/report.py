"""What a run reports: the JSON reports of a fit and of a slicing, and their summary lines.

The CLI and the demo print and write these; they are plain functions of the result records, so
a notebook or a pipeline gets the same figures as the command line.
"""

from __future__ import annotations

import json
from dataclasses import asdict
from pathlib import Path

import numpy as np

from ..types import FitResult, Ordering, SliceResult, within
from .atomic import write_text_atomic
from .layers import build_plate_offset


def write_report(path: str | Path, report: dict) -> None:
    """Write a report (`fit_report`, `slice_report`) as indented JSON, atomically."""
    write_text_atomic(path, json.dumps(report, indent=2))


def fit_report(result: FitResult, source: str) -> dict:
    """The JSON report of a fit: per contour figures, timings, outliers and notes."""
    return {
        "input": source, "points": result.n_points, "tolerance": result.tolerance,
        "max_error": result.max_error, "mean_error": result.mean_error,
        "contours": [{**asdict(r), "mscs_per_level": {str(k): v for k, v in
                                                       r.mscs_per_level.items()}}
                     for r in result.reports],
        "vertices": result.n_vertices, "outliers": len(result.outliers),
        "outlier_indices": result.outliers.tolist(), "validity": validity_report(result),
        "suggested_tolerance": result.suggested_tolerance,
        "timings": result.timings, "notes": list(result.notes),
    }


def validity_report(result: FitResult) -> dict:
    """Closed and open contour counts, and whether (or where not) the geometry is valid."""
    v = result.validity
    n_closed = sum(c.closed for c in result.contours)
    return {"closed": n_closed, "open": len(result.contours) - n_closed,
            "valid": v.valid if v is not None else None,
            "problems": [str(p) for p in v.problems] if v is not None else []}


def fit_summary(result: FitResult) -> list[str]:
    """Lines for a terminal: one per contour, then the totals, then the notes."""
    lines = []
    for k, (c, r) in enumerate(zip(result.contours, result.reports)):
        if r.first_piece is not None and r.first_piece != k:
            lines.append(f"contour {k}: open   a piece of contour {r.first_piece}'s points, "
                         f"split at a junction -> {r.final_vertices:4d} vertices, max error "
                         f"{c.max_error:.4g}")
            continue
        lines.append(f"contour {k}: {'closed' if c.closed else 'open  '} {r.input_points:7d} "
                     f"points -> {r.ordered_points:6d} ordered -> {r.wavelet_vertices:5d} "
                     f"wavelet -> {r.final_vertices:4d} vertices, max error {c.max_error:.4g}")
    shape = (str(result.validity) if result.validity is not None else
             f"{sum(c.closed for c in result.contours)} closed")
    lines.append(f"{result.n_points} points -> {len(result.contours)} contours ({shape}), "
                 f"{result.n_vertices} vertices, max error {result.max_error:.4g} "
                 f"(tolerance {result.tolerance:.4g}), {len(result.outliers)} outliers"
                 + (f"; the tolerance is below the scan's scatter or spacing: try "
                    f"{result.suggested_tolerance:g}" if result.suggested_tolerance else ""))
    lines += [f"note: {note}" for note in result.notes]
    return lines


def slice_report(result: SliceResult, source: str | list[str]) -> dict:
    """The JSON report of a slicing: per layer heights, thickness, contours, errors, and the
    engine that fitted the layers (``{"kind": "local" | "dask", ...}``)."""
    return {
        "input": source, "points": result.n_points, "tolerance": result.tolerance,
        "adaptive": result.adaptive, "layers": len(result.layers),
        "model_error": result.model_error, "model_error_kind": "3D staircase",
        "build_plate_offset": build_plate_offset(result),
        "vertices": result.n_vertices,
        "per_layer": [{"bottom": la.bottom, "thickness": la.thickness, "z": la.z,
                       "band_points": la.fit.n_points, "slab_points": la.slab_points,
                       "contours": len(la.fit.contours),
                       "closed": sum(c.closed for c in la.fit.contours),
                       "valid": la.fit.validity is None or la.fit.validity.valid,
                       "vertices": la.fit.n_vertices, "fit_max_error": la.fit.max_error,
                       "model_error": la.model_error if np.isfinite(la.model_error) else None,
                       "outliers": len(la.fit.outliers), "notes": list(la.fit.notes)}
                      for la in result.layers],
        "timings": result.timings, "notes": list(result.notes), "engine": result.engine,
    }


def slice_summary(result: SliceResult) -> str:
    """One line: layers, thickness range, contours, vertices, model error."""
    thick = np.array([la.thickness for la in result.layers])
    n_contours = sum(len(la.fit.contours) for la in result.layers)
    n_within = sum(within(la.model_error, result.tolerance) for la in result.layers
                   if la.slab_points)  # a layer with points but no contour is not within
    contours = [c for la in result.layers for c in la.fit.contours]
    n_closed = sum(c.closed for c in contours)
    n_invalid = sum(len(la.fit.validity.problems) for la in result.layers
                    if la.fit.validity is not None)
    return (f"{result.n_points} points -> {len(result.layers)} layers "
            f"({'adaptive' if result.adaptive else 'uniform'}, thickness {thick.min():.4g}"
            f"-{thick.max():.4g}), {n_contours} contours ({n_closed} closed, "
            f"{n_contours - n_closed} open, {n_invalid} invalid), {result.n_vertices} vertices, "
            f"layer model error {result.model_error:.4g} (tolerance {result.tolerance:g}; "
            f"{n_within} of {sum(la.slab_points > 0 for la in result.layers)} layers within it)")


def ordering_summary(ordering: Ordering, n_points: int) -> str:
    """One line: contours (closed/open), ordered points, outliers, radius."""
    n_closed = sum(c.closed for c in ordering.contours)
    ordered = sum(len(c.points) for c in ordering.contours)
    return (f"{n_points} points -> {len(ordering.contours)} contours ({n_closed} closed, "
            f"{len(ordering.contours) - n_closed} open), {ordered} ordered points, "
            f"{len(ordering.outliers)} outliers, radius {ordering.radius:.4g}")
