"""The optimal min-# baseline against brute force."""

from __future__ import annotations

from itertools import combinations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wavepoly.baselines import chord_errors, douglas_peucker, feasible_shortcuts, min_vertices
from wavepoly.geometry import segment_distance


def brute_feasible(points, tol):
    n = len(points)
    out = np.zeros((n, n), dtype=bool)
    for i in range(n):
        for j in range(i + 1, n):
            mid = points[i + 1:j]
            out[i, j] = len(mid) == 0 or segment_distance(mid, points[i], points[j]).max() <= tol
    return out


def brute_min(points, tol, closed):
    n = len(points)
    for k in range(2 if not closed else 3, n + 1):
        pool = range(1, n - 1) if not closed else range(n)
        extra = k - 2 if not closed else k
        for combo in combinations(pool, extra):
            ends = ([0], [n - 1]) if not closed else ([], [])
            v = np.array(ends[0] + list(combo) + ends[1])
            if chord_errors(points, v, closed).max() <= tol:
                return k
    return n


@st.composite
def wiggly(draw):
    n = draw(st.integers(4, 11))
    seed = draw(st.integers(0, 10**6))
    rng = np.random.default_rng(seed)
    steps = rng.normal(size=(n, 2)) * [1.0, 0.6] + [1.0, 0.0]
    return np.cumsum(steps, axis=0), draw(st.floats(0.05, 1.0))


@settings(max_examples=60, deadline=None)
@given(wiggly())
def test_feasibility_matches_brute_force(data):
    pts, tol = data
    fast = feasible_shortcuts(pts, tol)
    slow = brute_feasible(pts, tol)
    n = len(pts)
    for i in range(n):
        for j in range(i + 1, n):
            assert fast[i, j - i] == slow[i, j], (i, j)


@settings(max_examples=40, deadline=None)
@given(wiggly())
def test_min_vertices_is_optimal_open(data):
    pts, tol = data
    idx = min_vertices(pts, tol)
    assert idx[0] == 0 and idx[-1] == len(pts) - 1
    assert chord_errors(pts, idx, closed=False).max() <= tol + 1e-12
    assert len(idx) == brute_min(pts, tol, closed=False)


@settings(max_examples=25, deadline=None)
@given(st.integers(5, 9), st.integers(0, 10**6), st.floats(0.05, 0.6))
def test_min_vertices_is_optimal_closed(n, seed, tol):
    rng = np.random.default_rng(seed)
    t = np.sort(rng.uniform(0, 2 * np.pi, n))
    pts = np.column_stack([np.cos(t), np.sin(t)]) * rng.uniform(0.7, 1.3, (n, 1))
    idx = min_vertices(pts, tol, closed=True)
    assert chord_errors(pts, idx, closed=True).max() <= tol + 1e-12
    assert len(idx) == brute_min(pts, tol, closed=True)


def test_douglas_peucker_runs():
    t = np.linspace(0, 2 * np.pi, 500, endpoint=False)
    ring = np.column_stack([np.cos(t), np.sin(t)])
    simple = douglas_peucker(ring, 0.01, closed=True)
    assert 10 < len(simple) < 60


def test_size_limit_of_the_dense_matrix_only():
    """The dense feasibility matrix refuses what would not fit; min_vertices never builds it."""
    with pytest.raises(ValueError, match="O\\(n\\^2\\)"):
        feasible_shortcuts(np.zeros((20000, 2)), 0.1)
    t = np.linspace(0, 2 * np.pi, 3000, endpoint=False)
    ring = np.column_stack([np.cos(t), np.sin(t)])
    idx = min_vertices(ring, 1e-3, closed=True)
    assert chord_errors(ring, idx, closed=True).max() <= 1e-3 * (1 + 1e-9)
    assert 60 <= len(idx) <= 80  # a regular n-gon within 1e-3 of the unit circle needs 71
