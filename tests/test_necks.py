"""A lobe on a narrow neck is one outline, not two rings (`wavepoly.ordering.necks`); two
shapes that only come close stay two."""

from __future__ import annotations

import numpy as np
import shapely

import wavepoly
from wavepoly.geometry import polyline_distance

EPS = 1.0
BODY = 30.0  # the body's radius, in tolerances


def _sampled(shape: shapely.Polygon, noise: float, seed: int) -> np.ndarray:
    """Points every third of a tolerance at random along the outline, with Gaussian noise."""
    ring = shapely.LinearRing(shape.exterior)
    rng = np.random.default_rng(seed)
    at = rng.uniform(0, ring.length, int(3 * ring.length / EPS))
    pts = shapely.get_coordinates(shapely.line_interpolate_point(ring, at))
    return pts + rng.normal(0.0, noise * EPS, pts.shape)


def _lobe_on_a_neck(width: float, length: float, lobe: float) -> shapely.Polygon:
    """A disk with a round lobe joined to it by a neck ``width`` wide and ``length`` long."""
    body = shapely.Point(0, 0).buffer(BODY, 128)
    head = shapely.Point(BODY + length + lobe, 0).buffer(lobe, 64)
    neck = shapely.box(BODY - 1, -width / 2, BODY + length + 1, width / 2)
    return shapely.union_all([body, head, neck])


def test_a_lobe_on_a_neck_narrower_than_the_tolerance_is_one_outline():
    # the march closes the lobe with a spike into the neck and runs the body's outline past
    # its mouth with a bump: two rings, each valid, where the silhouette is one
    shape = _lobe_on_a_neck(0.8, 3.0, 6.0)
    pts = _sampled(shape, 0.0, 0)
    res = wavepoly.fit(pts, EPS)
    assert len(res.contours) == 1 and res.contours[0].closed
    polygon = shapely.Polygon(res.contours[0].vertices)
    assert polygon.is_valid and polygon.contains(shapely.Point(BODY + 9.0, 0.0))
    assert len(res.outliers) == 0
    assert polyline_distance(pts, res.contours[0].vertices, True).max() <= EPS * (1 + 1e-9)


def test_two_disks_a_tolerance_apart_stay_two_rings():
    # no wall runs between them: a link across the gap finds their walls only at its ends
    for seed in range(3):
        shapes = [shapely.Point(0, 0).buffer(BODY, 128),
                  shapely.Point(BODY + 1.0 + 3.0, 0).buffer(3.0, 64)]
        pts = np.vstack([_sampled(s, 0.125, seed) for s in shapes])
        res = wavepoly.fit(pts, EPS)
        assert len(res.contours) == 2 and all(c.closed for c in res.contours)
        assert len(res.outliers) == 0


def test_lobes_on_noisy_necks_are_one_outline():
    # noise a quarter of the tolerance: the neck's walls a band each, 1.2 tolerances apart
    shape = _lobe_on_a_neck(1.2, 3.0, 6.0)
    whole = 0
    for seed in range(6):
        res = wavepoly.fit(_sampled(shape, 0.25, seed), EPS)
        assert res.validity.valid and len(res.outliers) == 0
        whole += [c.closed for c in res.contours] == [True]
    assert whole >= 4


def test_a_densely_sampled_neck_is_read_thinned_and_still_joins():
    # 100 points per tolerance along the outline: the neck's tests read every k-th point
    from wavepoly.ordering.necks import NECK_DENSITY, _stride
    from wavepoly.types import OrderedContour

    shape = _lobe_on_a_neck(0.8, 3.0, 6.0)
    pts = _sampled(shape, 0.0, 0)
    dense = np.vstack([pts + np.random.default_rng(k).normal(0, 0.01, pts.shape)
                       for k in range(33)])
    res = wavepoly.fit(dense, EPS)
    assert [c.closed for c in res.contours] == [True] and res.validity.valid
    ring = OrderedContour(np.asarray(shape.exterior.coords)[:-1], True, np.arange(len(dense)))
    assert _stride([ring], EPS) >= len(dense) / shape.length / NECK_DENSITY > 1


def _walls(*rings: np.ndarray, step: float = 0.2) -> np.ndarray:
    """Points every ``step`` along each closed ring."""
    out = []
    for ring in rings:
        line = shapely.LinearRing(ring)
        at = np.arange(0.0, line.length, step)
        out.append(shapely.get_coordinates(shapely.line_interpolate_point(line, at)))
    return np.vstack(out)


def test_a_neck_away_from_where_the_cores_come_nearest_is_found():
    # the rings come nearest at the top, where nothing lies between them; the neck's two
    # walls run between them at the bottom, 2.5 radii long
    from scipy.spatial import cKDTree

    from wavepoly.ordering.necks import _necked

    body = np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float)
    lobe = np.array([[12.5, 0], [21, 0], [21, 10], [11, 10]], float)
    neck = np.vstack([np.column_stack([np.arange(10.0, 12.6, 0.2), np.full(13, y)])
                      for y in (1.0, 2.0)])
    bare = _walls(body, lobe)
    assert not _necked(body, lobe, cKDTree(bare), 1.0)
    assert _necked(body, lobe, cKDTree(np.vstack([bare, neck])), 1.0)


def test_an_inlet_the_body_closes_over_alone_is_no_enclosed_counter():
    # growing the body closes the mouth of its own bottle-shaped inlet: that hole is not
    # between the two rings; an annulus's two halves, grown, do enclose its middle
    from wavepoly.ordering.necks import _enclose

    body = np.array([[0, 0], [20, 0], [20, 14], [10.5, 14], [10.5, 10], [13, 10], [13, 3],
                     [7, 3], [7, 10], [9.5, 10], [9.5, 14], [0, 14]], float)
    lobe = np.array([[21.5, 3], [25, 3], [25, 7], [21.5, 7]], float)
    assert not _enclose(body, lobe, 1.0)
    t = np.linspace(0, np.pi, 40)
    upper = np.vstack([np.column_stack([np.cos(t), np.sin(t)]) * 10,
                       np.column_stack([np.cos(t[::-1]), np.sin(t[::-1])]) * 9])
    assert _enclose(upper + [0, 0.5], upper * [1, -1] - [0, 0.5], 1.0)
