"""Nodes between two walls about a reach apart (`wavepoly.ordering.walls.onto_walls`)."""

from __future__ import annotations

import numpy as np
import pytest

import wavepoly
from benchmarks.near_rings import OTHER_CIRCLE_SHARE, _inner_share
from wavepoly.ordering.noise import noise_adaptive_nodes
from wavepoly.ordering.walls import _parallel_sides, onto_walls
from wavepoly.samples import sample_rings

RADIUS = 0.1


def _nodes(pts):
    nodes, atoms, _ = noise_adaptive_nodes(pts, RADIUS, False, RADIUS)
    return nodes, atoms


def _walls(gap, noise, seed=0, length=6.0):
    """Two straight walls ``gap`` radii apart, sampled every radius / 3 at random, with
    Gaussian scatter ``noise`` radii."""
    rng = np.random.default_rng(seed)
    n = int(length / (RADIUS / 3))
    walls = [np.column_stack([rng.uniform(0, length, n), np.full(n, y)])
             for y in (0.0, gap * RADIUS)]
    pts = np.vstack(walls)
    return pts + rng.normal(scale=noise * RADIUS, size=pts.shape)


@pytest.mark.parametrize("seed", range(3))
def test_nodes_between_walls_a_reach_apart_go_onto_the_walls(seed):
    """Walls 1.5 radii apart with scatter a quarter radius: a node whose neighbourhood is
    centred near the middle takes its centroid from both walls and sits between them (a tenth
    to a quarter of the nodes); after, a few hundredths, and the nodes on a wall lie on it."""
    gap = 1.5 * RADIUS
    nodes, atoms = _nodes(_walls(1.5, 0.25, seed))
    inner = (nodes.xy[:, 0] > 0.5) & (nodes.xy[:, 0] < 5.5)  # away from the walls' ends

    def between(xy):
        return np.abs(xy[:, 1] - gap / 2) < gap / 4

    before = between(nodes.xy[inner]).mean()
    assert before > 0.1
    moved = onto_walls(nodes, atoms, RADIUS)
    inner = (moved.xy[:, 0] > 0.5) & (moved.xy[:, 0] < 5.5)
    assert between(moved.xy[inner]).mean() < min(0.05, 0.3 * before)
    assert len(moved.xy) == len(nodes.xy)  # moved, never dropped
    shifted = np.any(moved.xy != nodes.xy, axis=1)
    off_wall = np.minimum(np.abs(moved.xy[shifted, 1]), np.abs(moved.xy[shifted, 1] - gap))
    assert np.percentile(off_wall, 90) < gap / 4


def test_a_single_noisy_wall_is_left_alone():
    """One wall with scatter a quarter radius: its two-means halves are no two walls."""
    rng = np.random.default_rng(1)
    pts = np.column_stack([rng.uniform(0, 6, 180), np.zeros(180)])
    pts += rng.normal(scale=0.25 * RADIUS, size=pts.shape)
    nodes, atoms = _nodes(pts)
    moved = onto_walls(nodes, atoms, RADIUS)
    assert np.array_equal(moved.xy, nodes.xy)


def test_the_node_at_a_narrow_fork_stays():
    """Two walls meeting at 40 degrees (a glyph's arm meeting its stem): near the fork they
    are a radius or two apart, but not side by side; the nodes between them join the two
    and stay where they are."""
    s = np.linspace(0, 3, 300)
    angle = np.radians(40)
    pts = np.vstack([np.column_stack([s, np.zeros_like(s)]),
                     np.column_stack([s * np.cos(angle), s * np.sin(angle)])])
    nodes, atoms = _nodes(pts)
    moved = onto_walls(nodes, atoms, RADIUS)
    assert np.array_equal(moved.xy, nodes.xy)


@pytest.mark.parametrize(("radius", "seed"), [(3.0, 1), (3.0, 3), (8.0, 2), (8.0, 3)])
def test_rings_a_reach_apart_with_scatter_a_quarter_tolerance_stay_two_rings(radius, seed):
    """The validity benchmark's near rings 1.5 ε apart with noise ε / 4 (each band four
    standard deviations wide leaves half an ε empty between them): two closed rings, one on
    each circle. The march stepped between the circles through nodes in the middle and came
    out in open pieces or rings folded onto both."""
    eps = 0.1
    t = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    circle = np.column_stack([np.cos(t), np.sin(t)])
    pts = sample_rings([radius * circle, (radius + 1.5 * eps) * circle], spacing=eps / 3,
                       noise=0.25 * eps, seed=100 + seed)
    result = wavepoly.fit(pts, eps)
    assert [c.closed for c in result.contours] == [True, True]
    inner = sorted(_inner_share(c.vertices, radius + 0.75 * eps) for c in result.contours)
    assert inner[0] <= OTHER_CIRCLE_SHARE and inner[1] >= 1 - OTHER_CIRCLE_SHARE
    assert result.validity.valid and len(result.outliers) == 0


def test_walls_at_an_angle_are_not_side_by_side():
    """`_parallel_sides`: two walls 1.5 radii apart either side of the line, level or turned
    apart by 30 degrees (a narrow wedge's walls)."""
    from wavepoly.ordering.neighbourhoods import Atoms, perpendicular_offsets

    s = np.linspace(-0.15, 0.15, 61)
    for turn, parallel in ((0.0, True), (30.0, False)):
        half = np.radians(turn / 2)
        walls = [np.column_stack([s, side * (0.075 + s * np.tan(half))]) for side in (-1, 1)]
        xy = np.vstack(walls)
        atoms = Atoms(xy, np.ones(len(xy)), np.zeros((len(xy), 3)), np.zeros((len(xy), 2), int))
        centre, tangent = np.zeros((1, 2)), np.array([[1.0, 0.0]])
        o = perpendicular_offsets(centre, tangent, atoms, 0.2)
        assert _parallel_sides(centre, tangent, atoms, o, np.zeros(1))[0] == parallel


def test_walls_two_reaches_apart_keep_their_own_nodes():
    """Walls 2.5 radii apart with scatter a quarter radius: a neighbourhood on one wall does
    not reach the other's band (`NEAR_EDGE`), the march keeps to its wall, and hardly a node
    moves (without that bound, nine in ten of these moved)."""
    nodes, atoms = _nodes(_walls(2.5, 0.25, 0))
    moved = onto_walls(nodes, atoms, RADIUS)
    assert np.any(moved.xy != nodes.xy, axis=1).mean() < 0.1
