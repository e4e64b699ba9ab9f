"""A ring standing for two walls closer than the radius, drawn as an annulus's two rings
(`wavepoly.ordering.annuli`)."""

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

import wavepoly
from wavepoly.ordering.annuli import split_annuli
from wavepoly.samples import sample_rings
from wavepoly.types import OrderedContour

from .conftest import distance_to_output
from .truth import independent_problems

EPS = 1.0


def _circle(r, n=720):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return r * np.column_stack([np.cos(t), np.sin(t)])


def _square(half, n_side=200):
    s = np.linspace(-half, half, n_side, endpoint=False)
    h = np.full_like(s, half)
    return np.vstack([np.column_stack([s, -h]), np.column_stack([h, s]),
                      np.column_stack([-s, h]), np.column_stack([-h, -s])])


def _annulus_fit(rings, noise=0.0, seed=200):
    pts = sample_rings(rings, spacing=EPS / 3, noise=noise * EPS, seed=seed)
    return pts, wavepoly.fit(pts, EPS)


def _assert_two_rings(pts, result, rings):
    """Two closed rings, one inside the other, valid, every point kept; and the region they
    bound is the tube's wall, not its bore: it differs from the true wall by less than the
    walls' length times the tolerance (as a slice's layer is judged against its section)."""
    assert [c.closed for c in result.contours] == [True, True]
    assert len(result.outliers) == 0
    assert not independent_problems(result)
    assert distance_to_output(pts, result).max() <= EPS * (1 + 1e-9)
    drawn = sorted(result.contours, key=lambda c: -shapely.Polygon(c.vertices).area)
    outer, inner = (shapely.Polygon(c.vertices) for c in drawn)
    assert outer.contains(inner)
    wall = shapely.Polygon(rings[0], [rings[1]])
    between = outer.difference(inner).symmetric_difference(wall).area
    assert between <= (wall.exterior.length + wall.interiors[0].length) * EPS


@pytest.mark.parametrize("gap", [0.5, 0.8, 0.9])
@pytest.mark.parametrize("radius", [5.0, 12.0])
def test_a_tube_whose_wall_is_thinner_than_the_tolerance_is_two_rings(gap, radius):
    """Two circles less than a tolerance apart, sampled exactly: the march follows them as one
    ring down the middle (every point within half the gap of it), which would fill the tube's
    bore. Its members fall into two walls all round: an outline and its hole."""
    rings = [_circle(radius + gap), _circle(radius)]
    pts, result = _annulus_fit(rings)
    _assert_two_rings(pts, result, rings)


@pytest.mark.parametrize("gap", [0.95, 0.98, 1.02])
def test_rings_a_tolerance_apart_are_two_rings_not_one_or_a_ladder(gap):
    """Two circles about a tolerance apart, sampled every sixth of one with noise a twentieth
    (as a thin shell's sliced wall is): every neighbourhood has the other wall on its rim.
    The ring down the middle must not fold where it is offset onto each wall (`_unfolded`),
    and where the march stepped across and back, leaving open pieces or lenses (each out
    along one wall and back along the other), a fifth tighter reading follows each wall
    (`tighter_reading`). 7 of these 12 cases came out as one ring, open pieces or lenses."""
    rings = [_circle(2.5), _circle(2.5 - gap * 0.1)]
    for seed in range(4):
        pts = sample_rings(rings, spacing=0.1 / 6, noise=0.1 / 20, seed=seed)
        result = wavepoly.fit(pts, 0.1)
        assert [c.closed for c in result.contours] == [True, True], seed
        assert sorted(result.parents) in ([-1, 0], [-1, 1])
        assert not independent_problems(result)
        assert distance_to_output(pts, result).max() <= 0.1 * (1 + 1e-9)


def test_a_square_tube_keeps_its_corners_on_both_rings():
    """A square tube with a wall 0.8 tolerances thick: both rings, each within the tolerance
    of its own wall (the corners kept)."""
    rings = [_square(8.8), _square(8.0)]
    pts, result = _annulus_fit(rings)
    _assert_two_rings(pts, result, rings)


def test_a_thin_tube_with_a_little_noise_is_two_rings():
    """Walls 0.8 tolerances apart with noise a sixteenth of one (the walls 13 noise levels
    apart): still two sharp groups all round."""
    rings = [_circle(8.8), _circle(8.0)]
    pts, result = _annulus_fit(rings, noise=1 / 16, seed=201)
    _assert_two_rings(pts, result, rings)


@settings(max_examples=12, deadline=None)
@given(radius=st.floats(3.0, 15.0), noise=st.sampled_from([0.0, 0.125, 0.25]),
       seed=st.integers(0, 10_000))
def test_one_wall_is_never_read_as_two(radius, noise, seed):
    """A lone circle, exact or with noise up to a quarter tolerance: one ring (a bell of
    scatter, or a chain's chords over the bend, is no second wall)."""
    pts = sample_rings([_circle(radius)], spacing=EPS / 3, noise=noise * EPS, seed=seed)
    result = wavepoly.fit(pts, EPS)
    assert [c.closed for c in result.contours] == [True]
    assert not independent_problems(result)


def test_a_ring_whose_members_lie_on_one_wall_stays_one():
    """Unit: the members on one circle, the ring through them: nothing to split."""
    pts = _circle(1.0, 600)
    ring = OrderedContour(_circle(1.0, 30), True, np.arange(600))
    assert split_annuli([ring], pts, 0.1) == [ring]


def test_a_ring_beside_a_wall_that_stops_stays_one():
    """Unit: a second wall beside the ring for four fifths of the way round, none beside the
    last fifth (a wall that ends, no tube): not an annulus, left as it is."""
    t = np.linspace(0, 2 * np.pi, 600, endpoint=False)
    beside = t[t >= 0.4 * np.pi]
    pts = np.vstack([np.column_stack([np.cos(t), np.sin(t)]),
                     1.08 * np.column_stack([np.cos(beside), np.sin(beside)])])
    ring = OrderedContour(1.04 * _circle(1.0, 60), True, np.arange(len(pts)))
    assert split_annuli([ring], pts, 0.1) == [ring]


def test_an_offset_rings_small_fold_is_cut_off_and_a_large_one_refused():
    """A square whose edge folds over itself in a small loop (as an offset of a chain that
    bends sharply does) keeps its outline; a ring twisted into a figure eight is refused."""
    from wavepoly.ordering.annuli import _unfolded

    square = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [2.1, 4.0], [1.9, 4.1],
                       [1.9, 3.9], [2.1, 3.95], [0.0, 4.0]])
    assert not shapely.Polygon(square).is_valid
    ring = _unfolded(square)
    assert ring is not None and shapely.Polygon(ring).is_valid
    assert shapely.Polygon(ring).area == pytest.approx(16.0, abs=0.05)
    eight = np.array([[0.0, 0.0], [2.0, 2.0], [4.0, 0.0], [4.0, 2.0], [2.0, 0.0], [0.0, 2.0]])
    assert _unfolded(eight) is None


def test_an_unfolded_ring_keeps_its_sense_of_travel():
    """Cut free of its fold, a clockwise ring stays clockwise."""
    from wavepoly.ordering.annuli import _unfolded

    square = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [2.1, 4.0], [1.9, 4.1],
                       [1.9, 3.9], [2.1, 3.95], [0.0, 4.0]])
    for ring in (square, square[::-1]):
        ccw = shapely.LinearRing(ring).is_ccw
        assert shapely.LinearRing(_unfolded(ring)).is_ccw == ccw
