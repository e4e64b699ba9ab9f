"""Closed outlines with stems: slits and thin limbs narrower than the radius keep an outline
closed (`wavepoly.ordering.stems`), and a line drawing's strokes stay strokes."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from shapely import affinity

import wavepoly
from wavepoly.geometry import polyline_length
from wavepoly.ordering.stems import close_outlines
from wavepoly.samples import glyph_outlines, sample_rings
from wavepoly.types import OrderedContour

from .conftest import distance_to_output
from .truth import independent_problems

EPS = 0.05


def _silhouette(slit_half_angle: float, limb_width: float, angle: float) -> shapely.Polygon:
    """An ellipse with a wedge slit cut into it, and a thin limb standing out of it."""
    body = affinity.scale(shapely.Point(0, 0).buffer(1.0, 64), 2.0, 1.0)
    d = np.array([np.cos(angle), np.sin(angle)])
    n = np.array([-d[1], d[0]])
    wedge = shapely.Polygon([0.6 * d, 3 * d + 3 * slit_half_angle * n,
                             3 * d - 3 * slit_half_angle * n])
    limb = shapely.LineString([-1.5 * d + 0.3 * n, -2.6 * d + 1.0 * n]).buffer(
        limb_width / 2, 8, cap_style="flat")
    shape = body.difference(wedge).union(limb)
    return max(getattr(shape, "geoms", [shape]), key=lambda g: g.area)


def _fit(shape: shapely.Polygon, seed: int):
    ring = np.asarray(shape.exterior.coords)[:-1]
    pts = sample_rings([ring], spacing=EPS / 3, noise=EPS / 8, seed=seed)
    return pts, wavepoly.fit(pts, EPS)


def _one_closed_outline(pts, result):
    assert [c.closed for c in result.contours] == [True], result.validity
    assert independent_problems(result) == []
    assert len(result.outliers) == 0
    assert distance_to_output(pts, result).max() <= EPS * (1 + 1e-9)


def test_a_slit_and_a_thin_limb_keep_the_outline_closed():
    shape = _silhouette(0.01, 0.03, 0.4)
    pts, result = _fit(shape, 1)
    _one_closed_outline(pts, result)
    # the outline runs down the slit to its tip and out to the limb's end, not across them
    drawn = result.to_shapely()
    assert shapely.hausdorff_distance(drawn.boundary, shape.boundary) <= 1.5 * EPS


@pytest.mark.parametrize("slit", [0.008, 0.012])
@pytest.mark.parametrize("limb", [0.3 * EPS, 0.6 * EPS])
@pytest.mark.parametrize("angle", [0.4, 1.5, 2.5, 4.0, 5.5])
def test_slits_and_limbs_in_any_direction_give_one_valid_closed_outline(slit, limb, angle):
    pts, result = _fit(_silhouette(slit, limb, angle), 1)
    _one_closed_outline(pts, result)


def _ring_and_stroke(spacing: float) -> np.ndarray:
    """A unit ring and a stroke meeting it at a T, each sampled every ``spacing``."""
    t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    ring = np.column_stack([np.cos(t), np.sin(t)])
    stroke = np.linspace([1.0, 0.0], [2.0, 0.0], 40)
    return np.vstack([sample_rings([ring], spacing=spacing, seed=2),
                      sample_rings([stroke], spacing=spacing, closed=[False], seed=3)])


def _drawn_length(result) -> float:
    return sum(shapely.length(shapely.LineString(c.vertices)) for c in result.contours)


def test_a_stroke_of_a_line_drawing_stays_a_stroke():
    # a ring and a stroke each sampled as densely: a drawing, not a slit
    result = wavepoly.fit(_ring_and_stroke(EPS / 3), EPS)
    assert independent_problems(result) == []
    # drawn once (2 pi + 1 long), not out and back as a sliver (2 pi + 2)
    assert _drawn_length(result) < 2 * np.pi + 1.5


def test_a_stroke_on_an_uneven_sampling_stays_a_stroke():
    # the same drawing thinned to a quarter across: beside its root the stroke holds as many
    # points per length as the ring, though more than the ring's sparse side
    pts = _ring_and_stroke(EPS / 6)
    keep = np.random.default_rng(4).uniform(size=len(pts)) < 1 - 0.375 * (2 - pts[:, 0]) / 1.5
    result = wavepoly.fit(pts[keep], EPS)
    assert independent_problems(result) == []
    assert _drawn_length(result) < 2 * np.pi + 1.5


def test_a_loop_with_a_tail_down_a_slit_is_walked_out_and_back():
    t = np.linspace(0.02, 2 * np.pi - 0.02, 400)
    ring = np.column_stack([np.cos(t), np.sin(t)])
    loop = np.vstack([np.linspace([0.5, 0.0], [1.0, 0.0], 11), ring[::10], ring[-1:]])
    slit = np.column_stack([np.linspace(0.5, 1.0, 80), np.tile([0.01, -0.01], 40)])
    pts = np.vstack([ring, slit])
    out = close_outlines([OrderedContour(loop, False, np.arange(len(pts)))], pts, 0.05)
    assert len(out) == 1 and out[0].closed
    polygon = shapely.Polygon(out[0].points)
    assert polygon.is_valid
    # the slit's two passes lie on either side of its middle line, within its half-width
    xy = out[0].points
    across = xy[(xy[:, 0] > 0.55) & (xy[:, 0] < 0.95) & (np.abs(xy[:, 1]) < 0.1), 1]
    assert (across > 0).any() and (across < 0).any()
    assert np.abs(across).max() <= 0.5 * 0.05 + 1e-12
    assert np.array_equal(out[0].members, np.arange(len(pts)))


def test_two_rings_joined_by_a_bar_are_left_as_they_are():
    t = np.linspace(0, 2 * np.pi, 60, endpoint=False)
    left = np.column_stack([np.cos(t) - 2, np.sin(t)])
    right = np.column_stack([np.cos(t) + 2, np.sin(t)])
    bar = np.linspace([-1.0, 0.0], [1.0, 0.0], 30)
    pts = np.vstack([left, right, np.repeat(bar, 3, axis=0)])
    contours = [OrderedContour(left, True, np.arange(60)),
                OrderedContour(right, True, np.arange(60, 120)),
                OrderedContour(bar, False, np.arange(120, 210))]
    assert close_outlines(contours, pts, 0.1) is contours


def test_a_ring_cut_into_two_pieces_becomes_one_ring():
    t = np.linspace(0, np.pi, 50)
    upper = np.column_stack([np.cos(t), np.sin(t)])
    lower = upper[::-1] * [1, -1]
    pts = np.vstack([upper, lower])
    contours = [OrderedContour(upper, False, np.arange(50)),
                OrderedContour(lower, False, np.arange(50, 100))]
    out = close_outlines(contours, pts, 0.1)
    assert len(out) == 1 and out[0].closed and shapely.Polygon(out[0].points).is_valid


def test_a_stem_leaving_the_cycle_at_a_shallow_angle_does_not_cross_it():
    # found by hypothesis: the slit's first pass crossed the edge the walk arrived by
    pts, result = _fit(_silhouette(0.0078125, 0.03125, 4.0), 0)
    _one_closed_outline(pts, result)


def test_a_chord_inside_a_ring_beside_its_wall_is_left_out_of_the_outline():
    # where a slit's tip is, the chains may cross and leave a chord beside a wall: the ring
    # and the chord enclose two faces, and the outline is the region's boundary
    t = np.linspace(0, 2 * np.pi, 600, endpoint=False)
    pts = np.column_stack([np.cos(t), np.sin(t)])
    u = np.linspace(np.pi / 3, 2 * np.pi / 3, 20)
    chord = 0.97 * np.column_stack([np.cos(u), np.sin(u)])
    pieces = [OrderedContour(np.vstack([pts[:300:5], pts[300:301]]), False, np.arange(300)),
              OrderedContour(np.vstack([pts[300::5], pts[:1]]), False, np.arange(300, 600)),
              OrderedContour(chord, False, np.arange(0))]
    out = close_outlines(pieces, pts, 0.05)
    _one_simple_ring(out)
    assert np.abs(np.linalg.norm(out[0].points, axis=1) - 1).max() < 1e-3  # the chord: 0.97


def test_a_chord_far_from_the_ring_keeps_its_points_and_the_pieces_open():
    # a stroke across the middle of a ring (a line drawing's network) is not left out
    t = np.linspace(0, 2 * np.pi, 600, endpoint=False)
    ring = np.column_stack([np.cos(t), np.sin(t)])
    bar = np.column_stack([np.linspace(-1, 1, 200), np.zeros(200)])
    pts = np.vstack([ring, bar])
    pieces = [OrderedContour(np.vstack([ring[:300:5], ring[300:301]]), False, np.arange(300)),
              OrderedContour(np.vstack([ring[300::5], ring[:1]]), False, np.arange(300, 600)),
              OrderedContour(bar[::5], False, np.arange(600, 800))]
    out = close_outlines(pieces, pts, 0.05)
    assert not any(c.closed for c in out)


def test_a_ring_in_two_pieces_whose_ends_stop_apart_becomes_one_ring():
    # where a slit's walls converge the march stops on both, its ends two radii apart
    t = np.linspace(0, 2 * np.pi, 600, endpoint=False)
    pts = np.column_stack([np.cos(t), np.sin(t)])
    pieces = [OrderedContour(pts[5:296:5], False, np.arange(300)),
              OrderedContour(pts[305:596:5], False, np.arange(300, 600))]
    out = close_outlines(pieces, pts, 0.05)
    _one_simple_ring(out)


def _one_simple_ring(out: list[OrderedContour]) -> shapely.Polygon:
    """The one contour of ``out``, asserted closed and a valid polygon."""
    assert [c.closed for c in out] == [True]
    polygon = shapely.Polygon(out[0].points)
    assert polygon.is_valid
    return polygon


def _ring_with_slit(radius: float):
    """A unit ring in two pieces meeting at (1, 0) and (-1, 0), and the points of a slit cut
    in from (1, 0) to (0.5, 0), its walls 0.4 radii apart."""
    t = np.linspace(0, 2 * np.pi, 600, endpoint=False)
    ring = np.column_stack([np.cos(t), np.sin(t)])
    x = np.linspace(0.5, 1.0, 100)
    walls = np.vstack([np.column_stack([x, np.full(100, s * 0.2 * radius)]) for s in (-1, 1)])
    pieces = [OrderedContour(ring[:301:5], False, np.arange(300)),
              OrderedContour(np.vstack([ring[300::5], ring[:1]]), False, np.arange(300, 600))]
    return np.vstack([ring, walls]), pieces


def _closes_down_the_slit(ring, pieces, stem_points, closes: bool, radius: float) -> None:
    """The ring's two pieces and a stem from (1, 0) to (0.5, 0) holding ``stem_points``: one
    simple outline running down to the slit's tip, or the three pieces left open."""
    pts = np.vstack([ring, stem_points])
    stem = OrderedContour(np.linspace([1.0, 0.0], [0.5, 0.0], 21), False,
                          np.arange(len(ring), len(pts)))
    out = close_outlines([*pieces, stem], pts, radius)
    assert [c.closed for c in out] == ([True] if closes else [False, False, False])
    if closes:
        polygon = _one_simple_ring(out)
        assert shapely.distance(polygon.exterior, shapely.Point(0.5, 0.0)) < radius


