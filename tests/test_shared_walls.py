"""Two rings that share a thin wall (`wavepoly.ordering.shared_walls`): a hole whose corner
comes within the radius of its outline, two shapes a thin gap apart."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

import wavepoly
from benchmarks.holes import hole_by_the_wall
from wavepoly.ordering.piece_graph import Edge
from wavepoly.ordering.shared_walls import _side_by_side, theta_rings
from wavepoly.samples import sample_rings

from .conftest import distance_to_output
from .truth import independent_problems

EPS = 1.0


def _outline_and_hole(pts: np.ndarray) -> None:
    """The fit at `EPS` is an outline and its hole, valid, every point within the tolerance."""
    result = wavepoly.fit(pts, EPS)
    assert not independent_problems(result)
    assert [c.closed for c in result.contours] == [True, True]
    assert sorted(result.parents) == [-1, 0]
    assert len(result.outliers) == 0
    assert distance_to_output(pts, result).max() <= EPS * (1 + 1e-9)


@pytest.mark.parametrize("seed", [5, 9])
def test_a_hole_whose_corner_nears_the_wall_is_a_hole_not_an_open_piece(seed):
    """With noise ε / 4, the march ran from the wall into the hole at its corner, 0.4 ε away,
    round the hole and out again: three pieces between two junctions a fraction of a radius
    apart, a figure eight, which no walk of one cycle draws. It was one open piece."""
    pts = sample_rings(hole_by_the_wall(0.4), spacing=EPS / 3, noise=EPS / 4, seed=seed)
    _outline_and_hole(pts)


def _along(xy: np.ndarray, step: float) -> np.ndarray:
    """Points every ``step`` along a polyline."""
    line = shapely.LineString(xy)
    return shapely.get_coordinates(shapely.line_interpolate_point(
        line, np.arange(0.0, line.length, step)))


def test_two_shapes_a_thin_gap_apart_are_two_outlines():
    """Two squares 0.3 radii apart along a side: the march follows both sides as one chain,
    the middle piece of a theta, which holds twice the points per length of the others."""
    radius = 0.1
    left = np.array([[0.0, 0.0], [-1.0, 0.0], [-1.0, 1.0], [0.0, 1.0]])
    right = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    gap = np.array([[0.0, 0.0], [0.0, 1.0]])
    edges = [Edge(left, 0, 1, 0), Edge(gap, 0, 1, 1), Edge(right, 0, 1, 2)]
    walls = [_along(gap, 0.03) + [s * 0.015, 0.0] for s in (-1, 1)]
    pts = np.vstack([_along(left, 0.03), _along(right, 0.03), *walls])
    rings = theta_rings([0, 1, 2], edges, pts, radius)
    polygons = [shapely.Polygon(r) for r in rings]
    assert all(p.is_valid for p in polygons)
    assert 0.02 <= polygons[0].distance(polygons[1]) <= 0.05  # the walls 0.03 apart
    assert [p.area for p in polygons] == pytest.approx([1.0, 1.0], abs=0.03)


def test_a_stroke_drawn_theta_stays_strokes():
    """A line drawing's theta (a circle and its diameter, one stroke each): no piece holds two
    walls or is short beside the others, so the three stay open strokes."""
    radius = 0.1
    t = np.linspace(0.0, np.pi, 60)
    top = np.column_stack([np.cos(t), np.sin(t)])
    bottom = top * [1.0, -1.0]
    middle = np.array([[1.0, 0.0], [-1.0, 0.0]])
    edges = [Edge(top, 0, 1, 0), Edge(middle, 0, 1, 1), Edge(bottom, 0, 1, 2)]
    pts = np.vstack([_along(xy, 0.03) for xy in (top, middle, bottom)])
    assert theta_rings([0, 1, 2], edges, pts, radius) is None


def test_a_hole_whose_side_slants_along_the_wall_is_a_hole():
    """The hole sweep's seed 3 (`benchmarks.holes`): the square's side runs along the wall at
    a slant from 0.4 ε, so the walls merge over part of the shared piece (its denser half
    holds 1.3 x the points per length), and two pieces cross by a junction, leaving a sliver
    face. It was one open piece."""
    rng = np.random.default_rng(3)
    rings = hole_by_the_wall(0.4, rng.uniform(0, 360), rng.uniform(0, 90))
    pts = sample_rings(rings, spacing=EPS / 3, noise=EPS / 8, seed=3)
    _outline_and_hole(pts)


def test_a_bare_chord_where_two_shapes_overlap_is_no_shared_wall():
    """Two squares that overlap by a hair: their union's outline runs round both, and the
    march's chord across the stretch where they meet has no wall along it (scikit-image's
    random shapes, seed 14, came out as two outlines where the truth is one)."""
    radius = 0.1
    left = np.array([[0.0, 0.0], [-1.0, 0.0], [-1.0, 1.0], [0.0, 1.0]])
    right = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    chord = np.array([[0.0, 0.0], [0.0, 1.0]])
    edges = [Edge(left, 0, 1, 0), Edge(chord, 0, 1, 1), Edge(right, 0, 1, 2)]
    pts = np.vstack([_along(left, 0.03), _along(right, 0.03)])
    assert theta_rings([0, 1, 2], edges, pts, radius) is None


def test_an_outline_drawn_twice_is_no_outline_and_hole():
    """Two rings a third of a radius apart all the way round (a wavy wall of the turbine
    blade's root, followed as two chains side by side, gave such an outline and "hole": a
    hollow layer where the section is solid) are one outline; a hole that runs along its
    outline's wall for one side is a hole."""
    radius = 0.1
    square = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 2.0], [0.0, 2.0]])
    inner = np.array([[0.03, 0.03], [3.97, 0.03], [3.97, 1.97], [0.03, 1.97]])
    hole = np.array([[0.05, 0.5], [1.0, 0.5], [1.0, 1.5], [0.05, 1.5]])
    assert _side_by_side([square, inner], radius)
    assert not _side_by_side([square, hole], radius)
