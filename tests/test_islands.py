"""Small shapes on their own (`wavepoly.ordering.islands`, and the joins, tips and absorbed
nodes that must not reach across empty space to them): stars in a photograph at a coarse
tolerance, rivets in a slice."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

import wavepoly
from benchmarks.specks import shapes_drawn
from wavepoly.ordering.islands import ISLAND_POINTS, SPECK_EXTENT, speck_contours
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
    hull, as does a group up to `SPECK_EXTENT` tolerances across that nothing drew; a wider
    one, and a speck tied to a larger contour, are left as they are."""
    def circle(n: int, radius: float, centre: float) -> np.ndarray:
        t = np.linspace(0, 2 * np.pi, n, endpoint=False)
        return radius * np.column_stack([np.cos(t), np.sin(t)]) + [centre, 0.0]

    speck, mid, wide = circle(9, 0.4 * EPS, 0.0), circle(24, EPS, 10.0), circle(40, 1.5, 20.0)
    assert np.hypot(*np.ptp(mid, axis=0)) < SPECK_EXTENT * EPS < np.hypot(*np.ptp(wide, axis=0))
    pts = np.vstack([speck, mid, wide])
    scrap = OrderedContour(speck[:3], False, np.arange(3))
    contours, outliers = speck_contours([scrap], np.arange(3, len(pts)), pts, EPS, EPS)
    assert np.array_equal(outliers, np.arange(33, len(pts)))
    assert [len(c.members) for c in contours] == [9, 24]
    assert all(c.closed and shapely.Polygon(c.points).is_valid for c in contours)
    tied = OrderedContour(pts[:12], False, np.arange(12))  # one contour through both: left
    contours, outliers = speck_contours([tied], np.arange(33, len(pts)), pts, EPS, EPS)
    assert contours == [tied]


@pytest.mark.parametrize("seed", [3, 5])
def test_specks_drawn_as_a_line_through_them_are_rings(seed):
    """Ellipses 0.5-1.5 tolerances across: a speck 1.4 across of a dozen points was drawn as
    an open line through it (one in each of these images); it is its hull now."""
    rings = scattered_ellipses(30, across=(0.5 * EPS, 1.5 * EPS), clearance=2 * EPS,
                               box=60 * EPS, seed=seed)
    pts = sample_rings(rings, spacing=EPS / 3, seed=seed)
    result = wavepoly.fit(pts, EPS)
    assert all(c.closed for c in result.contours)
    assert all(len(drawn) == 1 for drawn in shapes_drawn(rings, result.contours))
    assert independent_problems(result) == []


def test_a_loop_only_scraps_drew_is_its_hull_and_a_dash_is_not():
    """`speck_contours`: a ring 2.5 tolerances across that an open scrap drew becomes its
    hull (its points surround its centre); a noisy straight dash as long, drawn the same
    way, is left a line (its points near the middle lie all round its centre); and on a
    noisy scan's outliers read again (``scraps`` False) both are left."""
    t = np.linspace(0, 2 * np.pi, 16, endpoint=False)
    loop = 0.9 * EPS * np.column_stack([np.cos(t), np.sin(t)])
    dash = np.column_stack([np.linspace(10, 12.5, 30), np.zeros(30)])
    dash += np.random.default_rng(1).normal(scale=EPS / 8, size=dash.shape)
    pts = np.vstack([loop, dash])
    assert np.hypot(*np.ptp(loop, axis=0)) > 2 * EPS
    scraps = [OrderedContour(loop[2:9], False, np.arange(16)),
              OrderedContour(dash[[0, -1]], False, np.arange(16, 46))]
    contours, outliers = speck_contours(scraps, np.empty(0, dtype=np.intp), pts, EPS, EPS)
    assert len(outliers) == 0
    assert [(c.closed, len(c.members)) for c in contours] == [(False, 30), (True, 16)]
    assert shapely.Polygon(contours[1].points).is_valid
    # a noisy scan's outliers read again: scatter beside a wall, whose hull is a sliver
    contours, _ = speck_contours(scraps, np.empty(0, dtype=np.intp), pts, EPS, EPS,
                                 scraps=False)
    assert contours == scraps


def _leg(centre, rng, n=40, radius=0.02, scatter=0.004):
    """A chair leg's returns, seen from round about: a ring of ``radius`` with scatter."""
    t = rng.uniform(0, 2 * np.pi, n)
    r = radius + rng.normal(0, scatter, n)
    return np.asarray(centre) + np.column_stack([r * np.cos(t), r * np.sin(t)])


def test_a_noisy_scans_leg_seen_from_round_about_is_its_hull():
    """On a noisy laser map a chair's leg is a speck of returns among the outliers: it
    becomes the ring of its hull, every point within the tolerance of it. A person seen from
    one side (an arc), a dash of scatter, and a leg with strays of a wall within the radius
    stay outliers."""
    from wavepoly.ordering.islands import clutter_specks

    rng = np.random.default_rng(0)
    leg = _leg((0.0, 0.0), rng)
    t = rng.uniform(-np.pi / 2, np.pi / 2, 40)
    arc = np.column_stack([2 + 0.15 * np.cos(t), 0.15 * np.sin(t)])
    dash = np.column_stack([rng.uniform(4, 4.2, 40), rng.normal(0, 0.004, 40)])
    crowded = np.vstack([_leg((6.0, 0.0), rng), [[6.08, 0.0], [6.09, 0.02]]])
    pts = np.vstack([leg, arc, dash, crowded])
    outliers = np.arange(len(pts) - 2)  # the two strays belong to a wall's contour
    rings, left = clutter_specks(outliers, pts, 0.1, 0.1)
    assert len(rings) == 1 and rings[0].closed
    assert np.array_equal(np.sort(rings[0].members), np.arange(len(leg)))
    ring = shapely.LinearRing(rings[0].points)
    assert shapely.distance(shapely.points(leg), ring).max() <= 0.1
    assert np.array_equal(left, np.arange(len(leg), len(pts) - 2))


def test_a_made_up_maps_chair_legs_are_rings_on_their_surfaces():
    """Map 1 at 0.1 (`benchmarks.laser`): the legs of its chairs and tables, specks the
    march drew as nothing or as lines to the next leg, are small rings, each on a true
    surface; the output stays valid."""
    from benchmarks.laser import laser_map

    pts, walls = laser_map(1)
    result = wavepoly.fit(pts, 0.1)
    assert independent_problems(result) == [] and result.validity.valid
    small = [c for c in result.contours
             if c.closed and np.ptp(c.vertices, axis=0).max() < SPECK_EXTENT * 0.1]
    assert len(small) >= 5
    assert max(shapely.distance(walls, shapely.Polygon(c.vertices)) for c in small) <= 0.05