def test_a_speck_at_a_junction_does_not_keep_the_outline_open():
    # the march left two nodes by a junction, and both of their ends met it
    radius = 0.05
    pts, pieces = _ring_with_slit(radius)
    pts = pts[:600]
    speck = OrderedContour(np.array([[1.0, 0.2 * radius], [1.0, -0.2 * radius]]), False,
                           np.arange(0))
    out = close_outlines([*pieces, speck], pts, radius)
    _one_simple_ring(out)
    assert np.array_equal(out[0].members, np.arange(600))


def test_a_slit_whose_root_the_march_drew_twice_is_walked_out_and_back():
    # by the slit's root the march made two chains of one wall (a bubble), and the slit's
    # stem hangs off their far junction, not off the ring
    radius = 0.05
    pts, pieces = _ring_with_slit(radius)
    root = np.linspace([1.0, 0.0], [0.85, 0.0], 6)
    bubble = [OrderedContour(root, False, np.arange(600, 630)),
              OrderedContour(root + [0.0, 0.3 * radius], False, np.arange(700, 730)),
              OrderedContour(np.linspace([0.85, 0.0], [0.5, 0.0], 15), False,
                             np.concatenate([np.arange(630, 700), np.arange(730, 800)]))]
    out = close_outlines([*pieces, *bubble], pts, radius)
    polygon = _one_simple_ring(out)
    # the outline runs down the slit to its tip
    assert shapely.distance(polygon.exterior, shapely.Point(0.5, 0.0)) < radius
    assert np.array_equal(out[0].members, np.arange(800))


