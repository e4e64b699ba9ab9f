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


def test_links_are_routed_through_the_walls_between_the_nodes():
    # a neck two radii long between nodes at its mouths' corners: the straight links pass
    # 1.5 radii from its walls; routed, they run along them

    from wavepoly.ordering.neck_routes import routed

    x = np.arange(0.5, 2.6, 0.1)
    walls = np.vstack([np.column_stack([x, np.full_like(x, y)]) for y in (0.5, -0.5)])
    body = np.array([[0.0, -2.0], [-5.0, -2.0], [-5.0, 2.0], [0.0, 2.0]])
    lobe = np.array([[3.0, 2.0], [8.0, 2.0], [8.0, -2.0], [3.0, -2.0]])
    links = ((body[-1], lobe[0]), (lobe[-1], body[0]))
    ring, _ = routed(links, (body, lobe), walls, 1.0)
    top, bottom = ring[np.isclose(ring[:, 1], 0.5)], ring[np.isclose(ring[:, 1], -0.5)]
    assert len(top) + len(bottom) == len(ring) - len(body) - len(lobe)
    assert min(len(top), len(bottom)) >= 4  # about a node every half radius along each
    assert np.all(np.diff(top[:, 0]) > 0) and np.all(np.diff(bottom[:, 0]) < 0)
    assert top[0, 0] < 1 and top[-1, 0] > 2 and bottom[0, 0] > 2 and bottom[-1, 0] < 1
    assert shapely.Polygon(ring).is_valid


def test_a_routed_link_hopping_across_an_empty_gap_is_not_continuous():
    # a wall with a gap of a radius and a half in it (two letters apart): the route crosses
    # it with no point beside; the whole wall is continuous
    from scipy.spatial import cKDTree

    from wavepoly.ordering.neck_routes import continuous

    x = np.arange(0.0, 6.01, 0.3)
    wall = np.column_stack([x, np.zeros_like(x)])
    route = np.array([[0.0, 0.0], [2.0, 0.0], [4.0, 0.0], [6.0, 0.0]])
    assert continuous((route, route), cKDTree(wall), 1.0)
    broken = wall[(x < 2.2) | (x > 3.8)]
    assert not continuous((route, route), cKDTree(broken), 1.0)
    assert not continuous((route, route[::-1] + [0, 1.0]), cKDTree(wall), 1.0)


def test_the_middle_of_the_gap_lies_beyond_the_rings_scatter():
    # noise a quarter of the radius: two walls' noise reaches half a radius into the gap
    from wavepoly.ordering.neck_routes import MID_BAND, MID_SIGMAS, MidGap
    from wavepoly.types import OrderedContour

    square = np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float)
    rings, points = [], []
    for k, shift in enumerate((0.0, 12.0)):
        xy = square + [shift, 0]
        pts = _walls(xy, step=0.1)
        pts += np.random.default_rng(k).normal(0, 0.25, pts.shape)
        rings.append(OrderedContour(xy, True, np.arange(len(pts)) + sum(map(len, points))))
        points.append(pts)
    band = MidGap(tuple(rings), np.vstack(points), 1.0).band
    assert abs(band - MID_SIGMAS * 0.25) < 0.1 and band > MID_BAND
    clean = [OrderedContour(r.points, True, r.members) for r in rings]
    flat = np.vstack([_walls(r.points, step=0.1) for r in rings])
    assert MidGap(tuple(clean), flat, 1.0).band == MID_BAND


def test_necks_longer_than_the_nodes_are_apart_are_drawn_through_their_walls():
    # the straight links could not follow the walls of these narrow necks: on the code
    # before routing, 6 of these 12 came out as two rings
    whole = 0
    for width in (0.5, 0.8):
        shape = _lobe_on_a_neck(width, 6.0, 6.0)
        for seed in range(6):
            res = wavepoly.fit(_sampled(shape, 0.0, seed), EPS)
            assert res.validity.valid and len(res.outliers) == 0
            whole += [c.closed for c in res.contours] == [True]
    assert whole >= 11


def test_a_fins_thin_tip_touching_another_fin_is_no_neck(shared_data):
    # Porpi.svg at diagonal / 150 with noise eps / 8 (the validity benchmark's sampling): the
    # lower fin's tip touches the belly fin's outline. Routed links ran along the tip's walls
    # and cut a single edge of the belly fin's ring, which runs on past the tip: 4 closed.
    from benchmarks.bench_validity import DIAGONAL_PER_TOLERANCE, _sample_shape

    from .truth import diagonal, svg_shape

    shape = svg_shape(shared_data / "curves2d" / "ground_truth_svg" / "Porpi.svg")
    eps = diagonal(shape) / DIAGONAL_PER_TOLERANCE
    res = wavepoly.fit(_sample_shape(shape, eps, 0), eps)
    assert res.validity.valid and sum(c.closed for c in res.contours) >= 5
