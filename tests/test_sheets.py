"""Thin walls: a neighbourhood across both faces of a wall is fitted to the point's own face."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from wavepoly.sheets import SHEET_POINTS, own_principal, own_sheet, principal


def _neighbourhood(rng, heights_of, noise, k=24, radius=1.0):
    """``k`` points on a disc of ``radius`` in (x, y), each at height ``heights_of(x, y,
    face)`` for a face drawn at random plus Gaussian ``noise``, the first point at the disc's
    centre; returns the (1, k, 3) neighbourhood about its centroid, its principal variances
    and axes, and the faces."""
    r, t = radius * np.sqrt(rng.uniform(0, 1, k)), rng.uniform(0, 2 * np.pi, k)
    x, y = r * np.cos(t), r * np.sin(t)
    x[0] = y[0] = 0.0
    face = rng.integers(0, 2, k)
    pts = np.column_stack([x, y, heights_of(x, y, face) + rng.normal(scale=noise, size=k)])
    _, centred, values, axes = principal(pts[None])
    return centred, (values, axes), face


def test_two_parallel_faces_are_told_apart():
    """A wall a third of the neighbourhood's radius thick, tilted: each point is fitted to the
    points of its own face, whose normal is the faces' own."""
    tilt = np.array([0.3, -0.2])
    for seed in range(20):
        rng = np.random.default_rng(seed)
        centred, pca, face = _neighbourhood(
            rng, lambda x, y, f: tilt[0] * x + tilt[1] * y + 0.3 * f, 0.005)
        if min(np.bincount(face, minlength=2)) < SHEET_POINTS:
            continue
        weight = own_sheet(centred, *pca)
        assert np.array_equal(weight[0] > 0, face == face[0])
        _, _, _, axes, _ = own_principal(centred)
        truth = np.array([-tilt[0], -tilt[1], 1.0]) / np.linalg.norm([*tilt, 1.0])
        assert abs(axes[0, :, 0] @ truth) > np.cos(np.radians(3))


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 10**6), noise=st.floats(0.001, 0.3), curve=st.floats(-0.5, 0.5))
def test_one_face_is_never_split(seed, noise, curve):
    """A single face, flat or curved, with any noise: every point is kept."""
    rng = np.random.default_rng(seed)
    centred, pca, _ = _neighbourhood(rng, lambda x, y, f: curve * x * x, noise)
    weight = own_sheet(centred, *pca)
    assert weight.min() == 1.0


def test_a_wedges_converging_faces_are_not_split():
    """The faces of a wedge 20 degrees across, two radii from its edge: two sharp groups of
    heights (13 of these 40 neighbourhoods are split without the faces' parallel test), but not
    a wall of even thickness."""
    slope = np.tan(np.radians(10))
    for seed in range(40):
        rng = np.random.default_rng(seed)
        centred, pca, _ = _neighbourhood(
            rng, lambda x, y, f: np.where(f == 1, 1, -1) * slope * (x + 2), 0.003)
        weight = own_sheet(centred, *pca)
        assert weight.min() == 1.0
