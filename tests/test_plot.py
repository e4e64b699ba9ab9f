"""Figures: written whole, drawn without choosing a backend at import."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
from matplotlib.figure import Figure

import wavepoly
from wavepoly.levels import decompose_contour
from wavepoly.plot import (
    plot_contact_sheet,
    plot_fit,
    plot_layer_model,
    plot_levels,
    plot_ordering,
    save_figure,
)
from wavepoly.samples import glyph_outlines, sample_rings

PNG = b"\x89PNG\r\n\x1a\n"


def test_importing_plot_chooses_no_backend():
    code = ("import sys, wavepoly.plot, wavepoly.cli; "
            "print('matplotlib.pyplot' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == "False"


def test_fit_and_ordering_figures_are_pngs(tmp_path):
    pts = sample_rings(glyph_outlines("O").rings, spacing=0.02, noise=0.005, seed=2)
    result = wavepoly.fit(pts, 0.05)
    ordering = wavepoly.order_points(pts, 0.05)
    for name, ax in (("fit.png", plot_fit(pts, result)),
                     ("ordering.png", plot_ordering(pts, ordering))):
        assert isinstance(ax.figure, Figure)
        save_figure(ax, tmp_path / name)
        assert (tmp_path / name).read_bytes()[:8] == PNG
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fit.png", "ordering.png"]


def test_levels_figure_labels_both_levels(tmp_path):
    t = np.linspace(0, 2 * np.pi, 300, endpoint=False)
    ring = np.column_stack([np.cos(t), np.sin(t)])
    pyramid = decompose_contour(ring, True, 0.01)
    k = pyramid.coarsest
    ax = plot_levels(ring, pyramid.coefficients[k + 1], pyramid.coefficients[k], True,
                     (f"level {k + 1}", f"level {k}"))
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels[0] == "input points (300)"
    assert labels[1].startswith(f"level {k + 1}") and labels[2].startswith(f"level {k}")
    lines = {line.get_label(): line for line in ax.get_lines()}
    fine, coarse = (lines[label] for label in labels[1:])
    assert fine.get_color() != coarse.get_color()  # the two levels can be told apart
    assert fine.get_marker() != coarse.get_marker()
    assert ax.get_xlabel() == "x" and ax.child_axes  # and the zoomed inset where they differ
    save_figure(ax, tmp_path / "levels.svg")
    assert (tmp_path / "levels.svg").read_text().lstrip().startswith("<?xml")


def test_layer_figures(tmp_path):
    rng = np.random.default_rng(0)
    t, h = rng.uniform(0, 2 * np.pi, 6000), rng.uniform(0, 4, 6000)
    cloud = np.column_stack([2 * np.cos(t), 2 * np.sin(t), h])
    res = wavepoly.slice_cloud(cloud, 0.1, layer_thickness=1.0, workers=1)
    save_figure(plot_layer_model(res), tmp_path / "model.png")
    sheet = plot_contact_sheet(res)
    assert len([ax for ax in sheet.axes if ax.lines]) == len(res.layers)
    save_figure(sheet, tmp_path / "sheet.png")
    assert (tmp_path / "model.png").read_bytes()[:8] == PNG


def test_a_failed_save_leaves_no_file(tmp_path):
    ax = plot_levels(np.zeros((3, 2)) + [[0, 0], [1, 0], [0, 1]], np.eye(2), np.eye(2), False)
    try:
        save_figure(ax, tmp_path / "figure.notaformat")
    except ValueError:
        pass
    assert list(tmp_path.iterdir()) == []


def test_outliers_are_light_and_capped_and_axes_carry_their_units():
    from wavepoly.plot import MAX_OUTLIER_DOTS, plot_fit

    rng = np.random.default_rng(1)
    t = rng.uniform(0, 2 * np.pi, 4000)
    ring = np.column_stack([np.cos(t), np.sin(t)]) + rng.normal(scale=0.002, size=(4000, 2))
    noise = rng.uniform(-3, 3, (5000, 2))
    pts = np.vstack([ring, noise])
    from dataclasses import replace

    import wavepoly

    res = replace(wavepoly.fit(ring, 0.02), outliers=np.arange(4000, 9000), n_points=9000)
    ax = plot_fit(pts, res, units="mm")
    assert ax.get_xlabel() == "x (mm)" and ax.get_ylabel() == "y (mm)"
    [dots] = [ln for ln in ax.get_lines() if ln.get_label().startswith("outliers")]
    assert len(dots.get_xdata()) == MAX_OUTLIER_DOTS
    assert f"{MAX_OUTLIER_DOTS} shown" in dots.get_label() and dots.get_alpha() < 1