def test_a_slit_whose_walls_the_march_followed_apart_is_walked_along_their_middle():
    # the slit's walls bow 1.4 radii apart over 8 radii by its root (the march followed each
    # as a chain of its own, between the same two junctions) and merge into a stem beyond
    radius = 0.05
    pts, pieces = _ring_with_slit(radius)
    x = np.linspace(1.0, 0.6, 41)
    bow = 0.7 * radius * np.sin(np.pi * (1.0 - x) / 0.4)
    walls = [np.column_stack([x, s * bow]) for s in (1, -1)]
    tip = np.linspace([0.6, 0.0], [0.3, 0.0], 31)
    pts = np.vstack([pts[:600], *walls, tip + [0, 0.2 * radius], tip - [0, 0.2 * radius]])
    slit = [OrderedContour(walls[0][::4], False, np.arange(600, 641)),
            OrderedContour(walls[1][::4], False, np.arange(641, 682)),
            OrderedContour(tip[::3], False, np.arange(682, 744))]
    out = close_outlines([*pieces, *slit], pts, radius)
    polygon = _one_simple_ring(out)
    assert shapely.distance(polygon.exterior, shapely.Point(0.3, 0.0)) < radius
    assert shapely.distance(shapely.points(pts), polygon.exterior).max() <= radius
    assert np.array_equal(out[0].members, np.arange(744))


