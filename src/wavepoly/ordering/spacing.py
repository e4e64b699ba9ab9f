"""How far apart the samples of a scan are: the scale that the ordering's radius must exceed."""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..types import FloatArray

#: The radius must be at least this many point spacings, or one neighbourhood holds too few
#: points along the curve to give a tangent; a smaller radius is widened, with a note.
SPACINGS_PER_RADIUS = 3.0
#: Points probed for a spacing estimate: the median of 20,000 distances is stable to ~1 %.
SPACING_SAMPLE = 20_000
#: Clouds larger than twice this are first estimated from a random subset of this size.
SPACING_SUBSET = 100_000
#: Points closer than this share of the cloud's extent are one sample: a scanner's repeated
#: return, a merged file's copy (float32 coordinates resolve about 6e-8 of it). Counted apart,
#: they halved the spacing measured on a scan given three times over, and 3 of 30 silhouettes
#: came out open that were closed once.
DISTINCT = 1e-7


def median_spacing(points: FloatArray, sample: int = SPACING_SAMPLE, seed: int = 0) -> float:
    """Median nearest-neighbour distance of ``points`` (on a random sample of ``sample``)."""
    return _neighbour_distance(points, 1, sample, seed)


def curve_spacing(points: FloatArray, sample: int = SPACING_SAMPLE, seed: int = 0) -> float:
    """Typical distance between consecutive samples along a curve.

    Half the median distance to the 4th nearest neighbour: exact for evenly spaced samples, and
    unlike the nearest-neighbour distance (the smaller of the two gaps beside a sample, about a
    third of the mean gap for random sampling) it sees the gaps that break a march.
    """
    return 0.5 * _neighbour_distance(points, 4, sample, seed)


def sparse_side_spacing(points: FloatArray, sample: int = SPACING_SAMPLE, seed: int = 0
                        ) -> float:
    """The spacing along the curves where the scan is sparsest: the `SPARSE_QUANTILE` of a
    local spacing smoothed over `SPARSE_NEIGHBOURS` samples (1 / (k / 2) of the distance to
    the k-th neighbour, which spans k / 2 spacings on either side). On a scan whose density
    varies (a turntable's far side, a sampling thinned across the part), it is several times
    `curve_spacing`, the median; on an even sampling a little more than it."""
    k = SPARSE_NEIGHBOURS
    return _neighbour_distance(points, k, sample, seed, SPARSE_QUANTILE) / (k / 2)


#: The sparse side's spacing is smoothed over this many neighbours (a shorter window measures
#: the gaps of random sampling, not the density)...
SPARSE_NEIGHBOURS = 32
#: ... and read at this quantile: the sparsest tenth of the scan.
SPARSE_QUANTILE = 0.9


def spacing_bound(points: FloatArray, seed: int, subset: int = SPACING_SUBSET) -> float:
    """A cheap upper estimate of `curve_spacing` for big clouds, from a random subset.

    Thinning points to a fraction f stretches their spacing by 1/f along a curve and by
    1/sqrt(f) over an area, so the subset's spacing times sqrt(f) is at least the full one.
    """
    if len(points) <= 2 * subset:
        return curve_spacing(points, seed=seed)
    pick = np.random.default_rng(seed).choice(len(points), subset, replace=False)
    return curve_spacing(points[pick], seed=seed) * np.sqrt(subset / len(points))


#: Points probed for `points_per_radius`: its median is stable to a few per cent.
DENSITY_SAMPLE = 2_000


def points_per_radius(points: FloatArray, radius: float, seed: int = 0,
                      subset: int = SPACING_SUBSET, sample: int = DENSITY_SAMPLE) -> float:
    """How many points a curve holds per ``radius`` of its length: half the median number of
    other points within ``radius`` of a sample of them (on clouds larger than ``subset``, of a
    random subset, scaled back up).

    On a clean curve it is about ``radius`` over the spacing along it (`curve_spacing`);
    across a band of noise it counts every point of the band, where the spacing of
    neighbours measures the points per area (the Intel map at 0.085: 35 points per radius,
    against 11 radii over `curve_spacing`).
    """
    points = distinct(points)
    rng = np.random.default_rng(seed)
    share = min(1.0, subset / max(len(points), 1))
    if share < 1.0:
        points = points[rng.choice(len(points), subset, replace=False)]
    if len(points) < 2:
        return 0.0
    probe = points if len(points) <= sample else points[rng.choice(len(points), sample, False)]
    within = cKDTree(points).query_ball_point(probe, radius, return_length=True) - 1
    return float(np.median(within)) / share / 2


def _neighbour_distance(points: FloatArray, k: int, sample: int, seed: int,
                        quantile: float = 0.5) -> float:
    """The ``quantile`` (the median by default) of the distances from a sample of the distinct
    points to their k-th neighbour."""
    points = distinct(points)
    tree = cKDTree(points)
    rng = np.random.default_rng(seed)
    probe = points if len(points) <= sample else points[rng.choice(len(points), sample, False)]
    dist, _ = tree.query(probe, k=min(k + 1, len(points)))
    kth = dist[:, -1][np.isfinite(dist[:, -1]) & (dist[:, -1] > 0)]
    return float(np.quantile(kth, quantile)) if len(kth) else 0.0


def distinct(points: FloatArray) -> FloatArray:
    """The points with those closer than `DISTINCT` x the cloud's extent to one another kept
    once (snapped to a grid of that size, so that repeats count as one sample)."""
    if len(points) < 2:
        return points
    extent = float(np.ptp(points, axis=0).max())
    if extent <= 0:
        return points[:1]
    cells = np.floor((points - points.min(axis=0)) / (DISTINCT * extent)).astype(np.int64)
    span = cells.max(axis=0) + 1
    if np.prod(span.astype(float)) < 2.0**62:  # one key per cell: a flat unique, 5-10 x faster
        _, first = np.unique(np.ravel_multi_index(tuple(cells.T), tuple(span)),
                             return_index=True)
    else:
        _, first = np.unique(cells, axis=0, return_index=True)
    return points[np.sort(first)]
