"""An outline left open across a gap its points fill closes (`wavepoly.ordering.gaps`), as do
pieces of one outline whose ends pair up across such gaps; a stroke whose ends face across an
empty gap stays open."""

from __future__ import annotations

import numpy as np
import shapely

import wavepoly
from wavepoly.ordering.gaps import close_gaps
from wavepoly.types import OrderedContour

from .conftest import distance_to_output
from .truth import independent_problems

RADIUS = 0.03


def _circle(n: int = 600, start: float = 0.0, stop: float = 2 * np.pi) -> np.ndarray:
    t = np.linspace(start, stop, n, endpoint=False)
    return np.column_stack([np.cos(t), np.sin(t)])


def test_a_ring_left_open_over_its_own_points_closes():
    pts = _circle()
    piece = OrderedContour(pts[3:-9:6], False, np.arange(600))
    out = close_gaps([piece], pts, RADIUS)[0]
    assert [c.closed for c in out] == [True]
    assert shapely.Polygon(out[0].points).is_valid


def test_a_gap_without_points_stays_open():
    pts = _circle()[:-12]  # the points stop where the piece does: a C
    piece = OrderedContour(pts[::6], False, np.arange(len(pts)))
    assert [c.closed for c in close_gaps([piece], pts, RADIUS)[0]] == [False]


def test_a_small_curl_whose_gap_its_points_fill_stays_open():
    """A 270-degree arc 3 radii across: the gap between its ends lies within a radius of its
    points (they curl round it), but the arc is only 3.3 x as long as the gap: a stroke."""
    t = np.linspace(0.0, 1.5 * np.pi, 61)
    pts = 1.5 * RADIUS * np.column_stack([np.cos(t), np.sin(t)])
    piece = OrderedContour(pts[::6], False, np.arange(len(pts)))  # end to end
    assert [c.closed for c in close_gaps([piece], pts, RADIUS)[0]] == [False]


def test_a_small_ring_left_open_at_a_corner_closes():
    """A triangle 4.5 radii across whose chain stops 2.7 radii short at a corner, over its own
    points: 4.4 x as long as the gap, and closed."""
    corners = 4.5 * RADIUS * np.array([[0, 0], [1, 0], [0.5, -1], [0, 0]])
    pts = np.vstack([np.linspace(a, b, 40, endpoint=False) for a, b in zip(corners, corners[1:])])
    piece = OrderedContour(pts[14:-4:3], False, np.arange(len(pts)))
    out = close_gaps([piece], pts, RADIUS)[0]
    assert [c.closed for c in out] == [True]
    assert shapely.Polygon(out[0].points).is_valid


def test_a_gap_closing_across_another_contour_stays_open():
    pts = _circle()
    piece = OrderedContour(pts[3:-9:6], False, np.arange(600))
    across = OrderedContour(np.array([[0.95, -0.2], [1.05, 0.2]]), False, np.arange(0))
    out = close_gaps([piece, across], pts, RADIUS)[0]
    assert [c.closed for c in out] == [False, False]


def test_a_ring_left_open_at_both_ends_of_two_pieces_closes_as_one():
    # the march broke a ring in two places (a notch's tip, a stretch sparser than the
    # radius): two pieces, each end a few radii from the other piece's end
    pts = _circle()
    first = OrderedContour(pts[6:294:6], False, np.arange(300))
    second = OrderedContour(pts[306:594:6][::-1], False, np.arange(300, 600))
    out = close_gaps([first, second], pts, RADIUS)[0]
    assert [c.closed for c in out] == [True]
    assert shapely.Polygon(out[0].points).is_valid
    assert np.array_equal(out[0].members, np.arange(600))


def test_three_pieces_of_a_ring_close_as_one():
    pts = _circle()
    pieces = [OrderedContour(pts[k + 6:k + 198:6], False, np.arange(k, k + 200))
              for k in (0, 200, 400)]
    out = close_gaps(pieces, pts, RADIUS)[0]
    assert [c.closed for c in out] == [True]
    assert shapely.Polygon(out[0].points).is_valid


def test_two_strokes_whose_ends_face_across_empty_gaps_stay_open():
    # two arcs of a drawing, a gap between their ends at both sides with nothing in it
    pts = np.vstack([_circle()[6:294], _circle()[306:594]])
    first = OrderedContour(pts[:288:6], False, np.arange(288))
    second = OrderedContour(pts[288::6], False, np.arange(288, 576))
    out = close_gaps([first, second], pts, RADIUS)[0]
    assert [c.closed for c in out] == [False, False]


def test_pieces_whose_ends_pair_into_no_cycle_stay_open():
    # one gap filled, the other left bare: a chain of two pieces, not a ring
    pts = _circle()[:560]
    first = OrderedContour(pts[6:294:6], False, np.arange(300))
    second = OrderedContour(pts[306:554:6], False, np.arange(300, 560))
    out = close_gaps([first, second], pts, RADIUS)[0]
    assert sorted(c.closed for c in out) == [False, False]


def test_a_ring_left_open_ten_radii_short_over_its_own_points_closes():
    # at a bitmap's tail of one-pixel spurs the march stops some 10 radii short
    pts = _circle()
    piece = OrderedContour(pts[12:-12:6], False, np.arange(600))
    gap = np.linalg.norm(piece.points[0] - piece.points[-1])
    assert 10 * RADIUS < gap < 11 * RADIUS
    out = close_gaps([piece], pts, RADIUS)[0]
    assert [c.closed for c in out] == [True]
    assert shapely.Polygon(out[0].points).is_valid