def test_a_slit_whose_tip_met_the_wall_beyond_it_is_walked_out_and_back():
    # the slit runs across the ring to 2 radii from its wall beyond, where the stem's dead
    # end met the wall: the stem became a chord across the ring
    radius = 0.05
    pts, pieces = _ring_with_slit(radius)
    tip = 0.9 * np.array([np.cos(np.radians(230)), np.sin(np.radians(230))])
    t = np.linspace(0.0, 1.0, 380)[:, None]
    d = (tip - [1.0, 0.0]) / np.linalg.norm(tip - [1.0, 0.0])
    side = 0.2 * radius * np.array([-d[1], d[0]])
    axis = [1.0, 0.0] + t * (tip - [1.0, 0.0])
    pts = np.vstack([pts[:600], axis + side, axis - side])
    stem = OrderedContour(axis[::5], False, np.arange(600, 1360))
    out = close_outlines([*pieces, stem], pts, radius)
    polygon = _one_simple_ring(out)
    assert shapely.distance(polygon.exterior, shapely.Point(tip)) < radius
    assert not polygon.covers(shapely.Point(*axis[190, :]))  # the slit is cut in, not bridged
    assert shapely.distance(shapely.points(pts), polygon.exterior).max() <= radius
    assert np.array_equal(out[0].members, np.arange(1360))


