"""Small shapes on their own (`wavepoly.ordering.islands`, and the joins, tips and absorbed
nodes that must not reach across empty space to them): stars in a photograph at a coarse
tolerance, rivets in a slice."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

import wavepoly
from benchmarks.specks import shapes_drawn
from wavepoly.ordering.islands import ISLAND_POINTS, speck_contours
from wavepoly.ordering.neighbourhoods import point_clusters
from wavepoly.samples import sample_rings, scattered_ellipses
from wavepoly.types import OrderedContour

from .conftest import distance_to_output
from .truth import independent_problems

EPS = 1.0


@pytest.mark.parametrize("seed", [0, 2, 3])
def test_small_shapes_two_tolerances_apart_are_drawn_apart(seed):
    """Thirty ellipses 1.5-4 tolerances across, at least 2 apart, sampled every ε / 3: each
    drawn by closed contours of its own. Before, a lone node of one was absorbed into a ring
    8 radii away, and a small ring beside another's sharp turn was taken as its tip: one
    polygon round two shapes."""
    rings = scattered_ellipses(30, across=(1.5 * EPS, 4 * EPS), clearance=2 * EPS,
                               box=60 * EPS, seed=seed)
    pts = sample_rings(rings, spacing=EPS / 3, seed=seed)
    result = wavepoly.fit(pts, EPS)
    assert all(len(drawn) == 1 for drawn in shapes_drawn(rings, result.contours))
    assert set().union(*shapes_drawn(rings, result.contours)) == set(range(len(rings)))
    assert all(c.closed for c in result.contours)
    assert independent_problems(result) == [] and len(result.outliers) == 0
    assert distance_to_output(pts, result).max() <= EPS * (1 + 1e-9)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_specks_are_small_polygons_of_their_own(seed):
    """Ellipses 0.5-1.5 tolerances across, 2 apart: each speck of `ISLAND_POINTS` points or
    more lies within a tolerance of its points' hull, which is its ring (fewer make no
    polygon and are outliers); before, most were outliers, and others open lines from one
    speck to the next across 3 radii of empty space."""
    rings = scattered_ellipses(30, across=(0.5 * EPS, 1.5 * EPS), clearance=2 * EPS,
                               box=60 * EPS, seed=seed)
    pts = sample_rings(rings, spacing=EPS / 3, seed=seed)
    result = wavepoly.fit(pts, EPS)
    assert all(len(drawn) == 1 for drawn in shapes_drawn(rings, result.contours))
    assert independent_problems(result) == []
    speck = point_clusters(pts, EPS)
    few = np.bincount(speck) < ISLAND_POINTS
    assert few[speck[result.outliers]].all()
    assert sum(c.closed for c in result.contours) >= len(rings) - few.sum() - 1
    drawn = np.setdiff1d(np.arange(len(pts)), result.outliers)
    assert distance_to_output(pts[drawn], result).max() <= EPS * (1 + 1e-9)


def test_a_speck_gives_way_to_its_hull_and_a_larger_group_does_not():
    """`speck_contours`: a speck's scrap of a line and its outliers become one ring, its
    hull; a group wider than `ISLAND_EXTENT` tolerances and a speck tied to a larger contour
    are left as they are."""
    t = np.linspace(0, 2 * np.pi, 9, endpoint=False)
    speck = 0.4 * EPS * np.column_stack([np.cos(t), np.sin(t)])
    t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    wide = 1.5 * EPS * np.column_stack([np.cos(t), np.sin(t)]) + [20.0, 0.0]
    pts = np.vstack([speck, wide])
    scrap = OrderedContour(speck[:3], False, np.arange(3))
    contours, outliers = speck_contours([scrap], np.arange(3, len(pts)), pts, EPS, EPS)
    assert np.array_equal(outliers, np.arange(9, len(pts)))  # 4.2 tolerances: no speck
    [hull] = contours
    assert hull.closed and np.array_equal(hull.members, np.arange(9))
    assert shapely.Polygon(hull.points).is_valid and len(hull.points) == 9
    tied = OrderedContour(pts[:12], False, np.arange(12))  # one contour through both: left
    contours, outliers = speck_contours([tied], np.arange(12, len(pts)), pts, EPS, EPS)
    assert contours == [tied] and len(outliers) == len(pts) - 12
