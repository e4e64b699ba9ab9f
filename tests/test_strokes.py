"""Dense noisy walls: no spike from a straight stretch; strokes among the outliers are contours."""

from __future__ import annotations

from functools import partial

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

import wavepoly
from wavepoly.ordering import _read
from wavepoly.ordering.contours import _cover_cut_corners
from wavepoly.ordering.strokes import CLEARANCE, stroke_contours
from wavepoly.types import OrderedContour

from .conftest import distance_to_output, teeth

SCATTER = 0.03  # a laser map's wall scatter (Intel: about 0.03), at a tolerance of 0.1
TOLERANCE = 0.1


def _wall(rng, n=20000, length=10.0):
    return np.column_stack([rng.uniform(0, length, n), rng.normal(0, SCATTER, n)])


@pytest.fixture(scope="module")
def tee_junctions():
    """A 10 m wall with nine short walls 0.5 m long standing on it, 1 m apart (a corridor
    with the walls of its rooms): 14.5 m of walls."""
    rng = np.random.default_rng(2)
    stubs = [np.column_stack([x + rng.normal(0, SCATTER, 800), rng.uniform(0, 0.5, 800)])
             for x in np.arange(1.0, 10.0)]
    pts = np.vstack([_wall(rng), *stubs])
    return pts, wavepoly.fit(pts, TOLERANCE)


def test_short_walls_meeting_a_wall_are_walls_not_spikes(tee_junctions):
    """The feet of the short walls are farther than the radius from the long wall's chain. They
    were reached by spikes up each short wall and back, 23.8 m of lines for 14.5 m of walls;
    now each short wall is a piece of its own that meets the wall (or the wall's vertex at its
    foot), and nothing is drawn twice."""
    pts, res = tee_junctions
    assert res.validity.valid
    inliers = np.setdiff1d(np.arange(len(pts)), res.outliers)
    assert distance_to_output(pts[inliers], res).max() <= TOLERANCE * (1 + 1e-9)
    assert len(res.outliers) <= 0.01 * len(pts)
    drawn = sum(shapely.length(shapely.linestrings(c.vertices)) for c in res.contours)
    assert 0.97 * 14.5 <= drawn <= 1.05 * 14.5
    tops = shapely.points(np.column_stack([np.arange(1.0, 10.0), np.full(9, 0.5)]))
    assert (distance_to_output(shapely.get_coordinates(tops), res) <= TOLERANCE).all()
    # the pieces meet at the junctions: each short wall's piece ends on the long wall's
    wall = max(res.contours, key=lambda c: np.ptp(c.vertices[:, 0]))
    line = shapely.linestrings(wall.vertices)
    stubs = [c for c in res.contours if c is not wall]
    assert len(stubs) >= 7
    assert all(shapely.distance(line, shapely.linestrings(c.vertices)) < 1e-9 for c in stubs)


def test_no_teeth_on_a_straight_dense_wall_with_a_ghost(tee_junctions):
    """A wall with a second, fainter band 1.6 tolerances beside it (a pass whose registration
    drifted): no vertex turns back between short edges, and the outliers are few."""
    rng = np.random.default_rng(1)
    ghost = np.column_stack([rng.uniform(2, 6, 3000), rng.normal(0.16, 0.015, 3000)])
    pts = np.vstack([_wall(rng), ghost])
    res = wavepoly.fit(pts, TOLERANCE)
    assert res.validity.valid and teeth(res) == 0
    assert len(res.outliers) <= 0.01 * len(pts)
    assert distance_to_output(pts[res.outliers], res).min() > TOLERANCE


def _straight_chain():
    return np.column_stack([np.linspace(0, 2, 21), np.zeros(21)])


def test_a_group_beside_a_straight_stretch_is_no_corner_on_a_dense_curve():
    """Eight points 0.08 off the middle of a straight chain: a corner it cut, on a sparse
    sample; on a dense curve (`bends_only`), not."""
    group = np.column_stack([np.linspace(0.96, 1.04, 8), np.full(8, 0.08)])
    chain = _straight_chain()
    sparse, _ = _cover_cut_corners(chain, group, False, 0.1)
    dense, far = _cover_cut_corners(chain, group, False, 0.1, bends_only=True)
    assert len(sparse) > len(chain)
    np.testing.assert_array_equal(dense, chain)
    assert len(far) == 0  # within the radius: members, as before


