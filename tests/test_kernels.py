"""The compiled kernels against their NumPy references, on random cases."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wavepoly.simplify import Frame, _sweep_cones, _sweep_cones_reference


def noisy_frame(seed: int, n_vertices: int, closed_turns: float):
    """Candidate vertices along a noisy curve and the points between them, by parameter."""
    rng = np.random.default_rng(seed)
    prm = np.sort(rng.uniform(0, 1, 40 * n_vertices))
    t = 2 * np.pi * closed_turns * prm
    pts = np.column_stack([np.cos(t) + 0.3 * np.cos(5 * t), np.sin(t)])
    pts += rng.normal(scale=rng.uniform(0.001, 0.05), size=pts.shape)
    u = np.sort(rng.choice(prm, n_vertices, replace=False))
    tu = 2 * np.pi * closed_turns * u
    v = np.column_stack([np.cos(tu) + 0.3 * np.cos(5 * tu), np.sin(tu)])
    return Frame(v, u, pts, prm)


def true_positions(rows):
    return [np.flatnonzero(r) for r in rows]


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 10_000), st.integers(3, 120), st.floats(0.2, 1.0),
       st.floats(0.005, 0.3), st.sampled_from(["left", "right"]))
def test_the_compiled_cone_sweep_matches_the_numpy_reference(seed, n, turns, limit, side):
    frame = noisy_frame(seed, n, turns)
    rows = np.arange(n)
    span = max(2, n // 2)
    got = _sweep_cones(frame, rows, limit, span, side)
    want = _sweep_cones_reference(frame, rows, limit, span, side)
    assert [list(g) for g in true_positions(got)] == [list(w) for w in true_positions(want)]


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 10_000), st.integers(2, 400), st.booleans(), st.floats(0.0, 3.0))
def test_the_grid_nearest_segment_matches_the_kd_tree_reference(seed, n, closed, spread):
    from wavepoly.geometry import (
        _nearest_segment_kd,
        nearest_segment,
        polyline_segments,
        segment_distance,
    )

    rng = np.random.default_rng(seed)
    t = np.sort(rng.uniform(0, 2 * np.pi, n))
    vertices = np.column_stack([np.cos(t), np.sin(3 * t)]) * rng.uniform(0.1, 100)
    vertices[rng.random(n) < 0.05] *= 3  # long segments too
    points = rng.normal(scale=1 + spread, size=(3000, 2)) * np.abs(vertices).max()
    points[:50] = vertices[rng.integers(0, n, 50)]  # exactly on vertices: ties
    seg, dist = nearest_segment(points, vertices, closed)
    _, ref_dist = _nearest_segment_kd(points, vertices, closed)
    scale = np.abs(vertices).max()
    np.testing.assert_allclose(dist, ref_dist, rtol=1e-12, atol=1e-12 * scale)  # round-off
    a, b = polyline_segments(vertices, closed)
    chosen = segment_distance(points, a[seg], b[seg])  # the same segment, or one as near
    np.testing.assert_allclose(chosen, ref_dist, rtol=1e-12, atol=1e-12 * scale)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 10_000), st.integers(2, 200), st.booleans())
def test_the_compiled_neighbour_distances_match_the_numpy_reference(seed, m, closed):
    from scipy.spatial import cKDTree

    from wavepoly.kernels import neighbour_distances
    from wavepoly.reconstruction import _neighbour_distances

    rng = np.random.default_rng(seed)
    coeffs = np.cumsum(rng.normal(size=(m, 2)), axis=0)
    points = coeffs[rng.integers(0, m, 2000)] + rng.normal(scale=0.5, size=(2000, 2))
    owner = cKDTree(coeffs).query(points)[1]
    got = neighbour_distances(points, owner, coeffs, closed)
    want = _neighbour_distances(points, owner, coeffs, closed)
    for g, w in zip(got, want):
        np.testing.assert_allclose(g, w, rtol=1e-12, atol=1e-12)
        assert np.array_equal(np.isinf(g), np.isinf(w))


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 10_000), st.integers(1, 30), st.floats(0.001, 0.5))
def test_the_compiled_hull_filter_matches_the_numpy_reference(seed, blocks, width):
    from wavepoly.geometry import _STRIP_ANGLES, _thin_blocks
    from wavepoly.kernels import thin_blocks

    rng = np.random.default_rng(seed)
    counts = rng.integers(20, 400, blocks)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.intp)
    ends = starts + counts
    t = np.concatenate([np.sort(rng.uniform(0, 1, c)) for c in counts])
    pts = np.column_stack([t * 10, width * rng.normal(size=len(t))])
    pts = np.round(pts, 3)  # ties among the extremes, as on a scanner's grid
    dirs = np.ascontiguousarray(np.stack([np.cos(_STRIP_ANGLES), np.sin(_STRIP_ANGLES)]))
    index = rng.permutation(len(pts))  # blocks of points listed anywhere
    pts = pts[np.argsort(index)]
    chord = pts[index[ends - 1]] - pts[index[starts]]
    axes = chord / np.hypot(chord[:, 0], chord[:, 1])[:, None]
    want, got = np.ones(len(pts), bool), np.ones(len(pts), bool)
    _thin_blocks(pts, index, starts, ends, axes, dirs, want)
    thin_blocks(pts, index, starts, ends, axes, dirs, got)
    np.testing.assert_array_equal(got, want)
    assert got.sum() < len(pts)


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 10_000), st.integers(0, 300), st.booleans())
def test_the_stepping_search_matches_searchsorted(seed, n, uneven):
    """`nearly_uniform_search` is exact on any sorted grid: even or not, repeated values, and
    values at, between and beyond its ends."""
    from wavepoly.kernels import nearly_uniform_search

    rng = np.random.default_rng(seed)
    grid = np.sort(rng.uniform(0, 1, n) ** (4 if uneven else 1))
    grid = np.round(grid, 2)  # repeats
    values = np.concatenate([rng.uniform(-0.2, 1.2, 500), grid, rng.choice(grid, 50)
                             if n else []])
    left, right = nearly_uniform_search(grid, values)
    np.testing.assert_array_equal(left, np.searchsorted(grid, values, "left"))
    np.testing.assert_array_equal(right, np.searchsorted(grid, values, "right"))


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 10_000), st.integers(1, 2000), st.floats(0.01, 3.0))
def test_the_grid_nearest_site_matches_the_kd_tree(seed, m, limit):
    """`geometry.nearest_site` gives what ``cKDTree.query`` with an upper bound gives."""
    from scipy.spatial import cKDTree

    from wavepoly.geometry import nearest_site

    rng = np.random.default_rng(seed)
    sites = rng.uniform(0, 10, (m, 2))
    points = rng.uniform(-2, 12, (3000, 2))
    dist, index = nearest_site(points, sites, limit)
    want_d, want_i = cKDTree(sites).query(points, distance_upper_bound=limit)
    np.testing.assert_allclose(dist, want_d, rtol=1e-12)
    np.testing.assert_array_equal(index, want_i)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 10_000), st.integers(2, 50), st.booleans())
def test_the_compiled_edge_distances_match_the_numpy_reference(seed, k, closed):
    """`edge_distances` (own-edge distances in one pass) against `geometry.segment_distance`."""
    from wavepoly.geometry import segment_distance
    from wavepoly.kernels import edge_distances

    rng = np.random.default_rng(seed)
    vertices = rng.uniform(0, 10, (k, 2))
    points = rng.uniform(-1, 11, (2000, 2))
    edge = rng.integers(0, k if closed else k - 1, len(points))
    want = segment_distance(points, vertices[edge], vertices[(edge + 1) % k])
    np.testing.assert_array_equal(edge_distances(points, edge, vertices), want)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 10_000), st.integers(1, 400))
def test_sorting_group_by_group_is_the_stable_sort(seed, groups):
    """`order_within_groups` gives ``np.argsort(kind="stable")`` when the groups never decrease
    along the values (ties included)."""
    from wavepoly.kernels import order_within_groups

    rng = np.random.default_rng(seed)
    values = np.round(rng.uniform(0, 1, 5000), 3)  # ties
    group = np.minimum((values * groups).astype(np.intp), groups - 1)
    np.testing.assert_array_equal(order_within_groups(values, group, groups),
                                  np.argsort(values, kind="stable"))


@pytest.mark.parametrize("sites", [np.column_stack([np.linspace(0, 10, 50), np.zeros(50)]),
                                   np.zeros((3, 2)) + 2.0,
                                   np.column_stack([np.zeros(40), np.linspace(0, 1e6, 40)])])
def test_the_site_grid_of_a_degenerate_set_is_bounded(sites):
    """Sites in a line or at one point span no area: the grid's cells are still bounded in
    number (no overflowing cast) and the answers are the tree's."""
    import warnings

    from scipy.spatial import cKDTree

    from wavepoly.geometry import nearest_site

    points = np.random.default_rng(0).uniform(-1, 11, (500, 2))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        dist, _ = nearest_site(points, sites)
    np.testing.assert_allclose(dist, cKDTree(sites).query(points)[0], rtol=1e-12)


