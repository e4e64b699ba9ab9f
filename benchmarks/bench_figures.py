"""Figures like the paper's, from a glyph and real scans: Fig. 1, 2, 6 and 7e."""

from __future__ import annotations

import numpy as np

import wavepoly
from wavepoly.levels import decompose_contour
from wavepoly.ordering import order_points
from wavepoly.plot import (
    plot_contact_sheet,
    plot_fit,
    plot_layer_model,
    plot_levels,
    plot_ordering,
    save_figure,
)
from wavepoly.samples import glyph_outlines, sample_rings

from .common import DOCS, SHARED

FIGURES = DOCS / "figures"


def _fig2(name: str, pts: np.ndarray, eps: float) -> str:
    ordering = order_points(pts, eps)
    contour = max(ordering.contours, key=lambda c: len(c.points))
    pyramid = decompose_contour(contour.points, contour.closed, eps, None)
    k = max(pyramid.coarsest + 1, pyramid.finest - 3)
    save_figure(plot_levels(pts[contour.members], pyramid.coefficients[k],
                            pyramid.coefficients[k - 1], contour.closed,
                            labels=(f"level {k}", f"level {k - 1}"),
                            title=f"Fig. 2 analogue: {name}"), FIGURES / f"{name}-fig2.png")
    save_figure(plot_ordering(pts, ordering), FIGURES / f"{name}-fig1.png")
    result = wavepoly.fit(pts, eps)
    save_figure(plot_fit(pts, result), FIGURES / f"{name}-fig6.png")
    counts = " + ".join(f"{r.input_points} -> {r.ordered_points} -> {r.final_vertices}"
                        for r in result.reports)
    return (f"**{name}** (tolerance {eps:.3g}): input -> ordered -> final per contour: "
            f"{counts}.\n\n![{name} Fig. 1](figures/{name}-fig1.png) "
            f"![{name} Fig. 2](figures/{name}-fig2.png) ![{name} Fig. 6](figures/{name}-fig6.png)")


def run() -> str:
    FIGURES.mkdir(parents=True, exist_ok=True)
    parts = ["## Figures (paper Fig. 1, 2, 6, 7e)\n"]
    glyph = sample_rings(glyph_outlines("B").rings, spacing=0.015, noise=0.015, seed=0)
    parts.append(_fig2("glyph-B", glyph, 0.08))
    if (SHARED / "scans3d").exists():
        from wavepoly.io import read_points
        from wavepoly.slicing import slice_cloud

        blade = read_points(SHARED / "scans3d" / "turbineblade.ply")
        eps = 0.005 * float(np.ptp(blade, axis=0).max())
        for label, frac in (("turbine-root", 0.05), ("turbine-airfoil", 0.6)):
            z = blade[:, 2].min() + frac * np.ptp(blade[:, 2])
            band = blade[np.abs(blade[:, 2] - z) <= eps][:, :2]
            parts.append(_fig2(label, band, eps))
        bunny = read_points(SHARED / "scans3d" / "bunny_zipper.ply")
        eps = 0.01 * float(np.ptp(bunny, axis=0).max())
        res = slice_cloud(bunny, eps, axis="y", adaptive=True, workers=2)
        save_figure(plot_layer_model(res), FIGURES / "bunny-fig7.png")
        save_figure(plot_contact_sheet(res), FIGURES / "bunny-layers.png")
        parts.append(f"**bunny, adaptive layers** ({len(res.layers)} layers): "
                     "![bunny layer model](figures/bunny-fig7.png) "
                     "![bunny layers](figures/bunny-layers.png)")
        parts.append(_real_orderings())
    return "\n\n".join(parts)


def _real_orderings() -> str:
    """Issue 3's real scans, ordered (the figures `wavepoly order --plot` draws): a merged
    bunny slice, a raw range-scan slice (open curves) and the Intel laser map."""
    from wavepoly.io import read_points

    from .bench_peers import _slice

    scans = SHARED / "scans3d"
    cases = []
    for label, path in (("bunny-slice", scans / "bunny_zipper.ply"),
                        ("bun000-slice", scans / "bunny_range_scans" / "bun000.ply")):
        cloud = read_points(path)
        eps = 0.01 * float(np.ptp(cloud, axis=0).max())
        cases.append((label, _slice(cloud, 1, 0.5, eps), eps))
    cases.append(("intel-map", read_points(SHARED / "lidar2d" / "intel-corrected.log.gz"), 0.05))
    lines = ["### Ordering real scans (§2)\n"]
    for label, pts, radius in cases:
        ordering = order_points(pts, radius)
        save_figure(plot_ordering(pts, ordering), FIGURES / f"{label}-ordering.png")
        n_open = sum(not c.closed for c in ordering.contours)
        notes = "; ".join(ordering.notes) or "no notes"
        lines.append(f"**{label}** (radius {radius:.3g}): {len(pts)} points -> "
                     f"{len(ordering.contours)} contours ({n_open} open), "
                     f"{len(ordering.outliers)} outliers. Notes: {notes}.\n\n"
                     f"![{label}](figures/{label}-ordering.png)")
    return "\n\n".join(lines)
