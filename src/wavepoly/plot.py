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
#: Outliers beyond this count are drawn as an even sample of them (the legend says so): a laser
#: map's thousands of stray returns would otherwise hide the walls.
MAX_OUTLIER_DOTS = 1500
#: What "MSC" means, for the figures that show them (§4).
MSC_CAPTION = ("MSC: multi-storable coefficients (eq. 8-10), a run of consecutive control "
               "points of one wavelet level whose curve keeps all its points within the "
               "tolerance; runs are kept from coarse to fine until every point is covered.")


def _axes(ax=None, title: str | None = None, units: str | None = None):
    if ax is None:
        ax = Figure(figsize=(8, 8)).add_subplot()
    ax.set_aspect("equal")
    if title:
        ax.set_title(title, fontsize=10)
    unit = f" ({units})" if units and units != "unitless" else ""
    ax.set_xlabel(f"x{unit}", fontsize=9)
    ax.set_ylabel(f"y{unit}", fontsize=9)
    return ax


def _input_points(ax, points: FloatArray) -> None:
    ax.plot(points[:, 0], points[:, 1], ".", ms=1, color="0.75", zorder=1,
            label=f"input points ({len(points)})")


def _legend(ax, **kw) -> None:
    """A legend whose markers are all of one readable size (the plotted dots are tiny)."""
    legend = ax.legend(fontsize=8, loc=kw.pop("loc", "best"), **kw)
    for handle in legend.legend_handles:
        if hasattr(handle, "set_markersize"):
            handle.set_markersize(LEGEND_MARKER)


#: Size (points) of every marker in a legend.
LEGEND_MARKER = 6


def _outliers(ax, points: FloatArray, outliers) -> None:
    """Outliers small and light, at most `MAX_OUTLIER_DOTS` of them (an even sample)."""
    if not len(outliers):
        return
    shown = np.asarray(outliers)
    label = f"outliers ({len(shown)})"
    if len(shown) > MAX_OUTLIER_DOTS:
        shown = shown[np.linspace(0, len(shown) - 1, MAX_OUTLIER_DOTS).astype(int)]
        label = f"outliers ({len(outliers)}, {MAX_OUTLIER_DOTS} shown)"
    out = points[shown]
    ax.plot(out[:, 0], out[:, 1], ".", ms=2, color="tab:red", alpha=0.45, zorder=4,
            label=label)


def _closed(xy: FloatArray, closed: bool) -> FloatArray:
    return np.vstack([xy, xy[:1]]) if closed and len(xy) else xy


def _contours_over_points(ax, points: FloatArray, polylines: list[tuple[FloatArray, bool]],
                          lw: float, marker: dict) -> None:
    """Raw points in grey, then each polyline in its own colour with its points marked (the
    marker's ``label`` names them in the legend, once)."""
    _input_points(ax, points)
    label = marker.pop("label", None)
    for k, (xy, closed) in enumerate(polylines):
        colour = _COLOURS[k % len(_COLOURS)]
        line = _closed(xy, closed)
        ax.plot(line[:, 0], line[:, 1], "-", lw=lw, color=colour, zorder=2)
        ax.plot(xy[:, 0], xy[:, 1], linestyle="none", color=colour, zorder=3,
                label=label if k == 0 else None, **marker)


def plot_ordering(points: FloatArray, ordering: Ordering, ax=None, title: str | None = None,
                  units: str | None = None):
    """Fig. 1: raw points in grey, each ordered contour in its own colour (its ordered points
    marked, the ends of open ones crossed), outliers small and light."""
    ax = _axes(ax, title or f"{len(points)} points -> {len(ordering.contours)} contours, "
               f"{sum(len(c.points) for c in ordering.contours)} ordered points", units)
    _contours_over_points(ax, points, [(c.points, c.closed) for c in ordering.contours],
                          lw=0.8, marker={"marker": ".", "ms": 2.5,
                                          "label": "ordered points, one colour per contour"})
    ends = [k for k, c in enumerate(ordering.contours) if not c.closed]
    for j, k in enumerate(ends):  # the ends of open contours
        ax.plot(*ordering.contours[k].points[[0, -1]].T, "x", ms=6, zorder=4,
                color=_COLOURS[k % len(_COLOURS)], label="ends of open contours" if not j
                else None)
    _outliers(ax, points, ordering.outliers)
    if len(ordering.merged_walls):
        ax.plot(*ordering.merged_walls.T, "o", mfc="none", color="m", ms=8, zorder=5,
                label="walls that may be merged")
    _legend(ax)
    return ax