def test_a_rounded_corner_is_still_restored_on_a_dense_curve():
    """A right angle at (1, 0) the neighbourhoods rounded off (an arc of 0.2 that passes 0.08
    inside it): the points beyond the chain are still inserted, for the chain bends there."""
    theta = np.linspace(-np.pi / 2, 0, 7)
    chain = np.vstack([np.column_stack([np.linspace(0, 0.75, 16), np.zeros(16)]),
                       np.column_stack([0.8 + 0.2 * np.cos(theta), 0.2 + 0.2 * np.sin(theta)]),
                       np.column_stack([np.ones(16), np.linspace(0.25, 1, 16)])])
    s = np.linspace(0, 1, 200)
    members = np.vstack([np.column_stack([s, np.zeros(200)]), np.column_stack([np.ones(200), s])])
    covered, _ = _cover_cut_corners(chain, members, False, 0.1, bends_only=True)
    assert np.min(np.linalg.norm(covered - [1.0, 0.0], axis=1)) < 0.03


def _reread(pts, radius=TOLERANCE):
    return partial(_read, radius=radius, given=radius, seed=0, min_points=4, notes=(),
                   spacing=0.0, tolerance=None, sparse=True, again=True)


def test_a_ghost_band_among_the_outliers_becomes_a_stroke_clear_of_the_wall():
    rng = np.random.default_rng(5)
    wall = OrderedContour(_straight_chain() * [5, 1], False, np.empty(0, dtype=np.intp))
    ghost = np.column_stack([rng.uniform(2, 6, 1500), rng.normal(0.16, 0.01, 1500)])
    strays = np.column_stack([rng.uniform(0, 10, 30), rng.uniform(0.3, 1.0, 30)])
    pts = np.vstack([ghost, strays])
    outliers = np.arange(len(pts))
    found, left = stroke_contours(pts, outliers, [wall], TOLERANCE, TOLERANCE, _reread(pts))
    assert len(found) == 1 and not found[0].closed
    stroke = shapely.linestrings(found[0].points)
    assert shapely.distance(stroke, shapely.linestrings(wall.points)) >= CLEARANCE * TOLERANCE
    assert stroke.length > 3.5
    assert set(left.tolist()) >= set(range(1500, 1530))  # the strays stay outliers
    assert len(left) < 1500 + 30 + 0.01 * 1500


def test_a_stroke_is_cut_where_it_would_cross_a_contour():
    """A line of outliers across a wall (its middle held by the wall in a real reading): two
    pieces, each clear of the wall."""
    rng = np.random.default_rng(6)
    wall = OrderedContour(_straight_chain() * [5, 1], False, np.empty(0, dtype=np.intp))
    across = np.column_stack([rng.normal(5, 0.01, 1200), rng.uniform(-1, 1, 1200)])
    found, _ = stroke_contours(across, np.arange(1200), [wall], TOLERANCE, TOLERANCE,
                               _reread(across))
    assert len(found) == 2
    for c in found:
        line = shapely.linestrings(c.points)
        assert shapely.distance(line, shapely.linestrings(wall.points)) >= (
            CLEARANCE * TOLERANCE * (1 - 1e-9))


#: A floor plan: two rooms and a corridor's end, with doors 1 m wide at (4.5, 0), (4, 3) and
#: (6, 6), and a wall ending in the right-hand room.
FLOOR_PLAN = [((0, 0), (4, 0)), ((5, 0), (10, 0)), ((10, 0), (10, 6)), ((10, 6), (6.5, 6)),
              ((5.5, 6), (0, 6)), ((0, 6), (0, 0)), ((4, 0), (4, 2.5)), ((4, 3.5), (4, 6)),
              ((6, 3), (10, 3))]
DOORS = [(4.5, 0.0), (4.0, 3.0), (6.0, 6.0)]


def _floor_plan_scan(seed, strays):
    rng = np.random.default_rng(seed)
    walls = []
    for a, b in FLOOR_PLAN:
        a, b = np.asarray(a, float), np.asarray(b, float)
        n = int(1500 * np.linalg.norm(b - a))
        t = rng.uniform(0, 1, n)[:, None]
        normal = np.array([a[1] - b[1], b[0] - a[0]]) / np.linalg.norm(b - a)
        walls.append(a + t * (b - a) + rng.normal(0, SCATTER, (n, 1)) * normal)
    floor = np.column_stack([rng.uniform(0.3, 9.7, strays), rng.uniform(0.3, 5.7, strays)])
    return np.vstack([*walls, floor])


