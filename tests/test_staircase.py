"""The staircase error (Wu et al. 2004) against a reference made of shapely's own distances."""

from __future__ import annotations

import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from wavepoly.geometry import segments_distance
from wavepoly.staircase import region, slab_errors, walls
from wavepoly.types import Contour


def blob(rng, centre, radius, n):
    """A star-shaped closed contour (simple by construction)."""
    t = np.sort(rng.uniform(0, 2 * np.pi, n))
    r = radius * rng.uniform(0.6, 1.0, n)
    return Contour(np.column_stack([centre[0] + r * np.cos(t), centre[1] + r * np.sin(t)]),
                   True)


def reference(uvh, bottom, top, own, below, above):
    """The same surfaces, measured with shapely.distance."""
    pts = shapely.points(uvh[:, :2])

    def to(geom):
        return (np.full(len(uvh), np.inf) if shapely.is_empty(geom)
                else shapely.distance(pts, geom))

    err = to(walls(own))
    for other, dz in ((above, top - uvh[:, 2]), (below, uvh[:, 2] - bottom)):
        exposed = region(own) if other is None else shapely.symmetric_difference(
            region(own), region(other))
        err = np.minimum(err, np.hypot(dz, to(exposed)))
        if other is not None:
            err = np.minimum(err, np.hypot(dz, to(walls(other))))
    return err


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 10_000), st.integers(3, 80))
def test_slab_errors_match_shapely_distances(seed, vertices):
    rng = np.random.default_rng(seed)
    own = [blob(rng, (0, 0), 5, vertices), blob(rng, (0.5, 0.2), 1.5, 12)]
    below = [blob(rng, (0.3, 0), 5.5, vertices)]
    above = [blob(rng, (-0.2, 0.1), 4, 7), Contour(rng.uniform(-6, 6, (5, 2)), False)]
    uvh = np.column_stack([rng.uniform(-8, 8, (3000, 2)), rng.uniform(0, 1, 3000)])
    for b, a in ((below, above), (None, above), (below, None)):
        got = slab_errors(uvh, 0.0, 1.0, own, b, a)
        np.testing.assert_allclose(got, reference(uvh, 0.0, 1.0, own, b, a), atol=1e-12)


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 10_000), st.integers(1, 300))
def test_segment_distances_match_shapely(seed, count):
    rng = np.random.default_rng(seed)
    a = rng.uniform(-10, 10, (count, 2))
    b = a + rng.normal(scale=rng.uniform(0.01, 5), size=(count, 2))
    pts = rng.uniform(-15, 15, (2000, 2))
    lines = shapely.multilinestrings(list(np.stack([a, b], axis=1)))
    want = shapely.distance(shapely.points(pts), lines)
    np.testing.assert_allclose(segments_distance(pts, a, b), want, atol=1e-12)
    limit = np.median(want)
    got = segments_distance(pts, a, b, limit=limit)
    near = want < limit
    np.testing.assert_allclose(got[near], want[near], atol=1e-12)
    assert np.all(got[~near] >= limit - 1e-12)


def test_a_point_deep_in_a_stack_of_thin_layers_is_measured_to_the_whole_stack():
    """Ten layers of one 100 x 100 square, 1 thick: a point at the middle of the stack is 4.5
    from its top face (its own and its neighbours' walls are 50 away); so is the answer of
    the jobs that the pool and the cluster run (`bands.farther_jobs`)."""
    from dataclasses import replace

    from wavepoly.bands import farther_jobs, layer_error_job
    from wavepoly.staircase import layer_errors
    from wavepoly.types import ErrorJob

    square = [Contour(50.0 * np.array([[-1.0, -1], [1, -1], [1, 1], [-1, 1]]), True)]
    bottoms, tops = np.arange(10.0), np.arange(1.0, 11.0)
    contours = [square] * 10
    uvh = np.array([[0.0, 0.0, 5.5]])
    errors = layer_errors(uvh, bottoms, tops, contours)
    assert errors[5] == np.float64(4.5) and errors[0] == 0.0
    jobs = [ErrorJob(uvh if k == 5 else np.empty((0, 3)), bottoms[k], tops[k], square,
                     square if k else None, square if k < 9 else None) for k in range(10)]
    first = [layer_error_job(job) for job in jobs]
    assert first[5] > 40  # the neighbours alone: their walls
    again = farther_jobs(jobs, first, bottoms, tops, contours)
    assert [k for k, _ in again] == [5]
    assert layer_error_job(replace(again[0][1])) == np.float64(4.5)
