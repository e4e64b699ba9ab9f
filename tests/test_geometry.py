"""Point-to-polyline distances: the KD-tree shortcut must agree exactly with shapely."""

from __future__ import annotations

import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import ConvexHull

from wavepoly.geometry import farther_than, hull_candidates, nearest_segment, segment_distance


@st.composite
def polyline_and_points(draw):
    """Uneven polylines: random steps, some of them long jumps (gaps, cut corners)."""
    seed = draw(st.integers(0, 2**31 - 1))
    rng = np.random.default_rng(seed)
    n = draw(st.integers(2, 300))
    steps = rng.normal(size=(n, 2)) * rng.choice([0.1, 1.0, 8.0], size=(n, 1), p=[.5, .45, .05])
    vertices = np.cumsum(steps, axis=0)
    spread = draw(st.sampled_from([0.05, 0.5, 5.0]))
    anchors = vertices[rng.integers(0, n, 400)]
    points = anchors + rng.normal(size=anchors.shape) * spread
    return vertices, points, draw(st.booleans()) and n >= 3


@settings(max_examples=60, deadline=None)
@given(polyline_and_points())
def test_nearest_segment_agrees_with_shapely(data):
    vertices, points, closed = data
    seg, dist = nearest_segment(points, vertices, closed)
    geom = shapely.linearrings(vertices) if closed else shapely.linestrings(vertices)
    truth = shapely.distance(shapely.points(points), geom)
    np.testing.assert_allclose(dist, truth, rtol=0, atol=1e-9)
    a = vertices[seg]
    b = vertices[(seg + 1) % len(vertices)]
    np.testing.assert_allclose(segment_distance(points, a, b), dist, rtol=0, atol=1e-12)


@settings(max_examples=40, deadline=None)
@given(polyline_and_points(), st.floats(0.01, 3.0))
def test_farther_than_finds_exactly_the_far_points(data, limit):
    vertices, points, closed = data
    far, seg, dist = farther_than(points, vertices, closed, limit)
    truth = nearest_segment(points, vertices, closed)[1]
    np.testing.assert_array_equal(far, np.flatnonzero(truth > limit))
    np.testing.assert_allclose(dist, truth[far], rtol=0, atol=1e-12)


def test_single_segment_and_single_vertex():
    line = np.array([[0.0, 0.0], [2.0, 0.0]])
    seg, dist = nearest_segment(np.array([[1.0, 1.0], [3.0, 0.0]]), line, False)
    np.testing.assert_array_equal(seg, [0, 0])
    np.testing.assert_allclose(dist, [1.0, 1.0])
    far, _, dist = farther_than(np.array([[0.0, 2.0], [0.1, 0.0]]), line[:1], False, 1.0)
    np.testing.assert_array_equal(far, [0])
    np.testing.assert_allclose(dist, [2.0])


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**31 - 1), st.sampled_from(["strip", 8, 16]),
       st.sampled_from([1e-3, 1.0, 1e4]), st.sampled_from([0.1, 0.002]))
def test_hull_candidates_keep_every_hull_vertex(seed, directions, scale, noise):
    """Thinning a block to its hull candidates keeps each block's convex hull (and, on a noisy
    strip, drops most points); thin, curved strips too, the case the default angles are for."""
    rng = np.random.default_rng(seed)
    n = 3000
    t = np.sort(rng.uniform(0, 50, n))
    points = np.column_stack([t, np.sin(t) + rng.normal(0, noise, n)]) * scale + 7 * scale
    starts = np.unique(np.concatenate([[0], rng.integers(0, n, 40)]))
    angles = None if directions == "strip" else np.arange(directions) * (2 * np.pi / directions)
    keep = hull_candidates(points, starts, angles)
    for b0, b1 in zip(starts, np.append(starts[1:], n)):
        block = points[b0:b1]
        if len(block) >= 3 and np.ptp(block, axis=0).min() > 0:
            assert keep[b0 + ConvexHull(block).vertices].all()
    if noise > 0.05:  # blocks are noisy strips: few hull vertices (a clean arc is all hull)
        assert keep.mean() < 0.5


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**31 - 1), st.integers(1, 60))
def test_group_hull_candidates_keep_every_group_hull_vertex(seed, groups):
    """Groups given by label (points in any order) keep their convex hulls, as blocks do."""
    from wavepoly.geometry import group_hull_candidates

    rng = np.random.default_rng(seed)
    n = 4000
    t = rng.uniform(0, 50, n)
    points = np.column_stack([t, np.sin(t) + rng.normal(0, 0.05, n)])
    group = np.minimum((t / 50 * groups).astype(np.intp), groups - 1)
    axes = np.tile([1.0, 0.0], (groups, 1))
    keep = group_hull_candidates(points, group, axes)
    for g in range(groups):
        idx = np.flatnonzero(group == g)
        if len(idx) >= 3:
            assert keep[idx[ConvexHull(points[idx]).vertices]].all()
    assert keep.mean() < 0.5


def test_turn_backs_count_the_teeth_of_a_zigzag_not_its_corners():
    from wavepoly.geometry import turn_backs

    x = np.arange(11) * 0.05
    shallow = np.column_stack([x, np.where(np.arange(11) % 2, 0.1, 0.0)])  # turns of 127
    steep = np.column_stack([x, np.where(np.arange(11) % 2, 0.2, 0.0)])  # turns of 152
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)  # right angles
    assert turn_backs(steep, False, 0.5) == 9
    assert turn_backs(steep, False, 0.1) == 0  # its edges are longer than that
    assert turn_backs(square, True, 2.0) == 0
    assert turn_backs(shallow, False, 0.5) == 0 and turn_backs(shallow, False, 0.5, turn=120) == 9