def test_a_stem_holding_one_wall_where_a_slit_parts_does_not_keep_the_outline_open():
    # a slit's stem holds both walls; a second, short stem (2.8 radii) one wall, as where a
    # wedge slit's walls part: together they hold more than twice the ring's points per
    # length (the short one alone 1.05 x), and the outline closes
    radius = 0.05
    pts, pieces = _ring_with_slit(radius)
    wall = np.column_stack([np.linspace(-1.0, -0.86, 14), np.zeros(14)])
    pts = np.vstack([pts, wall])
    stems = [OrderedContour(np.linspace([1.0, 0.0], [0.5, 0.0], 15), False,
                            np.arange(600, 800)),
             OrderedContour(wall[::2], False, np.arange(800, 814))]
    out = close_outlines([*pieces, *stems], pts, radius)
    _one_simple_ring(out)
    assert np.array_equal(out[0].members, np.arange(814))


def test_a_slit_whose_tip_stops_by_a_hole_keeps_the_hole_and_the_outline_apart():
    # the slit's tip stops two radii from a hole: the T junction there joined the hole's
    # ring to the outline (two rings and a bar), and neither closed
    radius = 0.05
    pts, pieces = _ring_with_slit(radius)
    t = np.linspace(0, 2 * np.pi, 60, endpoint=False)
    hole = np.column_stack([0.3 - 0.1 * np.cos(t), 0.1 * np.sin(t)])  # starts away from the tip
    pts = np.vstack([pts, hole])
    contours = [*pieces, OrderedContour(hole, True, np.arange(800, 860)),
                OrderedContour(np.linspace([1.0, 0.0], [0.5, 0.0], 15), False,
                               np.arange(600, 800))]
    out = close_outlines(contours, pts, radius)
    assert sorted(len(c.members) for c in out if c.closed) == [60, 800]
    assert len(out) == 2
    outline = next(c for c in out if len(c.members) == 800)
    assert shapely.Polygon(outline.points).is_valid
    assert shapely.distance(shapely.LinearRing(outline.points), shapely.Point(0.5, 0.0)) < radius


def test_a_lone_piece_holding_two_walls_is_a_thin_ring_and_a_lone_stroke_stays_open():
    # a hole thinner than the radius: the march followed its two walls as one chain
    radius = 0.05
    ring, pieces = _ring_with_slit(radius)
    x = np.linspace(-0.4, 0.4, 80)  # each wall as dense as the ring
    walls = np.vstack([np.column_stack([x, np.full(80, s * 0.2 * radius)]) for s in (-1, 1)])
    line = np.column_stack([np.linspace(-0.4, 0.4, 17), np.zeros(17)])
    for pts, thin in ((walls, True), (walls[:80], False)):  # two walls; one stroke
        everything = np.vstack([ring[:600], pts])
        lone = OrderedContour(line, False, np.arange(600, 600 + len(pts)))
        out = close_outlines([*pieces, lone], everything, radius)
        assert sorted(c.closed for c in out) == ([True, True] if thin else [False, True])
        assert all(shapely.Polygon(c.points).is_valid for c in out if c.closed)


def test_a_stem_that_holds_two_walls_over_less_than_half_of_it_closes_the_outline():
    # a wedge slit: by its root the walls part and the stem holds one of them (6 radii), by
    # its tip it holds both (4 radii); over its whole length it holds 1.4 x the ring's points
    # per length, over its denser half 1.7 x. A stem holding one wall throughout is a stroke.
    radius = 0.05
    ring, pieces = _ring_with_slit(radius)
    ring = ring[:600]  # 95 points per unit length
    one_wall = np.column_stack([np.linspace(0.7, 1.0, 29), np.full(29, 0.2 * radius)])
    tip = np.vstack([np.column_stack([np.linspace(0.5, 0.7, 19), np.full(19, s * 0.2 * radius)])
                     for s in (-1, 1)])
    stroke = np.column_stack([np.linspace(0.5, 1.0, 48), np.full(48, 0.2 * radius)])
    for walls, closes in ((np.vstack([one_wall, tip]), True), (stroke, False)):
        _closes_down_the_slit(ring, pieces, walls, closes, radius)


