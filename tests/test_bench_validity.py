"""The validity benchmark's ring matching (`benchmarks.bench_validity`): a sweep case is right
by rings only where each ring is drawn by a contour of its own."""

from types import SimpleNamespace

import numpy as np
import shapely

from benchmarks.bench_validity import _free_space_share, _one_per_ring


def _square(x, side=10.0):
    return np.array([[x, 0], [x + side, 0], [x + side, side], [x, side]], float)


def _contour(xy, closed=True):
    return SimpleNamespace(vertices=np.asarray(xy, float), closed=closed)


def test_each_ring_drawn_by_its_own_contour_is_right():
    rings = [_square(0), _square(20), _square(40)]
    assert _one_per_ring(rings, [_contour(r + 0.2) for r in rings], eps=1.0)


def test_a_split_ring_does_not_make_up_for_two_rings_drawn_as_one():
    rings = [_square(0), _square(20), _square(40)]
    union = np.vstack([_square(0, 10)[[0, 1]], _square(20)[[0, 1, 2, 3]], _square(0)[[2, 3]]])
    halves = [_contour(_square(40)[[0, 1, 2]]), _contour(_square(40)[[2, 3, 0]])]
    assert not _one_per_ring(rings, [_contour(union), *halves], eps=1.0)


def test_a_ring_under_four_tolerances_may_merge_into_its_neighbour():
    rings = [_square(0), _square(10.5, side=2.0)]  # a sliver 2.8 ε across beside the first
    assert _one_per_ring(rings, [_contour(_square(0))], eps=1.0)


def test_free_space_is_the_drawn_length_far_from_every_point():
    # points along y = 0 from 0 to 4 and from 6 to 10: a line from 0 to 10 crosses a gap of
    # 2, of which 2 - 2 ε lies farther than ε from both sides
    x = np.concatenate([np.linspace(0, 4, 401), np.linspace(6, 10, 401)])
    pts = np.column_stack([x, np.zeros_like(x)])
    line = _contour([[0.0, 0.0], [10.0, 0.0]], closed=False)
    assert abs(_free_space_share([line], pts, eps=0.5) - 0.1) < 0.01
    assert _free_space_share([_contour([[0.0, 0.0], [4.0, 0.0]], closed=False)], pts, 0.5) == 0


def test_an_unseen_sweep_row_counts_right_and_invalid_results():
    from benchmarks.bench_validity import _truth
    from benchmarks.silhouettes import traced_mask
    from benchmarks.unseen import _row

    mask = np.zeros((60, 60), bool)
    mask[10:50, 10:30] = mask[20:40, 35:50] = True  # two rectangles, 5 pixels apart
    rings = traced_mask(mask)
    assert len(rings) == 2
    name, eps, noise, right, shaped, invalid, _ = _row("two boxes", [rings, rings[:1]], 1.5,
                                                       0.125, _truth(), _one_per_ring)
    assert (right, shaped, invalid) == ("2/2", "2/2", 0)
    # a counter that finds every result wrong counts them so; their shapes are still right
    _, _, _, right, shaped, _, _ = _row("two boxes", [rings], 1.5, 0.125, _truth(),
                                        lambda *a: False)
    assert (right, shaped) == ("0/1", "1/1")


def test_the_shape_distance_sees_an_edge_cut_across_between_spikes():
    from benchmarks.silhouettes import shape_distance, star

    outline = star(5, 0.2)
    assert shape_distance([outline], [_contour(outline)], 0.3) < 1e-9
    # the hull of the star: its vertices all lie on the star, its edges cut across the gaps
    hull = np.asarray(shapely.MultiPoint(outline).convex_hull.exterior.coords)[:-1]
    assert shape_distance([outline], [_contour(hull)], 0.3) > 0.5


def test_a_ring_is_drawn_alone_by_one_closed_contour_of_its_own():
    from benchmarks.silhouettes import drawn_rings
    from benchmarks.unseen import drawn_alone

    rings = [_square(0), _square(20)]
    both = np.vstack([_square(0)[:3], _square(20)[1:]])  # one contour round the two
    cases = [([_contour(_square(0)), _contour(_square(20))], 2),
             ([_contour(_square(0)), _contour(_square(20), closed=False)], 1),
             ([_contour(both)], 0),
             ([_contour(_square(0)), _contour(_square(0) + 0.1)], 0)]  # drawn twice
    for contours, alone in cases:
        draws = drawn_rings(rings, contours, eps=1.0)
        assert drawn_alone(draws, np.array([c.closed for c in contours])) == alone


def test_a_small_hole_comes_its_gap_from_the_disk_wall():
    from benchmarks.holes import small_hole

    disk, hole = (shapely.Polygon(r) for r in small_hole(4.0, 1.5, 30.0))
    assert disk.contains(hole)
    assert abs(disk.exterior.distance(hole.exterior) - 1.5) < 0.01
    assert abs(hole.length - 4.0 * np.pi) < 0.01


def test_round_blob_scenes_are_apart_with_their_holes_inside():
    from benchmarks.holes import blob_scene

    holes = 0
    for seed in range(12):
        polygons = [shapely.Polygon(r) for r in blob_scene(seed)]
        assert all(p.is_valid for p in polygons)
        for i, p in enumerate(polygons):
            inside = [q for j, q in enumerate(polygons) if j != i and q.contains(p)]
            assert len(inside) <= 1
            holes += len(inside)
        outers = [p for p in polygons if not any(q.contains(p) for q in polygons if q is not p)]
        assert all(a.distance(b) > 0.03 for k, a in enumerate(outers) for b in outers[k + 1:])
    assert holes >= 1
