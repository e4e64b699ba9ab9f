"""Small shapes a couple of tolerances apart, as stars in a photograph at a coarse tolerance or
rivets in a slice: the validity benchmark's sweep of specks (`wavepoly.ordering.islands`, and
the joins, tips and junctions that must not reach across the empty space between them).
"""

from __future__ import annotations

import time

import numpy as np
import shapely
from scipy.spatial import cKDTree

import wavepoly
from wavepoly.ordering.islands import ISLAND_POINTS
from wavepoly.ordering.neighbourhoods import point_clusters
from wavepoly.samples import sample_rings, scattered_ellipses

from .common import table
from .silhouettes import shape_distance

#: The sweep: the ellipses' sizes (smallest and largest across, in ε), the noise (in ε), and
#: the images of each: `SPECK_COUNT` ellipses at least `SPECK_CLEARANCE` ε apart in a square
#: `SPECK_BOX` ε wide, sampled every ε / 3 at random.
SPECK_SIZES = ((0.5, 1.5), (1.5, 4.0), (4.0, 8.0))
SPECK_NOISE = (0.0, 0.125, 0.25)
SPECK_SEEDS = 6
SPECK_COUNT = 30
SPECK_CLEARANCE = 2.0
SPECK_BOX = 60.0
#: The tolerance they are fitted at.
SPECK_EPS = 1.0


def specks_sweep(truth) -> str:
    """For each size and noise, fits of `SPECK_SEEDS` images: *right* (every contour closed
    and drawing one ellipse, valid, the points within ε, outliers only in groups too small for
    a polygon), *bridged* (a contour drawing two ellipses), *open*, *outliers* (results with
    outliers in a group of `ISLAND_POINTS` points or more) and *invalid*
    (``truth.independent_problems``); the largest Hausdorff distance to the true outlines."""
    rows = []
    for low, high in SPECK_SIZES:
        for noise in SPECK_NOISE:
            right = bridged = opened = lost = invalid = 0
            shape = 0.0
            t0 = time.perf_counter()
            for seed in range(SPECK_SEEDS):
                rings = scattered_ellipses(SPECK_COUNT, across=(low * SPECK_EPS,
                                                                high * SPECK_EPS),
                                           clearance=SPECK_CLEARANCE * SPECK_EPS,
                                           box=SPECK_BOX * SPECK_EPS, seed=seed)
                pts = sample_rings(rings, spacing=SPECK_EPS / 3, noise=noise * SPECK_EPS,
                                   seed=seed)
                res = wavepoly.fit(pts, SPECK_EPS)
                bad = bool(truth.independent_problems(res))
                bridge = any(len(d) > 1 for d in shapes_drawn(rings, res.contours))
                open_ = any(not c.closed for c in res.contours)
                group = point_clusters(pts, SPECK_EPS)
                out = bool((np.bincount(group) >= ISLAND_POINTS)[group[res.outliers]].any())
                invalid, bridged, opened, lost = (invalid + bad, bridged + bridge,
                                                  opened + open_, lost + out)
                right += not (bad or bridge or open_ or out)
                shape = max(shape, shape_distance(rings, res.contours, SPECK_EPS) / SPECK_EPS)
            rows.append([f"{low:g}-{high:g} ε", f"{noise:g} ε", f"{right}/{SPECK_SEEDS}",
                         bridged, opened, lost, invalid, f"{shape:.2f} ε",
                         time.perf_counter() - t0])
    return ("### Specks\n\n" + f"{SPECK_COUNT} ellipses *size* ε across, at least "
            f"{SPECK_CLEARANCE:g} ε apart in a square {SPECK_BOX:g} ε wide, sampled every ε / 3 "
            "at random with Gaussian noise (`benchmarks/specks.py`), "
            f"{SPECK_SEEDS} images per row: stars in a photograph at a coarse tolerance, "
            "rivets in a slice. *right*: every contour closed and drawing one ellipse, valid, "
            f"outliers only in groups of fewer than {ISLAND_POINTS} points (no polygon); "
            "*bridged*: a contour drawing two ellipses (a line across the empty space between "
            "them); *open*: results with an open piece; *outliers*: results that left a group "
            f"of {ISLAND_POINTS} points or more out; *shape*: the largest Hausdorff distance "
            "between the true and the drawn outlines (a speck left out counts its distance to "
            "the nearest drawn line).\n\n"
            + table(["size", "noise", "right", "bridged", "open", "outliers", "invalid",
                     "shape", "seconds"], rows))


def shapes_drawn(rings: list[np.ndarray], contours) -> list[set[int]]:
    """For each contour, the rings its drawn line runs by: the nearest ring of each spot of
    it, cut every tenth of ε."""
    label = np.repeat(np.arange(len(rings)), [len(r) for r in rings])
    tree = cKDTree(np.vstack(rings))
    drawn = []
    for c in contours:
        v = np.vstack([c.vertices, c.vertices[:1]]) if c.closed else c.vertices
        spots = shapely.get_coordinates(shapely.segmentize(shapely.LineString(v),
                                                           0.1 * SPECK_EPS))
        drawn.append(set(label[tree.query(spots)[1]].tolist()))
    return drawn
