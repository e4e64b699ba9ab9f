"""The built-in shapes: glyph outlines and scan-like samplings of them."""

from __future__ import annotations

import numpy as np
import shapely

from wavepoly.samples import glyph_outlines, sample_rings


def test_glyph_outlines_have_their_holes_and_height():
    shape = glyph_outlines("B8", height=20.0)
    assert len(shape.rings) == 6 and all(shape.closed)  # B and 8: an outline and 2 holes each
    pts = np.concatenate(shape.rings)
    assert 19.0 < np.ptp(pts[:, 1]) < 21.5
    for ring in shape.rings:
        assert shapely.Polygon(ring).is_valid


def test_corners_of_a_glyph_are_its_sharp_turns():
    corners = glyph_outlines("L").corners()
    assert len(corners) == 6  # an L has six corners, no curve


def test_samples_lie_near_the_rings_with_the_asked_spacing_and_noise():
    shape = glyph_outlines("O", height=10.0)
    pts = sample_rings(shape.rings, spacing=0.01, noise=0.002, seed=4)
    length = sum(shapely.LinearRing(r).length for r in shape.rings)
    assert abs(len(pts) - length / 0.01) < 0.05 * length / 0.01
    lines = shapely.union_all([shapely.LinearRing(r) for r in shape.rings])
    dist = shapely.distance(shapely.points(pts), lines)
    assert 0.0012 < float(np.median(dist)) < 0.0016  # half-normal median: 0.674 sigma
    again = sample_rings(shape.rings, spacing=0.01, noise=0.002, seed=4)
    np.testing.assert_array_equal(pts, again)
