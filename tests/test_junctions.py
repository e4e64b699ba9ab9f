"""Junctions: an open piece that stops short of another contour runs on to meet it."""

from __future__ import annotations

import numpy as np
import shapely

from wavepoly.junctions import JUNCTION_GAP, meet_at_junctions
from wavepoly.types import Contour
from wavepoly.validity import check_contours

WALL = Contour(np.array([[0.0, 0.0], [4.0, 0.0]]), False)


def _line(*xy):
    return Contour(np.array(xy, dtype=float), False)


def test_a_piece_heading_into_a_wall_meets_it():
    stub = _line([2.0, 1.0], [2.0, 0.12])
    out, grown = meet_at_junctions([WALL, stub], 0.1)
    assert grown == [1]
    np.testing.assert_allclose(out[1].vertices[-1], [2.0, 0.0], atol=1e-12)
    np.testing.assert_array_equal(out[1].vertices[:2], stub.vertices)  # the piece's own edges stay
    assert check_contours(out).valid
    assert shapely.distance(shapely.linestrings(out[0].vertices),
                            shapely.linestrings(out[1].vertices)) < 1e-12


def test_a_piece_beside_a_wall_or_too_far_stays_as_it_is():
    beside = _line([1.0, 0.12], [3.0, 0.12])  # runs along the wall, heads nowhere near it
    far = _line([2.0, 1.0], [2.0, 0.1 * JUNCTION_GAP + 0.01])
    out, grown = meet_at_junctions([WALL, beside], 0.1)
    assert grown == []
    out, grown = meet_at_junctions([WALL, far], 0.1)
    assert grown == []


def test_a_piece_meets_the_nearest_contour_it_heads_for():
    """A short piece lies between the stub and the wall: the stub meets the piece, the nearer,
    and its edge crosses nothing on the way."""
    stub = _line([2.0, 1.0], [2.0, 0.15])
    between = _line([1.9, 0.08], [2.1, 0.08])
    out, grown = meet_at_junctions([WALL, between, stub], 0.1)
    assert 2 in grown
    np.testing.assert_allclose(out[2].vertices[-1], [2.0, 0.08], atol=1e-12)
    assert check_contours(out).valid


def test_both_ends_of_a_piece_between_two_walls_meet_them():
    top = Contour(np.array([[0.0, 1.0], [4.0, 1.0]]), False)
    rung = _line([2.0, 0.15], [2.0, 0.85])
    out, grown = meet_at_junctions([WALL, top, rung], 0.1)
    assert grown == [2] and len(out[2].vertices) == 4
    assert check_contours(out).valid


def test_an_open_line_whose_ends_meet_is_left_alone():
    loop = _line([2.0, 0.15], [2.5, 0.5], [1.5, 0.5], [2.0, 0.15])
    out, grown = meet_at_junctions([WALL, loop], 0.1)
    assert grown == [] and out[1] is loop
