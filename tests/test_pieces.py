"""The fit's last fallback: contours that still break validity cut into pieces that meet at
junctions, drawing the same lines."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import shapely

from wavepoly.pieces import join_at_ends, noded_contours, split_crossings
from wavepoly.types import Contour, ContourReport
from wavepoly.validity import check_contours


def _drawn(contours):
    return shapely.union_all([shapely.linestrings(np.vstack([c.vertices, c.vertices[:1]])
                                                  if c.closed else c.vertices)
                              for c in contours])


def _reports(contours):
    return [ContourReport(10, 4, c.closed, 0, 0, 0, {}, 4, len(c.vertices), 0.0, 0.0)
            for c in contours]


def test_contours_crossing_at_a_point_are_cut_there():
    wall = Contour(np.array([[0.0, 0.0], [4.0, 0.0]]), False)
    ring = Contour(np.array([[1.0, -1.0], [3.0, -1.0], [3.0, 1.0], [1.0, 1.0]]), True)
    out, reports = split_crossings([wall, ring], _reports([wall, ring]))
    assert check_contours(out).valid and len(out) == 5  # 3 wall pieces, 2 of the ring
    assert _drawn(out).hausdorff_distance(_drawn([wall, ring])) < 1e-12
    assert [r.first_piece for r in reports] == [0, 0, 0, 3, 3]


def test_a_result_whose_pieces_fold_over_each_other_is_noded_into_valid_pieces():
    """The fit's last fallback: contours still invalid after the crossings are split (a
    piece folding over itself, an open piece running along a ring) become the pieces of
    their noded linework; the others, and which pieces share a contour's points, stay."""
    fold = np.array([[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    ring = np.array([[3.0, 0.0], [5.0, 0.0], [5.0, 2.0], [3.0, 2.0]])
    along = np.array([[4.0, 0.0], [4.5, 0.0], [4.5, -1.0]])  # runs along the ring's edge
    apart = np.array([[0.0, 5.0], [2.0, 5.0]])
    contours = [Contour(fold, False), Contour(ring, True), Contour(along, False),
                Contour(apart, False)]
    reports = _reports(contours)
    validity = check_contours(contours)
    assert not validity.valid
    out, out_reports = noded_contours(contours, reports, validity)
    assert check_contours(out).valid
    assert _drawn(out).hausdorff_distance(_drawn(contours)) < 1e-12
    assert out[-1] is contours[-1] and out_reports[-1].first_piece is None
    counted = [k == (r.first_piece if r.first_piece is not None else k)
               for k, r in enumerate(out_reports)]
    assert sum(counted) == 4  # each contour's points are counted once, at its first piece


def _counted_points(reports):
    return sum(r.input_points for k, r in enumerate(reports)
               if k == (r.first_piece if r.first_piece is not None else k))


def test_pieces_meeting_end_to_end_where_nothing_else_passes_are_joined():
    """A wall cut where a stub crossed it, the stub left out: its two pieces meet end to end
    and are one line again; at a T, where a third piece ends, nothing is joined."""
    left = Contour(np.array([[0.0, 0.0], [1.0, 0.1], [2.0, 0.0]]), False, 0.01)
    right = Contour(np.array([[3.0, 0.5], [2.5, 0.1], [2.0, 0.0]]), False, 0.02)
    apart = Contour(np.array([[0.0, 3.0], [1.0, 3.0]]), False)
    contours = [left, apart, right]
    reports = _reports(contours)
    out, out_reports = join_at_ends(contours, reports)
    assert len(out) == 2 and check_contours(out).valid
    np.testing.assert_array_equal(out[0].vertices, [[0, 0], [1, 0.1], [2, 0], [2.5, 0.1],
                                                    [3, 0.5]])
    assert out[0].max_error == 0.02 and out[1] is apart
    assert _drawn(out).hausdorff_distance(_drawn(contours)) < 1e-12
    assert _counted_points(out_reports) == _counted_points(reports) == 30
    stem = Contour(np.array([[2.0, 0.0], [2.0, -1.0]]), False)
    tee, _ = join_at_ends([left, right, stem], _reports([left, right, stem]))
    assert len(tee) == 3


def test_pieces_that_close_a_ring_become_a_closed_contour():
    """An outline cut in two where a stroke crossed it, the stroke left out as a stub: the
    two pieces share both ends and close the ring again."""
    top = Contour(np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0]]), False)
    bottom = Contour(np.array([[0.0, 0.0], [0.0, 2.0], [2.0, 2.0]]), False)
    reports = _reports([top, bottom])
    reports[1] = replace(reports[1], first_piece=0)  # two pieces of one split contour
    out, out_reports = join_at_ends([top, bottom], reports)
    assert len(out) == 1 and out[0].closed and len(out[0].vertices) == 4
    assert check_contours(out).valid and out_reports[0].closed
    assert _counted_points(out_reports) == 10  # the split contour's points, once
