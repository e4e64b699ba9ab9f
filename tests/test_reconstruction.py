"""Reconstruction (eq. 8-10) on hand-checked cases."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wavepoly.parameters import sorted_by_parameter
from wavepoly.reconstruction import storable_mask, storable_runs


def test_storable_mask_by_hand():
    """Eq. 8-9: every point nearest a coefficient must be within tolerance of an adjacent edge."""
    coeffs = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0], [4.0, 0.0]])
    points = np.array([[0.9, 0.05],   # nearest coefficient 1, 0.05 from its edges: fine
                       [2.1, 0.3],    # nearest coefficient 2, 0.3 away: too far
                       [3.0, 0.09]])  # nearest coefficient 3, within 0.1
    mask, owner = storable_mask(points, coeffs, closed=False, tolerance=0.1)
    assert owner.tolist() == [1, 2, 3]
    assert mask.tolist() == [True, True, False, True, True]


def test_storable_runs_open_and_cyclic():
    m = np.array([1, 1, 1, 1, 0, 1, 1, 1, 0, 1, 1], dtype=bool)
    assert [r.tolist() for r in storable_runs(m, closed=False)] == [[0, 1, 2, 3]]
    # cyclic: the run 9, 10, 0, 1, 2, 3 wraps round
    assert [r.tolist() for r in storable_runs(m, closed=True)] == [[9, 10, 0, 1, 2, 3]]
    assert [len(r) for r in storable_runs(np.ones(6, bool), closed=True)] == [6]
    assert storable_runs(np.zeros(5, bool), closed=True) == []


@pytest.mark.parametrize("closed", [False, True])
def test_points_outside_a_corner_get_distinct_ordered_parameters(closed):
    """Regression (bunny slice): points outside a corner all projected onto it; with one shared
    parameter no inserted vertex could separate them and the repair never converged."""
    from wavepoly.levels import decompose_contour
    from wavepoly.parameters import point_parameters

    if closed:
        ordered = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]])
    else:
        ordered = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [2.0, 1.0], [2.0, 2.0]])
    pyramid = decompose_contour(ordered, closed, 0.1)
    angles = np.radians([-80.0, -45.0, -10.0])  # outside the corner (2, 0), towards +y last
    points = np.array([2.0, 0.0]) + 0.05 * np.column_stack([np.cos(angles), np.sin(angles)])
    u = point_parameters(points, pyramid)
    assert len(np.unique(u)) == 3 and np.all(np.diff(u) > 0)
    assert np.ptp(u) < 1e-6


@pytest.mark.parametrize("seed", [7, 11])
def test_no_vertex_overshoots_a_thin_tip(seed):
    """A blade section whose rounded trailing edge has no points (as where the slab's
    neighbourhoods straddle the edge): a coarse B-spline's control points stand outside the
    sharp turn, and one kept as a vertex put a spike 1.5-3 tolerances beyond the tip. The
    tolerance binds both ways: every vertex lies within it of the points."""
    import shapely

    import wavepoly

    rng = np.random.default_rng(seed)
    s = np.linspace(0, 1, 800, endpoint=False)
    x = 10 * np.cos(2 * np.pi * s)
    y = (0.6 * np.sin(2 * np.pi * s) * (1 - 0.95 * np.cos(2 * np.pi * s) ** 16)
         + 0.8 * (1 - (x / 10) ** 2))
    keep = x < 9.5 + rng.uniform(-0.2, 0.2)
    pts = np.column_stack([x, y])[keep] + rng.normal(scale=0.03, size=(keep.sum(), 2))
    res = wavepoly.fit(pts, 0.25)
    assert res.max_error <= 0.25 * (1 + 1e-9)
    cloud = shapely.multipoints(pts)
    for c in res.contours:
        assert shapely.distance(shapely.points(c.vertices), cloud).max() <= 0.25


@pytest.mark.parametrize("text, spacing, noise, closed", [("S", 0.0005, 0.0005, True),
                                                          ("e", 0.0004, 0.002, True),
                                                          ("S", 0.0005, 0.002, False)])
def test_a_dense_contour_gives_the_polygon_of_all_its_points(monkeypatch, text, spacing,
                                                              noise, closed):
    """Many points per ordered point: they are grouped between parameters, sorted by group and
    only each group's hull candidates go to the selection (`DENSE_SAMPLING`); the polygon is
    the one the plain path gives."""
    from scipy.spatial import cKDTree

    import wavepoly.reconstruction as rec
    from wavepoly.geometry import polyline_distance
    from wavepoly.levels import decompose_contour
    from wavepoly.ordering import order_points
    from wavepoly.samples import glyph_outlines, sample_rings

    ring = max(glyph_outlines(text).rings, key=len)
    pts = sample_rings([ring], spacing=spacing, noise=noise, seed=3)
    if not closed:  # an open stretch of the outline: cut out a quarter of it
        along = cKDTree(ring).query(pts)[1]
        pts = pts[along < 0.75 * len(ring)]
    oc = max(order_points(pts, 0.08).contours, key=lambda c: len(c.members))
    assert oc.closed == closed
    members = pts[oc.members]
    assert len(members) >= rec.DENSE_SAMPLING * len(oc.points)
    pyramid = decompose_contour(oc.points, oc.closed, 0.08)
    calls = []
    real_select = rec.select_vertices
    monkeypatch.setattr(rec, "select_vertices",
                        lambda *a, **k: calls.append(len(a[2])) or real_select(*a, **k))
    dense = rec.reconstruct_contour(pyramid, oc.points, members, 0.08)
    monkeypatch.setattr(rec, "DENSE_SAMPLING", np.inf)
    plain = rec.reconstruct_contour(pyramid, oc.points, members, 0.08)
    assert calls[0] < 0.2 * calls[1] and calls[1] == len(members)  # the selection saw fewer
    np.testing.assert_array_equal(dense.vertices, plain.vertices)
    assert dense.max_error == plain.max_error
    assert polyline_distance(members, dense.vertices, closed).max() <= 0.08 * (1 + 1e-9)


def test_a_thinning_that_drops_hull_points_still_keeps_the_tolerance(monkeypatch):
    """The selection's polygon is verified on every point: a thinning that dropped hull
    vertices (forced here) leaves the verified repaired polygon, never a polygon that misses
    a point."""
    import wavepoly.reconstruction as rec
    from wavepoly import parameters
    from wavepoly.geometry import polyline_distance
    from wavepoly.levels import decompose_contour
    from wavepoly.ordering import order_points
    from wavepoly.samples import glyph_outlines, sample_rings

    pts = sample_rings(glyph_outlines("O").rings[:1], spacing=0.0005, noise=0.003, seed=1)
    oc = order_points(pts, 0.08).contours[0]
    members = pts[oc.members]
    pyramid = decompose_contour(oc.points, oc.closed, 0.08)
    monkeypatch.setattr(parameters, "group_hull_candidates",
                        lambda p, g, a: np.arange(len(p)) % 50 == 0)  # not the hull
    result = rec.reconstruct_contour(pyramid, oc.points, members, 0.08)
    assert polyline_distance(members, result.vertices, True).max() <= 0.08 * (1 + 1e-9)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 40), st.integers(1, 60)), min_size=1, max_size=12),
       st.booleans())
def test_spread_ties_stay_sorted(runs, closed):
    """Runs of equal parameters (duplicate points at a corner of a laser map) are spread by
    the step and stay sorted and distinct, even where a run spreads past the next value
    (the repair's edge search assumes sorted parameters; unsorted, it found no point in an
    edge that held one beyond the tolerance and failed)."""
    step = 1e-3
    values = np.sort(np.array([0.5 + k * 0.7 * step for k, _ in runs]))
    raw = np.repeat(values, [n for _, n in runs])[::-1].copy()
    order, params = sorted_by_parameter(raw, step, closed)
    assert (np.diff(params) > 0).all()
    assert np.abs(params - raw[order]).max() <= step * len(raw)