def test_a_stem_that_zigzags_between_its_walls_is_walked_along_its_middle():
    # walls 1.2 radii apart: the march zigzagged between them, stepping back now and then,
    # and walked out and back along the zigzag the stem crossed itself
    radius = 0.05
    ring, pieces = _ring_with_slit(radius)
    x = np.linspace(0.5, 1.0, 100)
    walls = np.vstack([np.column_stack([x, np.full(100, s * 0.6 * radius)]) for s in (-1, 1)])
    pts = np.vstack([ring[:600], walls])
    k = np.arange(15)
    back = 0.5 * radius * (-1.0) ** k * (k % 3 == 1)
    zigzag = np.column_stack([np.linspace(1.0, 0.5, 15) + back, 0.6 * radius * (-1.0) ** k])
    zigzag[0], zigzag[-1] = [1.0, 0.0], [0.5, 0.0]
    out = close_outlines([*pieces, OrderedContour(zigzag, False, np.arange(600, 800))], pts,
                         radius)
    polygon = _one_simple_ring(out)
    assert shapely.distance(polygon.exterior, shapely.Point(0.5, 0.0)) < radius


def test_a_stem_that_zigzags_is_measured_along_its_middle():
    # walls 1.2 radii apart, each sampled as the ring is (95 points per unit length), and a
    # stem zigzagging between them 2.5 x as long as the slit: counted along the zigzag, the
    # stem held 0.8 x the ring's points per length, a stroke; along its middle, 2 x
    radius = 0.05
    ring, pieces = _ring_with_slit(radius)
    ring = ring[:600]
    x = np.linspace(0.5, 1.0, 48)
    walls = np.vstack([np.column_stack([x, np.full(48, s * 0.6 * radius)]) for s in (-1, 1)])
    pts = np.vstack([ring, walls])
    k = np.arange(21)
    zigzag = np.column_stack([np.linspace(1.0, 0.5, 21), 0.6 * radius * (-1.0) ** k])
    zigzag[0], zigzag[-1] = [1.0, 0.0], [0.5, 0.0]
    assert polyline_length(zigzag, False) > 2.4 * 0.5
    out = close_outlines([*pieces, OrderedContour(zigzag, False, np.arange(600, len(pts)))],
                         pts, radius)
    polygon = _one_simple_ring(out)
    assert shapely.distance(polygon.exterior, shapely.Point(0.5, 0.0)) < radius


def test_a_stem_whose_zigzag_tip_met_itself_is_walked_out_and_back():
    # a slit 1.2 radii wide cut into a closed ring, whose walls the march zigzagged between:
    # the zigzag is so much longer than the slit that its tip's end lies within reach of the
    # chain farther on, and met it there, closing a loop of 6 nodes at the stem's dead end
    radius = 0.05
    t = np.linspace(0, 2 * np.pi, 628, endpoint=False)
    ring = np.column_stack([np.cos(t), np.sin(t)])
    x = np.linspace(0.5, 1.0, 50)
    walls = np.vstack([np.column_stack([x, np.full(50, s * 0.6 * radius)]) for s in (-1, 1)])
    pts = np.vstack([ring, walls])
    steps = np.arange(0.5, 0.981, 0.02)
    zigzag = np.column_stack([steps, 0.6 * radius * (-1.0) ** np.arange(len(steps))])
    zigzag[0] = [0.5, 0.0]
    stroke = OrderedContour(np.vstack([zigzag, [[1.0, 0.0]]]), False, np.arange(628, len(pts)))
    out = close_outlines([OrderedContour(ring[::5], True, np.arange(628)), stroke], pts, radius)
    polygon = _one_simple_ring(out)
    assert shapely.distance(polygon.exterior, shapely.Point(0.5, 0.0)) < radius


def test_a_serif_y_at_a_coarse_tolerance_keeps_its_ball_terminal():
    """Computer Modern's 'y' at ε 0.8 (its hairlines under half an ε): a tip loop opened
    among open pieces alone let a reading close that split the ball terminal off at a
    hairline, and that reading won (`bubbles.without_tip_loops` opens loops only beside a
    ring the march closed)."""
    shape = glyph_outlines("y", height=20.0, family="cmr10")
    pts = sample_rings(shape.rings, spacing=0.1, noise=0.1, seed=13)
    result = wavepoly.fit(pts, 0.8)
    assert [c.closed for c in result.contours] == [True]
    assert independent_problems(result) == [] and len(result.outliers) == 0
    assert distance_to_output(pts, result).max() <= 0.8 * (1 + 1e-9)


