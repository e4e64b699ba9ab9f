"""Rings folded onto two walls side by side, end to end (`wavepoly.ordering.folds`), and
circles 1.5 tolerances apart drawn one ring each."""

import numpy as np
import pytest

import wavepoly
from wavepoly.ordering.folds import unfold_rings
from wavepoly.samples import sample_rings
from wavepoly.types import OrderedContour

from .truth import independent_problems

RADIUS = 0.01


def _arc(r, start, stop, step=0.7 * RADIUS):
    """Nodes every ``step`` along a circle's arc about the origin from ``start`` to ``stop``."""
    t = np.linspace(start, stop, max(int(abs(stop - start) * r / step), 2))
    return r * np.column_stack([np.cos(t), np.sin(t)])


def _fold(inner, outer, start, stop):
    """A thin ring walked out along the ``inner`` circle and back along the ``outer`` one."""
    return np.vstack([_arc(inner, start, stop), _arc(outer, stop, start)])


def _circles(radii, n=1200):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.vstack([r * np.column_stack([np.cos(t), np.sin(t)]) for r in radii])


def _contours(rings, pts):
    """Each ring with the points nearest to it as its members."""
    d = np.array([np.min(np.linalg.norm(pts[:, None] - r[None], axis=2), axis=1)
                  for r in rings])
    return [OrderedContour(r, True, np.flatnonzero(np.argmin(d, axis=0) == k))
            for k, r in enumerate(rings)]


def test_two_folded_rings_come_apart_into_the_two_circles():
    """Two rings each half on one circle and half on the other, turning back 3 radii short of
    where the other turns back: the walls' points run on through both gaps."""
    inner, outer, gap = 1.0, 1.0 + 1.5 * RADIUS, 1.5 * RADIUS
    rings = [_fold(inner, outer, gap, np.pi - gap), _fold(inner, outer, np.pi + gap,
                                                          2 * np.pi - gap)]
    pts = _circles([inner, outer])
    out = unfold_rings(_contours(rings, pts), pts, RADIUS)
    assert len(out) == 2 and all(c.closed for c in out)
    radii = sorted((np.hypot(*c.points.T) for c in out), key=np.mean)
    assert np.ptp(radii[0]) < 1e-9 and np.ptp(radii[1]) < 1e-9
    assert [radii[0][0], radii[1][0]] == pytest.approx([inner, outer])
    assert sorted(len(c.members) for c in out) == [1200, 1200]


def test_two_thin_slabs_end_to_end_stay_two_slabs():
    """Two thin arcs of a washer with a bare gap between their ends (no point there): each is
    the outline of a slab, and no join runs across the gaps."""
    inner, outer, gap = 1.0, 1.0 + 1.5 * RADIUS, 1.5 * RADIUS
    rings = [_fold(inner, outer, gap, np.pi - gap), _fold(inner, outer, np.pi + gap,
                                                          2 * np.pi - gap)]
    pts = np.vstack(rings)
    out = unfold_rings(_contours(rings, pts), pts, RADIUS)
    assert [len(c.points) for c in out] == [len(r) for r in rings]


def test_a_folded_ring_facing_another_at_one_place_stays():
    """A thin ring that turns back by another only at one of its ends (two slabs end to end
    whose gap the points fill) is no ring swapped at two places: left as it is."""
    inner, outer, gap = 1.0, 1.0 + 1.5 * RADIUS, 1.5 * RADIUS
    rings = [_fold(inner, outer, gap, 0.5 * np.pi - gap),
             _fold(inner, outer, 0.5 * np.pi + gap, np.pi)]
    t = np.linspace(0, np.pi, 800)
    pts = np.vstack([r * np.column_stack([np.cos(t), np.sin(t)]) for r in (inner, outer)])
    out = unfold_rings(_contours(rings, pts), pts, RADIUS)
    assert [len(c.points) for c in out] == [len(r) for r in rings]


@pytest.mark.parametrize(("radius", "noise", "seed"), [(8.0, 3 / 16, 100), (8.0, 3 / 16, 102),
                                                       (3.0, 3 / 16, 104), (3.0, 1 / 8, 106),
                                                       (3.0, 1 / 4, 106), (8.0, 1 / 4, 106)])
def test_circles_one_and_a_half_tolerances_apart_are_drawn_one_ring_each(radius, noise, seed):
    """Circles 1.5 ε apart sampled every ε / 3 with noise up to ε / 4 (a clean sampling):
    where one circle's points thin out the march swapped between them. These came out as two
    rings each walked out along one circle and back along the other, or one ring round both
    with the second circle dropped (a theta's third piece taken for a chord inside the
    first). Each ring now draws one circle: at most a tenth of its vertices nearer the other
    (a polygon's chords cut inside its circle by up to ε, its vertices lie on it). With
    noise ε / 4 (seed 106) a fold's hairpin closed across the band in one chord 15 radii
    long, and its stretches' ends lay farther apart than a join reached."""
    eps = 0.1
    t = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    rings = [r * np.column_stack([np.cos(t), np.sin(t)]) for r in (radius, radius + 1.5 * eps)]
    pts = sample_rings(rings, spacing=eps / 3, noise=noise * eps, seed=seed)
    result = wavepoly.fit(pts, eps)
    assert [c.closed for c in result.contours] == [True, True]
    assert len(result.outliers) == 0 and independent_problems(result) == []
    inner = sorted(float(np.mean(np.hypot(*c.vertices.T) < radius + 0.75 * eps))
                   for c in result.contours)
    assert inner[0] <= 0.1 and inner[1] >= 0.9


def test_chains_crossing_at_four_places_swap_back_onto_their_circles():
    """Two chains that each jump between two circles 1.5 radii apart at four places, crossing
    each other there: at every crossing each continues along the other's arc, and each comes
    out on one circle (the swap handled two crossings only, and the chains were split into
    open pieces at the crossings)."""
    from wavepoly.ordering.untangle import swap_crossed_stretches

    inner, outer = 1.0, 1.0 + 1.5 * RADIUS
    quarter = [(k * np.pi / 2, (k + 1) * np.pi / 2) for k in range(4)]
    one = np.vstack([_arc(inner if k % 2 == 0 else outer, a, b)[:-1]
                     for k, (a, b) in enumerate(quarter)])
    two = np.vstack([_arc(outer if k % 2 == 0 else inner, a, b)[:-1]
                     for k, (a, b) in enumerate(quarter)])
    pts = _circles([inner, outer])
    out = swap_crossed_stretches(_contours([one, two], pts), pts)
    radii = sorted((np.hypot(*c.points.T) for c in out), key=np.mean)
    assert [float(np.ptp(r)) for r in radii] == pytest.approx([0.0, 0.0], abs=1e-9)
    assert [radii[0][0], radii[1][0]] == pytest.approx([inner, outer])
    assert sum(len(c.members) for c in out) == len(pts)


@pytest.mark.parametrize(("radius", "seed"), [(3.0, 105)])
def test_circles_whose_chains_cross_at_six_places_come_out_one_ring_each(radius, seed):
    """Circles 1.5 ε apart with noise 3ε / 16 whose two chains crossed each other at six
    places: split there, they came out as ten open pieces; swapped back at every crossing,
    two rings, each on its circle."""
    test_circles_one_and_a_half_tolerances_apart_are_drawn_one_ring_each(radius, 3 / 16, seed)
