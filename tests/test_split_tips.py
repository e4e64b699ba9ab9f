"""A slit's or a thin limb's tip that the march closed as a ring of its own is joined back to
its outline (`wavepoly.ordering.split_tips`); a thin ring beside a smooth wall is left apart."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

import wavepoly
from wavepoly.ordering.split_tips import rejoin_split_tips
from wavepoly.types import OrderedContour

from .conftest import distance_to_output
from .truth import independent_problems

RADIUS = 0.05
W = 0.8 * RADIUS  # half-width of the wide part, where the march followed each wall
T = 0.4 * RADIUS  # half-width of the tip, whose walls it followed as one chain


def _ring(polygon: shapely.Polygon, first: int) -> OrderedContour:
    xy = np.asarray(shapely.segmentize(polygon, RADIUS / 2).exterior.coords)[:-1]
    return OrderedContour(xy, True, np.arange(first, first + len(xy)))


def _box(x0, x1, y0, y1):
    return shapely.box(x0, y0, x1, y1)


def _joined(body: shapely.Polygon, tip: shapely.Polygon):
    """The contours with the tip rejoined, asserted one valid closed ring, and its polygon."""
    out = rejoin_split_tips([_ring(body, 0), _ring(tip, 1000)], RADIUS)
    assert len(out) == 1 and out[0].closed
    polygon = shapely.Polygon(out[0].points)
    assert polygon.is_valid
    return out, polygon


def test_a_limb_tip_closed_apart_is_joined_to_its_outline():
    body = shapely.union(_box(-1, 1, -0.5, 0.5), _box(0.9, 1.3, -W, W))
    tip = _box(1.33, 1.6, -T, T)
    out, polygon = _joined(body, tip)
    assert polygon.covers(shapely.Point(1.59, 0.0)) and polygon.covers(shapely.Point(0.0, 0.0))
    assert len(out[0].members) == len(_ring(body, 0).members) + len(_ring(tip, 0).members)


@pytest.mark.parametrize("walls", [True, False])
def test_a_tip_beyond_a_wide_gap_joins_only_where_the_walls_run_across(walls):
    """A tip 2 radii beyond the hairpin joins where the limb's walls run on across the gap;
    with nothing between, it is a dot beyond a stroke's end (a '?' at ε 4 % of its height,
    its dot 2.5 radii below the stem), a ring of its own."""
    body = shapely.union(_box(-1, 1, -0.5, 0.5), _box(0.9, 1.3, -W, W))
    tip = _box(1.3 + 2 * RADIUS, 1.6, -T, T)
    x = np.arange(1.3, 1.3 + 2 * RADIUS, RADIUS / 3)
    across = np.vstack([np.column_stack([x, np.full_like(x, side * T)]) for side in (-1, 1)])
    rings, points = _with_points(body, tip, across if walls else np.empty((0, 2)))
    out = rejoin_split_tips(rings, RADIUS, points)
    assert len(out) == (1 if walls else 2) and all(c.closed for c in out)
    assert len(rejoin_split_tips(rings, RADIUS)) == 1  # without the points, not asked


def _folded(ring: OrderedContour) -> OrderedContour:
    """The ring with a fold of no width: its chain runs on along an edge, back, and on again
    (the march's zigzag in a thin part, which leaves the polygon invalid)."""
    xy = ring.points
    k = int(np.argmax(np.linalg.norm(np.diff(xy, axis=0), axis=1)))
    a, b = xy[k], xy[k + 1]
    fold = np.array([a + 0.75 * (b - a), a + 0.5 * (b - a)])
    return OrderedContour(np.vstack([xy[:k + 1], fold, xy[k + 1:]]), True, ring.members)


def test_a_limb_tip_whose_chains_fold_is_joined_to_its_outline():
    body = shapely.union(_box(-1, 1, -0.5, 0.5), _box(0.9, 1.3, -W, W))
    tip = _box(1.33, 1.6, -T, T)
    rings = [_folded(_ring(body, 0)), _folded(_ring(tip, 1000))]
    assert not any(shapely.Polygon(c.points).is_valid for c in rings)
    out = rejoin_split_tips(rings, RADIUS)
    assert len(out) == 1 and out[0].closed
    polygon = shapely.Polygon(out[0].points)
    assert polygon.is_valid and polygon.covers(shapely.Point(1.59, 0.0))


def test_a_slit_tip_closed_apart_is_cut_into_its_outline():
    body = shapely.difference(_box(-1, 1, -0.5, 0.5), _box(0.7, 1.1, -W, W))
    tip = _box(0.4, 0.67, -T, T)
    _, polygon = _joined(body, tip)
    assert not polygon.covers(shapely.Point(0.45, 0.0))  # the slit runs on to its tip
    assert polygon.covers(shapely.Point(0.3, 0.0))


def _with_points(body: shapely.Polygon, hole: shapely.Polygon, walls: np.ndarray
                 ) -> tuple[list[OrderedContour], np.ndarray]:
    """The two rings as the march leaves them, and the input points: each ring's vertices,
    and ``walls``, points of the body's walls that no vertex stands on."""
    rings = [_ring(body, 0), _ring(hole, 1000)]
    points = np.zeros((1000 + len(rings[1].points) + len(walls), 2))
    points[:len(rings[0].points)] = rings[0].points
    points[1000:1000 + len(rings[1].points)] = rings[1].points
    extra = np.arange(1000 + len(rings[1].points), len(points))
    points[extra] = walls
    rings[0] = OrderedContour(rings[0].points, True, np.concatenate([rings[0].members, extra]))
    return rings, points


def _keyhole(gap: float, slit: bool = True, walls: bool = True) -> list[OrderedContour]:
    """A body with a slit in from its right wall to x 0.7 (or none) and a round hole, not
    thin, ``gap`` to the left of where the slit ends; the slit's walls run on to the hole
    (``walls``), its points across the gap, where the march drew no chain."""
    body = _box(-1, 1, -0.5, 0.5)
    if slit:
        body = shapely.difference(body, _box(0.7, 1.1, -W, W))
    hole = shapely.Point(0.7 - gap - 0.15, 0.0).buffer(0.15, 16)
    x = np.arange(0.7 - gap, 0.7, RADIUS / 3)
    across = np.vstack([np.column_stack([x, np.full_like(x, side * W)]) for side in (-1, 1)])
    rings, points = _with_points(body, hole, across if walls else np.empty((0, 2)))
    return rejoin_split_tips(rings, RADIUS, points)


def test_a_slit_that_reaches_a_hole_makes_it_a_keyhole():
    out = _keyhole(0.8 * RADIUS)
    assert len(out) == 1 and out[0].closed
    polygon = shapely.Polygon(out[0].points)
    assert polygon.is_valid
    assert not polygon.covers(shapely.Point(0.55, 0.0))  # the hole is cut out, through the slit
    assert polygon.covers(shapely.Point(-0.5, 0.0))


def test_a_hole_whose_own_slit_end_reaches_the_outline_makes_a_keyhole():
    # the march drew the slit's inner part as the hole's spike, its outer part not at all
    body = _box(-1, 1, -0.5, 0.5)
    spike = shapely.Polygon([(-T, 0.2), (0.0, 0.5 - 0.8 * RADIUS), (T, 0.2)])
    hole = shapely.union(shapely.Point(0.0, 0.0).buffer(0.25, 16), spike)
    y = np.arange(0.5 - 0.8 * RADIUS, 0.5, RADIUS / 3)
    walls = np.vstack([np.column_stack([np.full_like(y, side * T), y]) for side in (-1, 1)])
    rings, points = _with_points(body, hole, walls)
    out = rejoin_split_tips(rings, RADIUS, points)
    assert len(out) == 1 and shapely.Polygon(out[0].points).is_valid
    assert not shapely.Polygon(out[0].points).covers(shapely.Point(0.0, 0.0))


def test_a_hole_short_of_a_slit_or_by_a_smooth_wall_is_left_apart():
    assert len(_keyhole(2 * RADIUS)) == 2  # the slit stops short of the hole
    assert len(_keyhole(0.8 * RADIUS, slit=False)) == 2  # a thin wall, no slit through it
    # a hairpin facing the hole across solid wall (a glyph's neck by its counter)
    assert len(_keyhole(0.8 * RADIUS, walls=False)) == 2
    assert len(rejoin_split_tips(_with_points(_box(-1, 1, -0.5, 0.5).difference(
        _box(0.7, 1.1, -W, W)), shapely.Point(0.51, 0.0).buffer(0.15, 16),
        np.empty((0, 2)))[0], RADIUS)) == 2  # no points: no keyhole


def test_a_thin_ring_beside_a_smooth_wall_is_left_apart():
    body = _box(-1, 1, -0.5, 0.5)
    hole = _box(-0.3, 0.3, 0.5 - 0.8 * RADIUS - 2 * T, 0.5 - 0.8 * RADIUS)
    rings = [_ring(body, 0), _ring(hole, 1000)]
    out = rejoin_split_tips(rings, RADIUS)
    assert len(out) == 2 and all(c.closed for c in out)


def test_a_thin_part_lying_along_an_outline_is_left_apart():
    body = _box(-1, 1, -0.5, 0.5)
    bar = _box(-0.5, 0.5, 0.5 + RADIUS, 0.5 + RADIUS + 2 * T)
    out = rejoin_split_tips([_ring(body, 0), _ring(bar, 1000)], RADIUS)
    assert len(out) == 2 and all(c.closed for c in out)


def test_a_thin_hole_running_in_from_near_a_wall_is_left_apart():
    # f3's small ring lies a radius inside its outline's wall (2.3 tolerances in the truth):
    # a hole of its own, not a slit whose mouth the march closed across
    body = _box(-1, 1, -0.5, 0.5)
    hole = shapely.Polygon([(-0.2, -0.5 + RADIUS), (-0.2 + 0.6 * RADIUS, -0.5 + RADIUS),
                            (0.1, -0.2), (0.1 - 0.6 * RADIUS, -0.2)])
    out = rejoin_split_tips([_ring(body, 0), _ring(hole, 1000)], RADIUS)
    assert len(out) == 2 and all(c.closed for c in out)


@pytest.mark.parametrize(("row", "seed"), [(4, 35), (3, 75), (0, 107)])
def test_a_silhouette_split_into_rings_comes_out_whole(row, seed):
    """Silhouette 35 traced from a 200-pixel bitmap, with noise: a limb 2 radii wide that the
    march closed as three rings (body, middle, tip), the middle one folding on itself.
    Silhouettes 75 (a 300-pixel bitmap) and 107 (exact): a slit that reaches a hole, a
    keyhole, which came out as an outline with a notch and a hole beside it."""
    from benchmarks.bench_validity import SILHOUETTE_SAMPLINGS
    from benchmarks.silhouettes import bitmap, sample, silhouette

    pixels, n, eps, noise = SILHOUETTE_SAMPLINGS[row]
    rings = silhouette(seed) if pixels is None else bitmap(silhouette(seed), pixels)
    pts = sample(rings, n, noise * eps, 1000 + seed)
    result = wavepoly.fit(pts, eps)
    assert [c.closed for c in result.contours] == [True] * len(rings)
    assert independent_problems(result) == []
    assert len(result.outliers) == 0
    assert distance_to_output(pts, result).max() <= eps * (1 + 1e-9)