def test_a_lone_piece_that_zigzags_between_two_walls_is_walked_along_its_middle():
    # a thin hole 1.2 radii wide, whose walls the march zigzagged between as one chain,
    # stepping back a radius now and then (the zigzag half as long again as the hole: its
    # walls sampled 1.5 x as densely as the ring)
    radius = 0.05
    ring, pieces = _ring_with_slit(radius)
    x = np.linspace(-0.4, 0.4, 120)
    walls = np.vstack([np.column_stack([x, np.full(120, s * 0.6 * radius)]) for s in (-1, 1)])
    k = np.arange(17)
    back = 1.0 * radius * (-1.0) ** k * (k % 3 == 1)
    zigzag = np.column_stack([np.linspace(-0.4, 0.4, 17) + back, 0.6 * radius * (-1.0) ** k])
    everything = np.vstack([ring[:600], walls])
    out = close_outlines([*pieces, OrderedContour(zigzag, False, np.arange(600, 840))],
                         everything, radius)
    assert sorted(c.closed for c in out) == [True, True]
    assert all(shapely.Polygon(c.points).is_valid for c in out)


def test_a_stem_running_on_from_where_the_ring_turns_back_needs_fewer_points():
    # a slit 2 radii wide at its mouth, where the ring ran in along each wall and turned
    # back; on from there, the stem holds 1.3 x the ring's points per length (a bitmap's
    # trace holds one wall in places). A stroke as dense off a smooth ring, its points on its
    # chain, is a stroke (two walls off a smooth ring: `..._spread_as_two_walls_...` below).
    radius = 0.05
    t = np.linspace(0, 2 * np.pi, 600, endpoint=False)
    circle = np.column_stack([np.cos(t), np.sin(t)])  # 95 points per unit length
    circle = circle[(circle[:, 0] < 0.9) | (np.abs(circle[:, 1]) > radius)]
    x = np.linspace(0.8, 0.999, 19)
    upper, lower = (np.column_stack([x, np.full(19, s * radius)]) for s in (1, -1))
    up, down = circle[circle[:, 1] > 0], circle[circle[:, 1] < 0]
    x = np.linspace(0.5, 0.79, 19)
    walls = np.vstack([np.column_stack([x, np.full(19, s * 0.2 * radius)]) for s in (1, -1)])
    pts = np.vstack([circle, upper, lower, walls])
    n_ring = len(pts) - len(walls)
    pieces = [OrderedContour(np.vstack([[0.8, 0.0], upper[::2], up[::5], [-1.0, 0.0]]), False,
                             np.arange(n_ring)),
              OrderedContour(np.vstack([[-1.0, 0.0], down[::5], lower[::-2], [0.8, 0.0]]),
                             False, np.arange(0))]
    stem = OrderedContour(np.linspace([0.8, 0.0], [0.5, 0.0], 13), False,
                          np.arange(n_ring, len(pts)))
    out = close_outlines([*pieces, stem], pts, radius)
    _one_simple_ring(out)
    assert shapely.distance(shapely.LinearRing(out[0].points), shapely.Point(0.5, 0.0)) < radius
    ring, smooth = _ring_with_slit(radius)
    line = np.column_stack([np.linspace(0.5, 1.0, 62), np.zeros(62)])
    pts = np.vstack([ring[:600], line])
    stroke = OrderedContour(np.linspace([1.0, 0.0], [0.5, 0.0], 21), False,
                            np.arange(600, len(pts)))
    assert not any(c.closed for c in close_outlines([*smooth, stroke], pts, radius))


