"""A limb the march closed across its root joins the body's outline (`wavepoly.ordering.mouths`);
two shapes that only come close stay two rings."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

import wavepoly
from wavepoly.ordering.mouths import join_through_mouths
from wavepoly.types import OrderedContour

from .test_validity import _valid

RADIUS = 0.4
SPACING = 0.05  # between input points along the walls
STEP = 0.25  # between the ordered points along the walls


def _walk(corners: list[tuple[float, float]], step: float) -> np.ndarray:
    """Points every ``step`` along the open polyline through ``corners``."""
    out = []
    for a, b in zip(corners[:-1], corners[1:]):
        a, b = np.asarray(a, float), np.asarray(b, float)
        n = max(int(round(np.linalg.norm(b - a) / step)), 1)
        out.append(a + np.linspace(0, 1, n, endpoint=False)[:, None] * (b - a))
    return np.vstack(out)


def _body_and_limb(root_open: bool, v_cap: bool = False):
    """A 10 x 4 body whose top wall opens, from x 4.6 to 5.4, into a limb 0.8 wide and 4 long
    (``root_open``), or runs on under a limb standing 0.3 above it, closed at its foot.

    The ordered rings are as the march leaves them at a root: the body's ring runs straight
    across the root on one edge (4.5 to 5.5), the limb's ring is capped across it at y 4.3,
    or (``v_cap``) at y 4.6 by two steep edges meeting in a V by the body's wall."""
    top_left = [(0, 0), (10, 0), (10, 4), (5.4, 4)]
    top_right = [(4.6, 4), (0, 4), (0, 0)]
    limb = [(5.4, 4.0 if root_open else 4.3), (5.4, 8), (4.6, 8), (4.6, 4.0 if root_open else 4.3)]
    body_pts = np.vstack([_walk(top_left, SPACING), _walk(top_right + [(0, 0)], SPACING)]
                         if root_open else [_walk([(0, 0), (10, 0), (10, 4), (0, 4), (0, 0)],
                                                  SPACING)])
    limb_pts = _walk(limb if root_open else limb + [limb[0]], SPACING)
    points = np.vstack([body_pts, limb_pts])
    body_ring = np.vstack([_walk([(0, 0), (10, 0), (10, 4), (5.5, 4)], STEP), [(5.5, 4)],
                           _walk([(4.5, 4), (0, 4), (0, 0)], STEP)])
    foot = 4.6 if v_cap else 4.3
    limb_ring = np.vstack([_walk([(5.4, foot), (5.4, 8), (4.6, 8), (4.6, foot)], STEP),
                           [(4.6, foot)], [(5.0, 4.1)] if v_cap else np.empty((0, 2))])
    body = OrderedContour(body_ring, True, np.arange(len(body_pts)))
    limb = OrderedContour(limb_ring, True, len(body_pts) + np.arange(len(limb_pts)))
    return points, [body, limb]


def test_a_limb_closed_across_its_root_joins_the_body():
    points, rings = _body_and_limb(root_open=True)
    out = join_through_mouths(rings, points, RADIUS)
    assert len(out) == 1 and out[0].closed
    polygon = shapely.Polygon(out[0].points)
    assert polygon.is_valid
    assert polygon.contains(shapely.Point(5.0, 6.0))  # the limb is part of the shape
    assert np.array_equal(np.sort(out[0].members), np.arange(len(points)))


def test_a_limb_closed_in_a_v_across_its_root_joins_the_body():
    # neither edge of the V faces the body's wall; the chord across both does
    points, rings = _body_and_limb(root_open=True, v_cap=True)
    out = join_through_mouths(rings, points, RADIUS)
    assert len(out) == 1 and out[0].closed
    polygon = shapely.Polygon(out[0].points)
    assert polygon.is_valid and polygon.contains(shapely.Point(5.0, 6.0))
    assert not np.any(np.all(out[0].points == [5.0, 4.1], axis=1))  # the V's tip is gone


def test_a_shape_standing_clear_of_a_wall_stays_apart():
    # the body's wall runs on under the limb: points all along the edge the march drew there
    points, rings = _body_and_limb(root_open=False)
    out = join_through_mouths(rings, points, RADIUS)
    assert len(out) == 2


@pytest.mark.parametrize(("row", "seed"), [(2, 56), (1, 60)])
def test_a_silhouette_limb_with_a_narrow_root_is_one_outline(row, seed):
    """Silhouette sweep row 2, seed 56 (1000 points, noise ε/4): a limb joins the body through
    a root about 2 tolerances wide, sampled by a few points; the march closed the limb across
    its root and ran the body past it (two closed rings). Row 1, seed 60 (exact, 1000 points):
    the same, the limb's ring closed in a V whose tip sits by the body's wall."""
    from benchmarks.bench_validity import SILHOUETTE_SAMPLINGS
    from benchmarks.silhouettes import sample, silhouette

    pixels, n, eps, noise = SILHOUETTE_SAMPLINGS[row]
    assert pixels is None
    pts = sample(silhouette(seed), n, noise * eps, 1000 + seed)
    result = wavepoly.fit(pts, eps)
    assert [c.closed for c in result.contours] == [True]
    assert len(result.outliers) == 0
    _valid(pts, result)


