"""Slicing (§5, Fig. 7): layer models of real scans, and a 1M-point cloud."""

from __future__ import annotations

import time

import numpy as np

from wavepoly.slicing import slice_cloud

from .common import SHARED, table


def run() -> str:
    rows = []
    scans = [("bunny_zipper.ply", "y"), ("turbineblade.ply", "z")]
    if not (SHARED / "scans3d").exists():
        return "## Slicing\n\n(shared scans absent: skipped)\n"
    from wavepoly.io import read_points

    for name, axis in scans:
        pts = read_points(SHARED / "scans3d" / name)
        eps = 0.01 * float(np.ptp(pts, axis=0).max())
        for label, kw in (("uniform 1.5 eps", {"layer_thickness": 1.5 * eps}),
                          ("adaptive", {"adaptive": True})):
            rows.append(_row(f"{name} ({label})", pts, eps, axis, kw))
    blade = read_points(SHARED / "scans3d" / "turbineblade.ply")
    eps = 0.01 * float(np.ptp(blade, axis=0).max())
    rng = np.random.default_rng(0)
    for copies in (5, 10):
        big = np.concatenate([blade + rng.normal(0, eps / 10, blade.shape)
                              for _ in range(copies)])
        thickness = float(np.ptp(big[:, 2])) / 150
        rows.append(_row(f"turbine blade x{copies} jittered", big, eps, "z",
                         {"layer_thickness": thickness}))
    return ("## Slicing (§5, Fig. 7)\n\nTolerance 1 % of the part's size (about twice the "
            "point spacing), 2 worker processes. *within*: layers whose every slab point is "
            "within the tolerance of the layer's contours. The goal for 1M points in 100-200 "
            "layers is under 10 s.\n\n"
            + table(["cloud", "points", "layers", "thickness", "contours", "vertices",
                     "within", "seconds"], rows))


def _row(label, pts, eps, axis, kw):
    t0 = time.perf_counter()
    res = slice_cloud(pts, eps, axis=axis, workers=2, **kw)
    dt = time.perf_counter() - t0
    thick = [la.thickness for la in res.layers]
    within = sum(la.model_error <= eps * (1 + 1e-9) for la in res.layers if la.slab_points)
    filled = sum(la.slab_points > 0 for la in res.layers)
    return [label, len(pts), len(res.layers), f"{min(thick):.3g}-{max(thick):.3g}",
            sum(len(la.fit.contours) for la in res.layers), res.n_vertices,
            f"{within}/{filled}", dt]