def test_a_stem_whose_points_spread_as_two_walls_needs_fewer_points():
    # a slit whose walls lie 0.3 radii to either side of its chain, holding 1.3 x the ring's
    # points per length (a noisy bitmap's slit: each wall sampled a little thinner), closes the
    # outline; a stroke as dense whose points lie on its chain stays a stroke
    radius = 0.05
    ring, pieces = _ring_with_slit(radius)
    ring = ring[:600]  # 95 points per unit length
    x = np.linspace(0.5, 1.0, 31)
    walls = np.vstack([np.column_stack([x, np.full(31, s * 0.3 * radius)]) for s in (-1, 1)])
    stroke = np.column_stack([np.linspace(0.5, 1.0, 62), np.zeros(62)])
    for points, closes in ((walls, True), (stroke, False)):
        _closes_down_the_slit(ring, pieces, points, closes, radius)


@pytest.mark.parametrize("seed", [40, 55, 60, 13])
def test_bitmap_slits_whose_walls_spread_about_their_stem_close_the_outline(seed):
    """Silhouettes traced from a 200-pixel bitmap with noise ε / 4: the slits' stems hold 1.36
    and 1.23 x the ring's points per length (under `STEM_DENSITY`) and spread 1.30 and 1.73 x
    as far; each outline was closed without its slit, which stayed an open stroke. Seed 60:
    a limb 1.5 ε wide whose stem zigzags, 2.6 x as long as the limb (0.8 x the ring's points
    per length along the zigzag, 1.9 x along its middle). Seed 13: a slit an ε wide whose
    stroke zigzags so that its tip met the stroke farther on, a loop at the stem's dead end
    (`bubbles.without_tip_loops`)."""
    from benchmarks.silhouettes import bitmap, sample, silhouette

    rings = bitmap(silhouette(seed), 200)
    eps = 0.01  # the silhouette is 1 unit across its diagonal
    pts = sample(rings, 2000, eps / 4, 1000 + seed)
    result = wavepoly.fit(pts, eps)
    assert [c.closed for c in result.contours] == [True] * len(rings)
    assert independent_problems(result) == []
    assert len(result.outliers) == 0
    assert distance_to_output(pts, result).max() <= eps * (1 + 1e-9)


@pytest.mark.parametrize(("seed", "noise"), [(1, 1 / 3), (13, 1 / 4)])
def test_a_walk_whose_passes_cross_in_the_noise_is_untangled(seed, noise):
    """Silhouettes sampled with 3000 points and noise ε / 3 or ε / 4: the two passes of a
    slit's walk, each along one wall, crossed each other where the walls' points mingle, and
    the fit fell back to cutting the self-crossing outline into open pieces (6 and 9)."""
    from benchmarks.silhouettes import sample, silhouette

    rings = silhouette(seed)
    eps = float(np.hypot(*np.ptp(np.vstack(rings), axis=0))) / 150
    pts = sample(rings, 3000, noise * eps, 1000 + seed)
    result = wavepoly.fit(pts, eps)
    assert [c.closed for c in result.contours] == [True]
    assert independent_problems(result) == []
    assert len(result.outliers) == 0
    assert distance_to_output(pts, result).max() <= eps * (1 + 1e-9)


@pytest.mark.parametrize("width, seed", [(0.5, 0), (0.5, 2), (0.7, 1)])
def test_a_thin_hole_whose_chain_zigzags_is_closed(width, seed):
    """A hole 16 tolerances long and 1-1.4 wide inside a ring, sampled every ε / 3 with
    noise ε / 4: the march follows its two walls as one chain that zigzags between them, and
    per length of that chain the hole held too few points to be a thin ring; per length of
    its averaged path it holds two walls' worth, and is closed."""
    t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    ring = 20 * np.column_stack([np.cos(t), np.sin(t)])
    hole = np.column_stack([8 * np.cos(t), width * np.sin(t)])
    pts = sample_rings([ring, hole], spacing=1 / 3, noise=0.25, seed=seed)
    result = wavepoly.fit(pts, 1.0)
    assert [c.closed for c in result.contours] == [True, True]
    assert len(result.outliers) == 0 and independent_problems(result) == []
