"""A closed outline carried out to the group beyond its sharp turn (`wavepoly.ordering.tips`):
a short stroke is a spike's tip, a loop of 4 radii or a long stroke a contour of its own."""

from __future__ import annotations

import numpy as np
import shapely

import wavepoly
from wavepoly.ordering.tips import TIP_OPEN, TIP_STROKE, extend_tips
from wavepoly.types import OrderedContour

from .conftest import distance_to_output
from .truth import independent_problems

RADIUS = 0.05
GAP = 2 * RADIUS
#: A square body with a spike to the right, its tip at (TIP, 0).
TIP = 0.2


def _spike_ring() -> np.ndarray:
    outline = shapely.Polygon([(-1, -0.5), (0, -0.5), (0, -0.1), (TIP, 0), (0, 0.1), (0, 0.5),
                               (-1, 0.5)])
    return np.asarray(shapely.segmentize(outline, RADIUS / 2).exterior.coords)[:-1]


def _stroke(length: float) -> np.ndarray:
    """Points along the spike's bisector, from a radius beyond its tip."""
    x = np.arange(TIP + RADIUS / 2, TIP + RADIUS / 2 + length, RADIUS / 3)
    return np.column_stack([x, np.zeros_like(x)])


def _tips(group: np.ndarray, closed: bool) -> tuple[list[OrderedContour], np.ndarray]:
    ring = _spike_ring()
    pts = np.vstack([ring, group])
    contours = [OrderedContour(ring, True, np.arange(len(ring))),
                OrderedContour(group, closed, np.arange(len(ring), len(pts)))]
    out, outliers = extend_tips(contours, np.array([], dtype=np.intp), pts, RADIUS, GAP)
    assert len(outliers) == 0
    return out, pts


def test_a_stroke_beyond_a_spike_is_its_tip():
    # 8 radii: a spike narrower than the radius whose tip the march left as a stroke
    out, pts = _tips(_stroke(8 * RADIUS), closed=False)
    assert len(out) == 1 and out[0].closed
    assert np.array_equal(out[0].members, np.arange(len(pts)))
    ring = shapely.Polygon(out[0].points)
    assert ring.is_valid
    assert shapely.distance(shapely.points(pts), ring.exterior).max() <= GAP
    assert out[0].points[:, 0].max() == pts[:, 0].max()  # out to the stroke's far end


def test_a_long_stroke_beyond_a_spike_is_a_contour_of_its_own():
    out, _ = _tips(_stroke((TIP_OPEN + 1) * RADIUS), closed=False)
    assert [c.closed for c in out] == [True, False]


def test_a_loop_beyond_a_spike_is_a_contour_of_its_own():
    # a thin loop 5 radii long (a hoof beside a leg's turn): a ring, whatever its shape
    t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    half = (TIP_STROKE + 1) * RADIUS / 2
    loop = np.column_stack([TIP + RADIUS + half * (1 + np.cos(t)), 0.3 * RADIUS * np.sin(t)])
    out, _ = _tips(loop, closed=True)
    assert [c.closed for c in out] == [True, True]


def test_a_small_ring_across_empty_space_beyond_a_spike_is_a_contour_of_its_own():
    # a ring 2 radii across, 2.5 radii beyond the tip with nothing between: no tip of the
    # spike, though small enough to be one, within reach of its turn and covered by it
    t = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    loop = np.column_stack([TIP + 3.5 * RADIUS + RADIUS * np.cos(t), RADIUS * np.sin(t)])
    out, _ = _tips(loop, closed=True)
    assert [c.closed for c in out] == [True, True]
    assert out[0].points[:, 0].max() == TIP


def test_a_silhouette_spike_whose_tip_was_a_stroke_comes_out_closed():
    """Silhouette 58 traced from a 300-pixel bitmap, with noise: a spike 1.5 tolerances wide
    whose tip the march left as a stroke 7 radii long, beyond the turn of an outline closed
    only later by its stems (1 closed and 1 open contour before)."""
    from benchmarks.bench_validity import SILHOUETTE_SAMPLINGS
    from benchmarks.silhouettes import bitmap, sample, silhouette

    pixels, n, eps, noise = SILHOUETTE_SAMPLINGS[3]
    pts = sample(bitmap(silhouette(58), pixels), n, noise * eps, 1058)
    result = wavepoly.fit(pts, eps)
    assert [c.closed for c in result.contours] == [True]
    assert independent_problems(result) == []
    assert len(result.outliers) == 0
    assert distance_to_output(pts, result).max() <= eps * (1 + 1e-9)
