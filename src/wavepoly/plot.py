"""Figures in the manner of the paper's: raw vs ordered points (Fig. 1), two decomposition levels
(Fig. 2), MSCs per level (Fig. 3-4) and the final polygon over the raw points (Fig. 6).

Each function draws on a matplotlib Axes (a new figure when none is given) and returns it;
`save_figure` writes a figure atomically. New figures are `matplotlib.figure.Figure` objects
made without pyplot, so importing this module chooses no backend and opens no window: a file
is rendered by the canvas of its format when it is saved, and in a notebook the caller passes
``ax=`` from its own figure.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
from matplotlib.figure import Figure

from .io.atomic import atomic_path
from .types import FitResult, FloatArray, Ordering, SliceResult

_COLOURS = matplotlib.colormaps["tab10"].colors


def _axes(ax=None, title: str | None = None):
    if ax is None:
        ax = Figure(figsize=(8, 8)).add_subplot()
    ax.set_aspect("equal")
    if title:
        ax.set_title(title, fontsize=10)
    return ax


def _closed(xy: FloatArray, closed: bool) -> FloatArray:
    return np.vstack([xy, xy[:1]]) if closed and len(xy) else xy


def _contours_over_points(ax, points: FloatArray, polylines: list[tuple[FloatArray, bool]],
                          lw: float, marker: dict) -> None:
    """Raw points in grey, then each polyline in its own colour with its points marked."""
    ax.plot(points[:, 0], points[:, 1], ".", ms=1, color="0.75", zorder=1)
    for k, (xy, closed) in enumerate(polylines):
        colour = _COLOURS[k % len(_COLOURS)]
        line = _closed(xy, closed)
        ax.plot(line[:, 0], line[:, 1], "-", lw=lw, color=colour, zorder=2)
        ax.plot(xy[:, 0], xy[:, 1], linestyle="none", color=colour, zorder=3, **marker)


def plot_ordering(points: FloatArray, ordering: Ordering, ax=None, title: str | None = None):
    """Fig. 1: raw points in grey, each ordered contour in its own colour, outliers in black."""
    ax = _axes(ax, title or f"{len(points)} points -> {len(ordering.contours)} contours, "
               f"{sum(len(c.points) for c in ordering.contours)} ordered points")
    _contours_over_points(ax, points, [(c.points, c.closed) for c in ordering.contours],
                          lw=0.8, marker={"marker": ".", "ms": 2.5})
    for k, c in enumerate(ordering.contours):  # the ends of open contours
        if not c.closed:
            ax.plot(*c.points[[0, -1]].T, "x", color=_COLOURS[k % len(_COLOURS)], ms=6,
                    zorder=4)
    if len(ordering.outliers):
        out = points[ordering.outliers]
        ax.plot(out[:, 0], out[:, 1], ".", ms=3, color="k", zorder=4)
    if len(ordering.merged_walls):
        ax.plot(*ordering.merged_walls.T, "o", mfc="none", color="m", ms=8, zorder=5)
    return ax


def plot_levels(points: FloatArray, fine: FloatArray, coarse: FloatArray, closed: bool,
                labels: tuple[str, str] = ("level k", "level k-1"), ax=None,
                title: str | None = None):
    """Fig. 2: a contour's control polygon at two decomposition levels over the raw points."""
    ax = _axes(ax, title)
    ax.plot(points[:, 0], points[:, 1], ".", ms=1, color="0.75")
    for xy, label, style in ((fine, labels[0], "-"), (coarse, labels[1], "--")):
        xy2 = _closed(xy, closed)
        ax.plot(xy2[:, 0], xy2[:, 1], style, lw=1, marker=".", ms=4,
                label=f"{label}: {len(xy)} coefficients")
    ax.legend(fontsize=8)
    return ax