@pytest.mark.parametrize("seed", [0, 1])
def test_strays_on_the_floor_draw_no_walls_and_doors_stay_open(seed):
    """Returns scattered over the floor (people, dust), one per 1.5 square metres: a stray's
    neighbourhood holds one point, which has no tangent, so it is no node of a chain (strays
    had been chained into lines across the rooms, vertices 1.6-1.8 m off any wall); and a
    chain's ends 1 m apart across a door join only along points (the left room had closed
    through its door)."""
    pts = _floor_plan_scan(seed, 60)
    res = wavepoly.fit(pts, TOLERANCE)
    assert res.validity.valid
    walls = shapely.union_all([shapely.linestrings([a, b]) for a, b in FLOOR_PLAN])
    vertices = np.vstack([c.vertices for c in res.contours])
    assert shapely.distance(shapely.points(vertices), walls).max() <= 2 * TOLERANCE
    drawn = shapely.union_all([shapely.linestrings(
        np.vstack([c.vertices, c.vertices[:1]]) if c.closed else c.vertices)
        for c in res.contours])
    assert (shapely.distance(shapely.points(DOORS), drawn) > 0.4).all()
    assert len(res.contours) <= 6 and len(res.outliers) <= 0.01 * len(pts) + 60


@st.composite
def floor_plans(draw):
    """A few axis-parallel walls 1-5 m long on a 10 m floor, scanned with a laser map's
    scatter and density, and strays on the floor."""
    seed = draw(st.integers(0, 2**31 - 1))
    n_walls = draw(st.integers(2, 6))
    strays = draw(st.integers(0, 80))
    rng = np.random.default_rng(seed)
    walls = []
    for _ in range(n_walls):
        start = rng.uniform(0, 8, 2)
        end = start.copy()
        axis = int(rng.integers(2))
        end[axis] = min(start[axis] + rng.uniform(1, 5), 10.0)
        walls.append((start, end))
    return walls, _scan(rng, walls, strays)


def _scan(rng, walls, strays):
    parts = []
    for a, b in walls:
        n = int(800 * np.linalg.norm(b - a))
        t = rng.uniform(0, 1, n)[:, None]
        normal = np.array([a[1] - b[1], b[0] - a[0]]) / np.linalg.norm(b - a)
        parts.append(a + t * (b - a) + rng.normal(0, SCATTER, (n, 1)) * normal)
    parts.append(rng.uniform(0, 10, (strays, 2)))
    return np.vstack(parts)


@settings(max_examples=12, deadline=None)
@given(floor_plans())
def test_floor_plans_are_valid_and_within_the_tolerance(plan):
    """Walls crossing, meeting at T and L junctions or running side by side, with strays:
    the result is valid geometry, every point not listed is within the tolerance, and no
    listed point is."""
    _, pts = plan
    res = wavepoly.fit(pts, TOLERANCE)
    assert res.validity.valid, res.validity.problems[:3]
    inliers = np.setdiff1d(np.arange(len(pts)), res.outliers)
    assert distance_to_output(pts[inliers], res).max() <= TOLERANCE * (1 + 1e-9)
    if len(res.outliers):
        assert distance_to_output(pts[res.outliers], res).min() > TOLERANCE


def test_no_teeth_along_a_ghost_that_starts_at_a_corner():
    """The Intel map's corridor at (-4, -16.6): a wall turns a corner, and a fainter band runs
    beside one leg from the corner on, 1.2 tolerances off. The corner's rounded segments take
    a vertex out to the corner's points; each inserted vertex made the straight stretch beside
    it a bend in the next round, so vertices went on out to the band along the whole leg (a
    square wave). The stretch keeps the straightness it came with, and the band is a stroke."""
    rng = np.random.default_rng(5)
    leg = np.column_stack([rng.uniform(0, 6, 12000), rng.normal(0, SCATTER, 12000)])
    up = np.column_stack([rng.normal(0, SCATTER, 8000), rng.uniform(0, 4, 8000)])
    ghost = np.column_stack([rng.uniform(0.1, 4, 2500), rng.normal(-0.12, 0.015, 2500)])
    pts = np.vstack([leg, up, ghost])
    res = wavepoly.fit(pts, TOLERANCE)
    assert res.validity.valid and teeth(res) == 0
    assert len(res.outliers) <= 0.01 * len(pts)