@settings(max_examples=80, deadline=None)
@given(st.integers(0, 10_000), st.integers(2, 60), st.floats(0.05, 0.9), st.integers(1, 3))
def test_the_compiled_fewest_edge_path_matches_the_numpy_reference(seed, n, density,
                                                                   min_edges):
    """Random forward chords (ragged rows, as the cone test leaves them), every start."""
    from wavepoly.simplify import _shortest_path_reference, shortest_path

    rng = np.random.default_rng(seed)
    feasible = [rng.random(rng.integers(0, n - a + 1)) < density for a in range(n)]
    for start in range(0, n - 1, max(1, n // 7)):
        try:
            want = _shortest_path_reference(feasible, start, n - 1, min_edges)
        except RuntimeError:
            with pytest.raises(RuntimeError):
                shortest_path(feasible, start, n - 1, min_edges)
            continue
        assert shortest_path(feasible, start, n - 1, min_edges).tolist() == want.tolist()


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 10_000), st.floats(0.0, 0.3), st.floats(0.002, 0.05),
       st.floats(0.05, 1.0))
def test_the_compiled_two_means_matches_the_numpy_reference(seed, gap, noise, share):
    """Two walls ``gap`` apart (one with ``share`` of the other's points), lines through
    random points of them: the compiled sides are the NumPy ones, bit for bit."""
    from wavepoly.ordering.neighbourhoods import cell_atoms
    from wavepoly.ordering.walls import _sides, _sides_reference

    rng = np.random.default_rng(seed)
    n = 3000
    x = rng.uniform(0, 2, n)
    y = np.where(rng.random(n) < share / (1 + share), gap, 0.0) + rng.normal(0, noise, n)
    pts = np.column_stack([x, y])
    atoms = cell_atoms(pts, 0.1)
    centre = pts[rng.choice(n, 50, replace=False)]
    angle = rng.normal(0, 0.2, 50)
    tangent = np.column_stack([np.cos(angle), np.sin(angle)])
    got = _sides(centre, tangent, atoms, 0.15)
    want = _sides_reference(centre, tangent, atoms, 0.15)
    for g, w in zip(got, want):
        np.testing.assert_array_equal(g, w)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 10_000), st.integers(10, 4000), st.floats(0.01, 0.5),
       st.booleans())
