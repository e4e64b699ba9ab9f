"""Levels (eq. 6-7) and reconstruction (eq. 8-10, selection) on hand-checked cases."""

from __future__ import annotations

from itertools import combinations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wavepoly.levels import level_errors
from wavepoly.reconstruction import storable_mask, storable_runs
from wavepoly.simplify import own_edge_distance, select_vertices, shortest_path


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


def test_shortest_path_honours_min_edges():
    # 0 -> 4 is a single feasible chord, but a closed polygon needs at least three edges
    feasible = [np.ones(4 - a, bool) for a in range(4)] + [np.zeros(0, bool)]
    assert shortest_path(feasible, 0, 4).tolist() == [0, 4]
    path = shortest_path(feasible, 0, 4, min_edges=3)
    assert len(path) == 4 and path[0] == 0 and path[-1] == 4
    assert np.all(np.diff(path) > 0)


def _brute_force_fewest(vertices, vparams, points, params, closed, tol):
    """Fewest vertices, by trying every subset, whose own-edge distance stays within tol."""
    k = len(vertices)
    for size in range(3 if closed else 2, k + 1):
        pool = range(k) if closed else range(1, k - 1)
        extra = size if closed else size - 2
        for combo in combinations(pool, extra):
            keep = list(combo) if closed else [0, *combo, k - 1]
            d = own_edge_distance(vertices[keep], vparams[keep], points, params, closed)
            if d.max() <= tol * (1 + 1e-9):
                return size
    return k


@st.composite
def wiggly_polyline(draw):
    k = draw(st.integers(5, 10))
    closed = draw(st.booleans())
    seed = draw(st.integers(0, 10**6))
    rng = np.random.default_rng(seed)
    if closed:
        t = np.sort(rng.uniform(0, 2 * np.pi, k))
        r = 1 + 0.3 * rng.uniform(-1, 1, k)
        vertices = np.column_stack([r * np.cos(t), r * np.sin(t)])
        vparams = t / (2 * np.pi)
    else:
        vertices = np.column_stack([np.arange(k), rng.uniform(-0.5, 0.5, k)])
        vparams = np.linspace(0.0, 1.0, k)
    # data points along the polyline's own edges, a little off them; dense enough, sometimes,
    # that the cone test sees only the hull candidates of each gap (`hull_candidates`)
    m = draw(st.sampled_from([60, 3000]))
    e = rng.integers(0, k if closed else k - 1, m)
    f = rng.uniform(0, 1, m)
    a, b = vertices[e], vertices[(e + 1) % k]
    nxt = np.where((e + 1) % k == 0, 1.0, vparams[(e + 1) % k]) if closed else vparams[e + 1]
    params = vparams[e] + f * (nxt - vparams[e])
    points = a + f[:, None] * (b - a) + rng.normal(0, 0.02, (m, 2))
    tol = draw(st.floats(0.05, 0.6))
    tol = max(tol, own_edge_distance(vertices, vparams, points, params, closed).max())
    return vertices, vparams, points, np.mod(params, 1.0) if closed else params, closed, tol


@settings(max_examples=40, deadline=None)
@given(wiggly_polyline())
def test_select_vertices_is_optimal_and_within_tolerance(case):
    vertices, vparams, points, params, closed, tol = case
    chosen, chosen_u = select_vertices(vertices, vparams, points, params, closed, tol)
    assert own_edge_distance(chosen, chosen_u, points, params, closed).max() <= tol * (1 + 1e-9)
    assert len(chosen) == _brute_force_fewest(vertices, vparams, points, params, closed, tol)
    assert len(chosen) >= (3 if closed else 2)


@pytest.mark.parametrize("closed", [True, False])
def test_select_checks_points_at_a_vertex_parameter(closed):
    """A point whose parameter equals a vertex's belongs to the edge that starts there: the
    peak vertex after it must stay, though no other point needs it."""
    vertices = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 1.0], [4.0, 0.0]])
    vparams = np.array([0.0, 0.2, 0.4, 0.6, 0.8])
    points = np.array([[0.5, 0.0], [2.5, 0.5]])  # the second is on edge 2-3, at u = 0.4
    params = np.array([0.1, 0.4])
    chosen, chosen_u = select_vertices(vertices, vparams, points, params, closed, 0.1)
    assert own_edge_distance(chosen, chosen_u, points, params, closed).max() <= 0.1
    assert 0.6 in chosen_u
    # the same among many points on the flat edges (their gaps are thinned to hull candidates)
    rng = np.random.default_rng(0)
    f = rng.uniform(0, 1, 4000)
    flat = np.column_stack([2 * f, rng.uniform(-0.05, 0.05, 4000)])
    many = np.vstack([points, flat])
    many_u = np.concatenate([params, 0.4 * f])
    chosen, chosen_u = select_vertices(vertices, vparams, many, many_u, closed, 0.1)
    assert own_edge_distance(chosen, chosen_u, many, many_u, closed).max() <= 0.1
    assert 0.6 in chosen_u


@pytest.mark.parametrize("closed", [False, True])
def test_points_outside_a_corner_get_distinct_ordered_parameters(closed):
    """Regression (bunny slice): points outside a corner all projected onto it; with one shared
    parameter no inserted vertex could separate them and the repair never converged."""
    from wavepoly.levels import decompose_contour
    from wavepoly.reconstruction import point_parameters

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