def plot_fit(points: FloatArray, result: FitResult, ax=None, title: str | None = None):
    """Fig. 6: the final polygons over the raw points, vertices marked, outliers in black."""
    n_v = result.n_vertices
    ax = _axes(ax, title or f"{result.n_points} points -> {n_v} vertices, "
               f"max error {result.max_error:.3g} (tolerance {result.tolerance:.3g})")
    _contours_over_points(ax, points, [(c.vertices, c.closed) for c in result.contours],
                          lw=1.0, marker={"marker": "o", "ms": 3, "mfc": "white"})
    if len(result.outliers):
        out = points[result.outliers]
        ax.plot(out[:, 0], out[:, 1], ".", ms=3, color="k", zorder=4)
    return ax


def plot_mscs(points: FloatArray, mscs_by_level: dict[int, list[FloatArray]], closed: bool,
              ax=None, title: str | None = None):
    """Fig. 3-4: the multi-storable coefficient runs found at each level, one colour per level."""
    ax = _axes(ax, title or "MSCs per level")
    ax.plot(points[:, 0], points[:, 1], ".", ms=1, color="0.75")
    for k, (level, runs) in enumerate(sorted(mscs_by_level.items())):
        colour = _COLOURS[k % len(_COLOURS)]
        for j, run in enumerate(runs):
            ax.plot(run[:, 0], run[:, 1], "-o", ms=3, lw=1.5, color=colour,
                    label=f"level {level}: {len(runs)} MSCs" if j == 0 else None)
    ax.legend(fontsize=8)
    return ax


def plot_layer_model(result: SliceResult, max_layers: int = 400):
    """Fig. 7e: the layer model in 3D, each layer's contours drawn at its bottom and top."""
    fig = Figure(figsize=(8, 8))
    ax = fig.add_subplot(projection="3d")
    step = max(1, len(result.layers) // max_layers)
    cmap = matplotlib.colormaps["viridis"]
    for k, layer in enumerate(result.layers[::step]):
        colour = cmap(k * step / max(1, len(result.layers) - 1))
        for c in layer.fit.contours:
            xy = _closed(c.vertices, c.closed)
            for h in (layer.bottom, layer.top):
                xyz = result.to_world(xy, h)
                ax.plot(xyz[:, 0], xyz[:, 1], xyz[:, 2], lw=0.6, color=colour)
    ax.set_title(f"{len(result.layers)} layers, {result.n_vertices} vertices, model error "
                 f"{result.model_error:.3g} (tolerance {result.tolerance:.3g})", fontsize=10)
    _equal_3d(ax, result)
    return ax


def _equal_3d(ax, result: SliceResult) -> None:
    pts = [result.to_world(c.vertices, la.z) for la in result.layers for c in la.fit.contours]
    if pts:
        allp = np.concatenate(pts)
        ax.set_box_aspect(np.maximum(np.ptp(allp, axis=0), 1e-12))


def plot_contact_sheet(result: SliceResult, max_panels: int = 36):
    """Each layer's 2D fit in a grid (every n-th layer when there are more than ``max_panels``)."""
    picks = np.unique(np.linspace(0, len(result.layers) - 1,
                                  min(max_panels, len(result.layers))).astype(int))
    cols = int(np.ceil(np.sqrt(len(picks))))
    rows = int(np.ceil(len(picks) / cols))
    fig = Figure(figsize=(2.5 * cols, 2.5 * rows))
    axes = fig.subplots(rows, cols, squeeze=False)
    for ax in axes.ravel():
        ax.set_axis_off()
    for ax, k in zip(axes.ravel(), picks):
        layer = result.layers[k]
        ax.set_aspect("equal")
        for j, c in enumerate(layer.fit.contours):
            xy = _closed(c.vertices, c.closed)
            ax.plot(xy[:, 0], xy[:, 1], "-", lw=0.8, color=_COLOURS[j % len(_COLOURS)])
        ax.set_title(f"{k}: z {layer.z:.4g}, {layer.fit.n_vertices} v", fontsize=7)
    return fig


def save_figure(ax_or_fig, path: str | Path, dpi: int = 150) -> None:
    """Write the figure of ``ax_or_fig`` to ``path`` (format from the extension)."""
    fig = ax_or_fig if hasattr(ax_or_fig, "savefig") else ax_or_fig.figure
    suffix = Path(path).suffix.lstrip(".") or "png"
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=dpi, bbox_inches="tight", format=suffix)