def test_the_compiled_neighbourhood_sums_match_the_numpy_reference(seed, n, reach, dense):
    """Centroids and covariances over random neighbourhoods of points or of cell atoms (with
    their own scatter): the compiled sums are the NumPy ones, bit for bit."""
    from wavepoly.ordering.neighbourhoods import _moments_reference, cell_atoms, moments

    rng = np.random.default_rng(seed)
    pts = rng.normal(size=(n, 2)) * [1.0, 0.1]
    atoms = cell_atoms(pts, 0.1, min_per_cell=1.0 if dense else 1e9)
    centres = rng.uniform(-1.5, 1.5, (60, 2))  # some far from every point: empty
    for got, want in zip(moments(centres, atoms, reach), _moments_reference(centres, atoms,
                                                                             reach)):
        np.testing.assert_array_equal(got, want)


def test_sheet_sides_matches_its_numpy_reference():
    """Two faces a wall apart, single noisy faces and curved ones: the compiled split and its
    reference agree on every side and sharpness."""
    from wavepoly.kernels import sheet_sides
    from wavepoly.sheets import SHEET_POINTS, SHEET_ROUNDS, sheet_sides_reference

    rng = np.random.default_rng(4)
    n, k = 400, 24
    xy = rng.uniform(-1, 1, (n, k, 2))
    face = rng.integers(0, 2, (n, k))
    wall = rng.choice([0.0, 0.3, 0.8], n)[:, None]
    z = wall * face + rng.uniform(-0.5, 0.5, (n, 1)) * xy[..., 0] ** 2
    pts = np.concatenate([xy, (z + rng.normal(scale=0.02, size=(n, k)))[..., None]], axis=2)
    centred = pts - pts.mean(axis=1, keepdims=True)
    axes = np.linalg.eigh(np.einsum("nki,nkj->nij", centred, centred))[1]
    starts = np.ascontiguousarray(np.moveaxis(axes[:, :, :2], 2, 1))
    high, sharpness = sheet_sides(centred, starts, SHEET_POINTS, SHEET_ROUNDS)
    ref_high, ref_sharpness = sheet_sides_reference(centred, starts)
    assert np.allclose(sharpness, ref_sharpness, rtol=1e-6)
    # the same two sides (which is "high" follows the sign of an eigenvector)
    assert np.all((high == ref_high).all(axis=1) | (high == ~ref_high).all(axis=1))
