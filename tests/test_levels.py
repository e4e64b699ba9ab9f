"""How deep to decompose (§3, eq. 6-7), and ordered points as level-J control points."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from wavepoly import wavelets
from wavepoly.levels import decompose_contour, finest_level, level_errors, to_control_points


def test_level_errors_by_hand():
    """Eq. 6: the largest distance of the points nearest each segment; eq. 7: over its length."""
    coarse = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 2.0]])
    ordered = np.array([[1.0, 0.3], [2.0, -0.5], [3.0, 0.1], [4.2, 1.0], [3.9, 1.5]])
    errs = level_errors(ordered, coarse, closed=False, level=1)
    np.testing.assert_allclose(errs.shape, [0.5, 0.2])
    np.testing.assert_allclose(errs.relative, [0.5 / 4.0, 0.2 / 2.0])
    assert errs.violates(0.4, 0.1)  # segment 0 breaks both
    assert not errs.violates(0.4, 0.2)  # segment 0 is long enough: its relative error passes
    assert not errs.violates(0.6, 0.0)


def test_level_errors_closed_counts_the_closing_segment():
    coarse = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]])
    ordered = np.array([[1.0, -0.1], [2.05, 1.0], [1.0, 2.2], [-0.3, 1.0]])
    errs = level_errors(ordered, coarse, closed=True, level=2)
    np.testing.assert_allclose(errs.shape, [0.1, 0.05, 0.2, 0.3])


@pytest.mark.parametrize("closed", [False, True])
@pytest.mark.parametrize("n", [3, 5, 17, 64, 100])
def test_control_points_keep_every_ordered_point_and_the_polyline(n, closed):
    """Every ordered point stays a control point, in order, and the polygon is the same line."""
    rng = np.random.default_rng(n)
    pts = np.cumsum(rng.normal(size=(n, 2)), axis=0)
    cp, where = to_control_points(pts, closed)
    level = finest_level(n, closed)
    assert len(cp) == wavelets.n_coefficients(level, closed)
    np.testing.assert_array_equal(cp[where], pts)
    assert np.all(np.diff(where) > 0)
    line = shapely.linearrings(pts) if closed else shapely.linestrings(pts)
    assert shapely.hausdorff_distance(line, shapely.multipoints(cp)) <= (
        np.linalg.norm(np.diff(pts, axis=0), axis=1).max())
    assert np.max(shapely.distance(shapely.points(cp), line)) < 1e-9


def test_finest_level_is_the_smallest_that_holds_the_points():
    for closed in (False, True):
        for n in (4, 9, 33, 1000):
            level = finest_level(n, closed)
            assert wavelets.n_coefficients(level, closed) >= n
            if level - 1 > wavelets.MIN_LEVEL[closed]:
                assert wavelets.n_coefficients(level - 1, closed) < n


def test_decomposition_stops_where_eq_6_and_7_both_break():
    """A square with rounded sampling: a tight tolerance stops early, a loose one goes deep."""
    t = np.linspace(0, 2 * np.pi, 256, endpoint=False)
    ring = np.column_stack([np.cos(t), np.sin(t)]) * (1 + 0.2 * np.cos(4 * t))[:, None]
    tight = decompose_contour(ring, True, 1e-4)
    loose = decompose_contour(ring, True, 0.5)
    assert tight.coarsest > loose.coarsest
    # the level it stopped above violates eq. 6-7; every kept level does not
    for level, errs in tight.errors.items():
        assert not errs.violates(1e-4, 0.05), level
    coarser, _ = wavelets.analyze(tight.coefficients[tight.coarsest], True)
    stop = level_errors(ring, coarser, True, tight.coarsest - 1)
    assert stop.violates(1e-4, 0.05)


def test_no_relative_tolerance_decomposes_to_the_coarsest_level():
    """None (automatic): every level is kept, for the fit to choose the start among them."""
    t = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    ring = np.column_stack([np.cos(t), np.sin(t)])
    pyramid = decompose_contour(ring, True, 1e-6, None)
    assert pyramid.coarsest == wavelets.MIN_LEVEL[True]
    assert set(pyramid.coefficients) == set(range(pyramid.coarsest, pyramid.finest + 1))