def _body_and_pocket(depth_below_top: float):
    """A 10 x 4 body with a slot 0.6 wide (1.5 radii) from y 1 up to ``depth_below_top`` under
    its top wall: a notch open at the top (0) or a hole (> 0). The ordered rings are as the
    march leaves a notch whose mouth it closed: the body's ring runs straight across the top,
    the slot's ring is closed 0.3 (0.75 radii) under it, or at the hole's top wall."""
    top = 4.0 - depth_below_top
    if depth_below_top == 0:
        outline = [(0, 0), (10, 0), (10, 4), (5.3, 4), (5.3, 1), (4.7, 1), (4.7, 4), (0, 4),
                   (0, 0)]
        points = _walk(outline, SPACING)
    else:
        slot = [(5.3, top), (5.3, 1), (4.7, 1), (4.7, top), (5.3, top)]
        points = np.vstack([_walk([(0, 0), (10, 0), (10, 4), (0, 4), (0, 0)], SPACING),
                            _walk(slot, SPACING)])
    foot = min(top, 3.7)
    body_ring = _walk([(0, 0), (10, 0), (10, 4), (0, 4), (0, 0)], STEP)
    pocket_ring = _walk([(5.3, foot), (5.3, 1), (4.7, 1), (4.7, foot), (5.3, foot)], STEP)
    body = OrderedContour(body_ring, True, np.arange(len(points)))
    return points, [body, OrderedContour(pocket_ring, True, np.empty(0, dtype=np.intp))]


def test_a_notch_closed_across_its_mouth_joins_the_outline():
    """The ring the march closed inside the notch was a hole where the truth is a notch (the
    slit between scikit-image's horse's ears): it joins the outline through the mouth."""
    points, rings = _body_and_pocket(0.0)
    out = join_through_mouths(rings, points, RADIUS)
    assert len(out) == 1 and out[0].closed
    polygon = shapely.Polygon(out[0].points)
    assert polygon.is_valid
    assert not polygon.contains(shapely.Point(5.0, 2.5))  # the notch is outside the shape
    assert polygon.contains(shapely.Point(3.0, 2.0))
    assert shapely.LinearRing(out[0].points).distance(shapely.Point(5.0, 1.0)) < 0.1


@pytest.mark.parametrize("wall", [0.5, 1.2])
def test_a_thin_hole_with_a_wall_under_the_outline_stays_a_hole(wall):
    # 1.25 radii of wall between the slot's top and the outline, whose points run all along
    # it (no mouth), or 3 radii: a hole, not a notch
    points, rings = _body_and_pocket(wall)
    out = join_through_mouths(rings, points, RADIUS)
    assert len(out) == 2 and all(c.closed for c in out)


def _ring_with_a_small_hole(gap: float, cut: float, seed: int) -> tuple[np.ndarray, float]:
    """The validity benchmark's small hole (`benchmarks.holes.small_hole`: a disk 24 ε across,
    a round hole 4 ε across ``gap`` ε from its wall) sampled every ε / 3 at random with noise
    ε / 8; the disk's points left out over ``cut`` ε of its length beside the hole (a gap a
    random sampling leaves now and then)."""
    from benchmarks.holes import small_hole
    from wavepoly.samples import sample_rings

    eps = 0.1
    pts = sample_rings(small_hole(4.0, gap, 0.0, eps), spacing=eps / 3, noise=eps / 8,
                       seed=seed)
    beside = ((np.abs(np.arctan2(pts[:, 1], pts[:, 0])) < cut / 24)
              & (np.hypot(pts[:, 0], pts[:, 1]) > 11.5 * eps))
    return pts[~beside], eps


@pytest.mark.parametrize("gap, cut, seed", [(1.6, 0.0, 1), (1.6, 2.0, 0), (1.9, 1.5, 1),
                                            (1.9, 2.0, 2), (1.3, 1.5, 1), (1.6, 1.5, 0)])
def test_a_small_round_hole_near_its_outline_stays_a_hole(gap, cut, seed):
    """A ring inside a ring 1.3-1.9 ε from it: the hole, round and a couple of radii across,
    had joined the outline where the outline's points leave a gap beside it, as a notch
    closed off at its mouth (a pocket), or (the last two) as a limb whose cap, two of the
    hole's edges, turned no more than the small ring bends everywhere."""
    pts, eps = _ring_with_a_small_hole(gap, cut, seed)
    result = wavepoly.fit(pts, eps)
    assert [c.closed for c in result.contours] == [True, True]
    assert len(result.outliers) == 0
    outer, hole = sorted((shapely.Polygon(c.vertices) for c in result.contours),
                         key=lambda p: -p.area)
    assert outer.contains(hole) and hole.area > 0.5 * np.pi * (2 * eps) ** 2
    _valid(pts, result)
