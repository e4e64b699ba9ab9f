"""``wavepoly demo``: fit noisy scan-like samples of glyph outlines and write the results.

The input comes from matplotlib's bundled DejaVu Sans (an installed dependency): outlines with
sharp corners, arcs and holes, sampled at random with Gaussian noise like a sliced scan, at the
scale of the paper's first example (a ~20 mm part, tolerance 0.08 mm).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

import wavepoly
from wavepoly.levels import decompose_contour
from wavepoly.plot import plot_fit, plot_levels, plot_mscs, plot_ordering, save_figure
from wavepoly.reconstruction import reconstruct_contour
from wavepoly.samples import glyph_outlines, sample_rings

DEMO_TEXT = "B8&k"
DEMO_TOLERANCE = 0.08  # mm, the paper's first example
DEMO_SPACING = 0.015  # mm between samples along the outline
DEMO_NOISE = 0.015  # mm, standard deviation of the scanner noise


def demo_points(seed: int = 7) -> np.ndarray:
    """The demo's input: noisy samples of the outlines of `DEMO_TEXT`, 20 mm high, shuffled."""
    shape = glyph_outlines(DEMO_TEXT, height=20.0)
    return sample_rings(shape.rings, spacing=DEMO_SPACING, noise=DEMO_NOISE, seed=seed)


def run_demo(out: Path, echo: Callable[[str], None] = print) -> None:
    """Fit the demo points and write input, polygons, report and figures into ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    pts = demo_points()
    echo(f"demo: {len(pts)} noisy points on the outlines of {DEMO_TEXT!r} (DejaVu Sans, 20 mm),"
         f" tolerance {DEMO_TOLERANCE} mm")
    wavepoly.write_points(out / "input-points.xy", pts, header="x y (mm): wavepoly demo input")
    t0 = time.perf_counter()
    result = wavepoly.fit(pts, DEMO_TOLERANCE)
    elapsed = time.perf_counter() - t0
    for k, (c, r) in enumerate(zip(result.contours, result.reports)):
        echo(f"contour {k}: {'closed' if c.closed else 'open'}, {r.input_points} points -> "
             f"{r.ordered_points} ordered -> {r.wavelet_vertices} wavelet -> "
             f"{r.final_vertices} vertices, levels {r.finest_level}->{r.coarsest_level}, "
             f"max error {c.max_error:.4f} mm")
    echo(f"total: {len(pts)} points -> {result.n_vertices} vertices in {len(result.contours)} "
         f"contours, max error {result.max_error:.4f} mm <= {DEMO_TOLERANCE} mm, "
         f"{len(result.outliers)} outliers, {elapsed:.2f} s")
    for name in ("polygons.svg", "polygons.geojson", "polygons.dxf"):
        wavepoly.write_polygons(out / name, result, units="mm")
    wavepoly.write_report(out / "report.json", wavepoly.fit_report(result, "demo"))
    save_figure(plot_fit(pts, result, units="mm"), out / "fit.png")
    ordering = wavepoly.order_points(pts, DEMO_TOLERANCE)
    save_figure(plot_ordering(pts, ordering, units="mm"), out / "ordering.png")
    _level_figures(pts, ordering, out)
    echo(f"wrote {out}/: input-points.xy polygons.svg polygons.geojson polygons.dxf "
         "report.json fit.png ordering.png levels.png mscs.png")


def _level_figures(pts: np.ndarray, ordering: wavepoly.Ordering, out: Path) -> None:
    """Fig. 2 (two levels) and Fig. 3-4 (MSCs) of the demo's longest contour."""
    contour = max(ordering.contours, key=lambda c: len(c.points))
    members = pts[contour.members]
    pyramid = decompose_contour(contour.points, contour.closed, DEMO_TOLERANCE)
    k = pyramid.coarsest
    title = f"decomposition: level {k + 1} and level {k} (paper Fig. 2)"
    save_figure(plot_levels(members, pyramid.coefficients[k + 1], pyramid.coefficients[k],
                            contour.closed, (f"level {k + 1}", f"level {k}"), title=title,
                            units="mm"),
                out / "levels.png")
    rec = reconstruct_contour(pyramid, contour.points, members, DEMO_TOLERANCE)
    runs: dict[int, list] = {}
    for m in rec.mscs:
        runs.setdefault(m.level, []).append(m.points)
    save_figure(plot_mscs(members, runs, contour.closed, units="mm",
                          title="MSCs per level (paper Fig. 3-4)"), out / "mscs.png")
