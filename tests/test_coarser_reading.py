"""Scans whose density varies across the part: where the clean reading at the tolerance's
radius breaks outlines on the sparse side, the ordering reads the scan again at a radius of
its sparse side's spacing (`wavepoly.ordering.order_points`)."""

import numpy as np
import pytest

import wavepoly
from benchmarks.bench_validity import _one_per_ring
from benchmarks.silhouettes import sample, silhouette, thinned
from wavepoly.ordering import curve_spacing
from wavepoly.ordering.spacing import sparse_side_spacing

from .conftest import assert_rings_drawn, distance_to_output
from .truth import independent_problems

EPS = 1 / 150


def _thinned(rings, floor: float, seed: int) -> np.ndarray:
    """The rings as the sweep's thinned rows sample them: 1000 points at full density."""
    return thinned(rings, 1000, 0.0, floor, seed)


def test_the_sparse_side_spacing_sees_a_thinned_side_and_not_an_even_sampling():
    even, thinned = [], []
    for seed in range(6):
        rings = silhouette(seed)
        pts = sample(rings, 1000, 0.0, seed)
        even.append(sparse_side_spacing(pts) / curve_spacing(pts))
        pts = _thinned(rings, 0.25, seed)
        thinned.append(sparse_side_spacing(pts) / curve_spacing(pts))
    assert max(even) < 1.45 and np.mean(even) < 1.3 < 1.6 < np.mean(thinned)


@pytest.mark.parametrize("seed", [0, 4, 12, 17])
def test_a_silhouette_thinned_to_a_quarter_on_one_side_is_one_closed_outline(seed):
    """Thinned to 25 % across the part, the outline broke into 2-4 open pieces where the
    points are sparsest (20 of 30 silhouettes right before, 28 of 30 now)."""
    rings = silhouette(seed)
    pts = _thinned(rings, 0.25, seed)
    result = wavepoly.fit(pts, EPS)
    assert_rings_drawn(rings, pts, result, EPS)
    assert any("the point spacing varies across the scan" in n for n in result.notes)


def test_an_evenly_sampled_silhouette_is_read_once():
    """An even sampling whose outline closes at the tolerance's radius is not read again."""
    rings = silhouette(3)
    result = wavepoly.fit(sample(rings, 1000, 0.0, 1003), EPS)
    assert all(c.closed for c in result.contours)
    assert not any("varies across" in n for n in result.notes)


@pytest.mark.parametrize("seed", [8, 21, 45])
def test_a_thinned_silhouettes_slit_is_read_against_the_walls_beside_it(seed):
    """Thinned to a quarter across, a slit's merged walls hold twice the points per length of
    the walls beside them but not of the whole outline's densest side; measured against the
    whole, the loop and its tail down the slit stayed open (the sweep's finer row: 46 of 60
    right before, 55 now)."""
    rings = silhouette(seed)
    eps = EPS / 2
    pts = thinned(rings, 3000, eps / 8, 0.25, seed)
    result = wavepoly.fit(pts, eps)
    assert all(c.closed for c in result.contours), [c.closed for c in result.contours]
    assert _one_per_ring(rings, result.contours, eps)
    assert result.validity.valid and independent_problems(result) == []
    assert distance_to_output(pts, result).max() <= eps * (1 + 1e-9)
