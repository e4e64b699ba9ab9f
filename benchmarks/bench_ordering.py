"""Ordering throughput (§2): points per second on glyph scans of growing size and real scans."""

from __future__ import annotations

import numpy as np

from wavepoly.ordering import order_points
from wavepoly.samples import glyph_outlines, sample_rings

from .common import SHARED, best_time, table


def run() -> str:
    rows = []
    rings = glyph_outlines("B8&%").rings
    for spacing in (0.02, 0.005, 0.002, 0.0005):
        pts = sample_rings(rings, spacing=spacing, noise=spacing, seed=0)
        t, res = best_time(lambda pts=pts: order_points(pts, 0.08), repeat=2)
        rows.append([f"glyphs B8&% spacing {spacing}", len(pts), len(res.contours),
                     sum(len(c.points) for c in res.contours), len(res.outliers), t,
                     f"{len(pts) / t / 1e3:.0f}k"])
    intel = SHARED / "lidar2d" / "intel-corrected.log.gz"
    if intel.exists():
        from wavepoly.io import read_points

        pts = read_points(intel)
        t, res = best_time(lambda: order_points(pts, 0.05), repeat=1)
        rows.append(["Intel laser map, r 0.05 m", len(pts), len(res.contours),
                     sum(len(c.points) for c in res.contours), len(res.outliers), t,
                     f"{len(pts) / t / 1e3:.0f}k"])
    text = table(["input", "points", "contours", "ordered", "outliers", "seconds",
                  "points/s"], rows)
    return ("## Ordering (§2)\n\nRadius 0.08 on glyphs 20 units high, noise = spacing. "
            "The goal is 1M points/s; the table says where it stands.\n\n" + text)


if __name__ == "__main__":
    print(run(), np.__version__)