def test_a_ring_left_open_fourteen_radii_short_over_its_own_points_closes():
    # where a noisy limb's walls merged the march stopped 12.4 radii short of its start
    pts = _circle()
    piece = OrderedContour(pts[18:-18:6], False, np.arange(600))
    gap = np.linalg.norm(piece.points[0] - piece.points[-1])
    assert 14 * RADIUS < gap < 15 * RADIUS
    assert [c.closed for c in close_gaps([piece], pts, RADIUS)[0]] == [True]


def test_a_gap_that_cuts_the_outline_a_radius_deep_closes():
    # the straight gap runs up to 1.05 radii from the arc it cuts across (the horse's tail)
    pts = _circle()
    piece = OrderedContour(pts[24:577:6], False, np.arange(600))
    a, b = piece.points[0], piece.points[-1]
    assert 16 * RADIUS < np.linalg.norm(a - b) < 17 * RADIUS
    depth = 1 - np.linalg.norm((a + b) / 2)
    assert RADIUS < depth < 1.1 * RADIUS
    assert [c.closed for c in close_gaps([piece], pts, RADIUS)[0]] == [True]


def test_a_silhouette_broken_at_a_notch_tip_and_a_waist_comes_out_closed():
    """Silhouette 20 sampled exactly (1000 points, ε = 1/150 of its size): the march broke
    its outline at the tip of the notch between two fingers and where a lobe nearly touches
    the arm below it, two pieces each ending a few radii from the other (3 open pieces
    before)."""
    from benchmarks.bench_validity import SILHOUETTE_SAMPLINGS
    from benchmarks.silhouettes import sample, silhouette

    _, n, eps, noise = SILHOUETTE_SAMPLINGS[1]
    pts = sample(silhouette(20), n, noise * eps, 1020)
    result = wavepoly.fit(pts, eps)
    assert [c.closed for c in result.contours] == [True]
    assert independent_problems(result) == []
    assert len(result.outliers) == 0
    assert distance_to_output(pts, result).max() <= eps * (1 + 1e-9)


def _arcs(spacing: float, gap: float, count: int) -> list[np.ndarray]:
    """``count`` arcs of the unit circle sampled every ``spacing`` radians, with empty
    stretches of ``gap`` radians between them (one centred on angle 0)."""
    step = 2 * np.pi / count
    arcs = []
    for k in range(count):
        t = np.arange(k * step + gap / 2, (k + 1) * step - gap / 2, spacing)
        arcs.append(np.column_stack([np.cos(t), np.sin(t)]))
    return arcs


def _pieces(arcs: list[np.ndarray]) -> tuple[np.ndarray, list[OrderedContour]]:
    """The arcs' points, and each arc as an open piece holding its own points."""
    pts = np.vstack(arcs)
    bounds = np.cumsum([0] + [len(a) for a in arcs])
    return pts, [OrderedContour(a, False, np.arange(b, b + len(a)))
                 for a, b in zip(arcs, bounds)]


def test_pieces_of_a_sparse_ring_close_across_gaps_a_random_sampling_leaves():
    """A ring sampled every 0.8 radii, broken where two stretches have no point for 3.2-4
    radii (5 spacings at most: the widest of 250 random gaps is some ln 250 = 5.5
    spacings): no point lies near the gaps' middles, and still the two pieces are one
    ring."""
    pts, pieces = _pieces(_arcs(0.8 * RADIUS, 3.2 * RADIUS, 2))
    assert np.linalg.norm(pieces[0].points[-1] - pieces[1].points[0]) < 4 * RADIUS
    out, left_out = close_gaps(pieces, pts, RADIUS)
    assert [c.closed for c in out] == [True]
    assert shapely.Polygon(out[0].points).is_valid and len(left_out) == 0


def test_pieces_of_a_dense_sampling_stay_open_across_the_same_gaps():
    """The same gaps where the points lie every 0.2 radii: 16-20 spacings, no chance gap."""
    pts, pieces = _pieces(_arcs(0.2 * RADIUS, 3.2 * RADIUS, 2))
    assert [c.closed for c in close_gaps(pieces, pts, RADIUS)[0]] == [False, False]


def test_a_ring_closing_across_a_gap_takes_the_points_left_out_there():
    """A ring whose piece stops short either side of a lone point (a limb's round tip on a
    sparse scan, the point left out): the ring closes through it, and it is no outlier."""
    pts, (piece,) = _pieces(_arcs(0.8 * RADIUS, 4 * RADIUS, 1))
    pts, lone = np.vstack([pts, [[1.0, 0.0]]]), len(pts)
    out, left_out = close_gaps([piece], pts, RADIUS, np.array([lone]))
    assert [c.closed for c in out] == [True]
    assert len(left_out) == 0 and lone in out[0].members
    assert np.any(np.all(out[0].points == pts[lone], axis=1))


def test_a_thinned_silhouette_broken_at_a_slit_and_a_sparse_limb_tip_comes_out_closed():
    """Silhouette 16 thinned across to a quarter of its density (3000 points, ε = 1/300,
    noise ε / 8): the march broke its outline in a slit and across a limb's round tip on
    the sparse side, 5.3 radii with no point: 7.7 times the mean spacing near its ends
    (0.6-0.8 radii), under ln 3312 = 8.1 (two open pieces before)."""
    from benchmarks.bench_validity import THINNED_SAMPLINGS
    from benchmarks.silhouettes import silhouette, thinned

    n, eps, noise, floor = THINNED_SAMPLINGS[1]
    pts = thinned(silhouette(16), n, noise * eps, floor, 16)
    result = wavepoly.fit(pts, eps)
    assert [c.closed for c in result.contours] == [True]
    assert independent_problems(result) == []
    assert len(result.outliers) == 0
    assert distance_to_output(pts, result).max() <= eps * (1 + 1e-9)
