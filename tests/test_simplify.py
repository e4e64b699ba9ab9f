"""The fewest-vertex selection (Imai-Iri over Chan-Chin's cone test) against brute force."""

from __future__ import annotations

from itertools import combinations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wavepoly.simplify import (
    edge_of,
    feasible_chords,
    own_edge_distance,
    select_vertices,
    shortest_path,
)


def test_shortest_path_honours_min_edges():
    # 0 -> 4 is a single feasible chord, but a closed polygon needs at least three edges
    feasible = [np.ones(4 - a, bool) for a in range(4)] + [np.zeros(0, bool)]
    assert shortest_path(feasible, 0, 4).tolist() == [0, 4]
    path = shortest_path(feasible, 0, 4, min_edges=3)
    assert len(path) == 4 and path[0] == 0 and path[-1] == 4
    assert np.all(np.diff(path) > 0)
    with pytest.raises(ValueError, match="over 5 vertices"):
        shortest_path(feasible, 0, 5)  # past the last vertex: refused, not read out of bounds


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


def test_edge_of_follows_the_own_edge_rule():
    """A point at a vertex's parameter belongs to the edge that starts there."""
    vparams = np.array([0.0, 0.25, 0.5, 0.75])
    params = np.array([0.0, 0.1, 0.25, 0.74, 0.75, 0.99])
    assert edge_of(vparams, params, closed=True).tolist() == [0, 0, 1, 2, 3, 3]
    assert edge_of(vparams, params, closed=False).tolist() == [0, 0, 1, 2, 2, 2]


@settings(max_examples=40, deadline=None)
@given(st.integers(3, 12), st.integers(0, 10**6), st.floats(0.02, 0.8))
def test_feasible_chords_match_brute_force(n, seed, tol):
    """Chord (a, b) is feasible exactly when every point between them is within tol of it."""
    rng = np.random.default_rng(seed)
    vertices = np.cumsum(rng.normal(size=(n, 2)) * [1.0, 0.5] + [1.0, 0.0], axis=0)
    u = np.arange(n) / n
    points = vertices[:-1] + rng.uniform(0, 1, (n - 1, 1)) * np.diff(vertices, axis=0)
    points += rng.normal(scale=0.2, size=points.shape)
    params = u[:-1] + rng.uniform(0, 1 / n, n - 1)
    rows = feasible_chords(vertices, u, points, params, tol)
    for a in range(n):
        for b in range(a + 1, n):
            inside = (params >= u[a]) & (params < u[b])
            a_pt, b_pt = vertices[a], vertices[b]
            d = _segment_distance(points[inside], a_pt, b_pt)
            expected = bool(d.max(initial=0.0) <= tol * (1 + 1e-9))
            got = b - a - 1 < len(rows[a]) and bool(rows[a][b - a - 1])
            if abs(d.max(initial=0.0) - tol) > 1e-9:  # away from round-off ties
                assert got == expected, (a, b)


def _segment_distance(p, a, b):
    ab = b - a
    t = np.clip((p - a) @ ab / (ab @ ab), 0.0, 1.0)
    return np.linalg.norm(p - (a + t[:, None] * ab), axis=1)