def plot_levels(points: FloatArray, fine: FloatArray, coarse: FloatArray, closed: bool,
                labels: tuple[str, str] = ("level k", "level k-1"), ax=None,
                title: str | None = None, units: str | None = None):
    """Fig. 2: a contour's control polygon at two decomposition levels over the raw points,
    the finer thin in blue with dots, the coarser thick in orange with squares."""
    ax = _axes(ax, title, units)
    _input_points(ax, points)
    styles = ({"color": "tab:blue", "lw": 0.8, "marker": ".", "ms": 4, "ls": "-"},
              {"color": "tab:orange", "lw": 1.6, "marker": "s", "ms": 4, "ls": "--",
               "mfc": "white"})
    zoom = ax.inset_axes([1.04, 0.45, 0.55, 0.55])  # the levels apart, where the coarse turns
    for where in (ax, zoom):
        for xy, label, style in zip((fine, coarse), labels, styles):
            xy2 = _closed(xy, closed)
            where.plot(xy2[:, 0], xy2[:, 1], label=f"{label}: {len(xy)} control points",
                       **style)
    zoom.plot(points[:, 0], points[:, 1], ".", ms=1.5, color="0.6", zorder=0)
    centre, half = _sharpest_turn(coarse, closed), ZOOM * float(np.ptp(points, axis=0).max())
    zoom.set_xlim(centre[0] - half, centre[0] + half)
    zoom.set_ylim(centre[1] - half, centre[1] + half)
    zoom.set_aspect("equal")
    zoom.set_xticks([])
    zoom.set_yticks([])
    ax.indicate_inset_zoom(zoom, edgecolor="0.3")
    _legend(ax, loc="upper left")
    return ax


#: Half the width of the zoomed inset of `plot_levels`, as a fraction of the drawing's extent.
ZOOM = 0.05


def _sharpest_turn(xy: FloatArray, closed: bool) -> FloatArray:
    """The vertex of a polygon where its direction turns most (where two levels differ)."""
    if len(xy) < 3:
        return xy.mean(axis=0)
    d = np.diff(_closed(xy, closed), axis=0)
    angle = np.arctan2(d[:, 1], d[:, 0])
    turn = np.abs(np.angle(np.exp(1j * np.diff(np.append(angle, angle[:1]) if closed
                                               else angle))))
    return xy[(int(np.argmax(turn)) + 1) % len(xy)]


def plot_fit(points: FloatArray, result: FitResult, ax=None, title: str | None = None,
             units: str | None = None):
    """Fig. 6: the final polygons over the raw points, vertices marked, outliers small and
    light."""
    n_v = result.n_vertices
    ax = _axes(ax, title or f"{result.n_points} points -> {n_v} vertices, "
               f"max error {result.max_error:.3g} (tolerance {result.tolerance:.3g})", units)
    _contours_over_points(ax, points, [(c.vertices, c.closed) for c in result.contours],
                          lw=1.0, marker={"marker": "o", "ms": 3, "mfc": "white",
                                          "label": "polygon vertices, one colour per contour"})
    _outliers(ax, points, result.outliers)
    _legend(ax)
    return ax


def plot_mscs(points: FloatArray, mscs_by_level: dict[int, list[FloatArray]], closed: bool,
              ax=None, title: str | None = None, units: str | None = None):
    """Fig. 3-4: the multi-storable coefficient runs found at each level, one colour per level,
    with a caption that says what an MSC is (`MSC_CAPTION`)."""
    ax = _axes(ax, title or "MSCs per level", units)
    _input_points(ax, points)
    for k, (level, runs) in enumerate(sorted(mscs_by_level.items())):
        colour = _COLOURS[k % len(_COLOURS)]
        for j, run in enumerate(runs):
            ax.plot(run[:, 0], run[:, 1], "-o", ms=3, lw=1.5, color=colour,
                    label=f"level {level}: {len(runs)} MSCs" if j == 0 else None)
    ax.legend(fontsize=8)
    ax.figure.text(0.02, 0.005, MSC_CAPTION, fontsize=7, wrap=True, va="bottom")
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
