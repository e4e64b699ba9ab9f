"""An outline left open across a gap its points fill closes (`wavepoly.ordering.gaps`); a
stroke whose ends face across an empty gap stays open."""

from __future__ import annotations

import numpy as np
import shapely

from wavepoly.ordering.gaps import close_gaps
from wavepoly.types import OrderedContour

RADIUS = 0.03


def _circle(n: int = 600, start: float = 0.0, stop: float = 2 * np.pi) -> np.ndarray:
    t = np.linspace(start, stop, n, endpoint=False)
    return np.column_stack([np.cos(t), np.sin(t)])


def test_a_ring_left_open_over_its_own_points_closes():
    pts = _circle()
    piece = OrderedContour(pts[3:-9:6], False, np.arange(600))
    out = close_gaps([piece], pts, RADIUS)
    assert [c.closed for c in out] == [True]
    assert shapely.Polygon(out[0].points).is_valid


def test_a_gap_without_points_stays_open():
    pts = _circle()[:-12]  # the points stop where the piece does: a C
    piece = OrderedContour(pts[::6], False, np.arange(len(pts)))
    assert [c.closed for c in close_gaps([piece], pts, RADIUS)] == [False]


def test_a_gap_closing_across_another_contour_stays_open():
    pts = _circle()
    piece = OrderedContour(pts[3:-9:6], False, np.arange(600))
    across = OrderedContour(np.array([[0.95, -0.2], [1.05, 0.2]]), False, np.arange(0))
    out = close_gaps([piece, across], pts, RADIUS)
    assert [c.closed for c in out] == [False, False]



def test_a_ring_left_open_ten_radii_short_over_its_own_points_closes():
    # at a bitmap's tail of one-pixel spurs the march stops some 10 radii short
    pts = _circle()
    piece = OrderedContour(pts[12:-12:6], False, np.arange(600))
    gap = np.linalg.norm(piece.points[0] - piece.points[-1])
    assert 10 * RADIUS < gap < 11 * RADIUS
    out = close_gaps([piece], pts, RADIUS)
    assert [c.closed for c in out] == [True]
    assert shapely.Polygon(out[0].points).is_valid


def test_a_ring_left_open_fourteen_radii_short_over_its_own_points_closes():
    # where a noisy limb's walls merged the march stopped 12.4 radii short of its start
    pts = _circle()
    piece = OrderedContour(pts[18:-18:6], False, np.arange(600))
    gap = np.linalg.norm(piece.points[0] - piece.points[-1])
    assert 14 * RADIUS < gap < 15 * RADIUS
    assert [c.closed for c in close_gaps([piece], pts, RADIUS)] == [True]


def test_a_gap_that_cuts_the_outline_a_radius_deep_closes():
    # the straight gap runs up to 1.05 radii from the arc it cuts across (the horse's tail)
    pts = _circle()
    piece = OrderedContour(pts[24:577:6], False, np.arange(600))
    a, b = piece.points[0], piece.points[-1]
    assert 16 * RADIUS < np.linalg.norm(a - b) < 17 * RADIUS
    depth = 1 - np.linalg.norm((a + b) / 2)
    assert RADIUS < depth < 1.1 * RADIUS
    assert [c.closed for c in close_gaps([piece], pts, RADIUS)] == [True]
