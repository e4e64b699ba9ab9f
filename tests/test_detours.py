"""A ring's short detour onto a neighbouring ring's wall, cut off
(`wavepoly.ordering.detours`)."""

import numpy as np
import pytest

import wavepoly
from wavepoly.ordering.detours import cut_detours
from wavepoly.samples import sample_rings
from wavepoly.types import OrderedContour

from .truth import independent_problems

RADIUS = 0.1


def _circle(r, n, phase=0.0):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False) + phase
    return r * np.column_stack([np.cos(t), np.sin(t)])


def _two_circles(inner=1.0, outer=1.15):
    """Dense points on two circles, and ordered rings on each (nodes about half a radius
    apart), each ring with its own circle's points as members."""
    pts = np.vstack([_circle(inner, 2000), _circle(outer, 2000)])
    rings = [_circle(inner, 128), _circle(outer, 128, phase=0.02)]
    return pts, rings, [np.arange(2000), np.arange(2000, 4000)]


def _contours(rings, members):
    return [OrderedContour(r, True, m) for r, m in zip(rings, members)]


def test_a_detour_of_two_nodes_onto_the_other_circle_is_cut_and_its_members_go_there():
    """The inner ring steps out onto the outer circle for two nodes, taking some of the outer
    circle's points with it: cut off, the ring runs on along its own circle, and those points
    are the outer ring's again."""
    pts, rings, members = _two_circles()
    rings[0][[20, 21]] *= 1.15
    taken = np.arange(2000 + 305, 2000 + 345)  # outer points beside the detour
    members = [np.sort(np.concatenate([members[0], taken])), np.setdiff1d(members[1], taken)]
    out = cut_detours(_contours(rings, members), pts, RADIUS)
    assert len(out[0].points) == 126
    assert np.hypot(*out[0].points.T) == pytest.approx(1.0)
    assert np.array_equal(out[0].members, np.arange(2000))
    assert np.array_equal(out[1].members, np.arange(2000, 4000))


def test_a_ring_sharing_a_long_stretch_of_wall_keeps_it():
    """Where the inner ring runs on the outer wall for 13 nodes (seven radii), the two share a
    wall (`shared_walls`); no detour is cut."""
    pts, rings, members = _two_circles()
    rings[0][20:33] *= 1.14
    out = cut_detours(_contours(rings, members), pts, RADIUS)
    assert [len(c.points) for c in out] == [128, 128]


def test_the_ring_another_detours_onto_keeps_its_own_nodes():
    """The outer ring steps in onto the inner circle for four nodes: those are cut off. The
    inner ring's nodes there lie within reach of the detour's line but on their own line,
    which nothing leaves: they stay."""
    pts, rings, members = _two_circles()
    rings[1][20:24] *= 1.0 / 1.15
    out = cut_detours(_contours(rings, members), pts, RADIUS)
    assert [len(c.points) for c in out] == [128, 124]
    assert np.hypot(*out[1].points.T) == pytest.approx(1.15)


def test_a_spike_onto_the_other_ring_over_a_bare_root_stays():
    """A spike of the inner outline that reaches the outer circle, with no points across its
    root (the outline's points go up the spike and down, the root three radii wide is bare):
    a feature of the points, kept."""
    inner = _circle(1.0, 128)
    root = np.flatnonzero(np.hypot(*(inner - [-1.0, 0.0]).T) <= 0.15)  # about angle pi
    spike = np.array([[-1.16, 0.01], [-1.16, -0.01]])
    ring = np.vstack([inner[:root[0]], spike, inner[root[-1] + 1:]])
    s = np.linspace(0, 1, 50)[:, None]
    circle = _circle(1.0, 2000)
    bare = np.hypot(*(circle - [-1.0, 0.0]).T) <= 0.15
    up, down = inner[root[0] - 1], inner[root[-1] + 1]
    pts = np.vstack([circle[~bare], up + s * (spike[0] - up), spike[1] + s * (down - spike[1]),
                     _circle(1.15, 2000)])
    n = len(pts) - 2000
    contours = [OrderedContour(ring, True, np.arange(n)),
                OrderedContour(_circle(1.15, 128, 0.02), True, np.arange(n, len(pts)))]
    out = cut_detours(contours, pts, RADIUS)
    assert len(out[0].points) == len(ring)


def test_a_stretch_the_other_ring_skips_is_no_detour():
    """The inner ring skips a stretch of its circle in one straight chord, and the outer ring
    draws the inner circle's points there, stepping onto it for five nodes: those run near
    the inner ring's chord, but no node of the inner ring runs there; they stay."""
    pts, rings, members = _two_circles()
    rings[0] = np.delete(rings[0], np.arange(21, 34), axis=0)
    rings[1][24:29] *= 1.0 / 1.15
    out = cut_detours(_contours(rings, members), pts, RADIUS)
    assert [len(c.points) for c in out] == [115, 128]


def _polygon_nodes(corners, step):
    """Points every ``step`` along the closed polygon through ``corners``."""
    corners = np.asarray(corners, dtype=float)
    out = []
    for a, b in zip(corners, np.roll(corners, -1, axis=0)):
        k = max(int(round(np.linalg.norm(b - a) / step)), 1)
        out.append(a + np.arange(k)[:, None] / k * (b - a))
    return np.vstack(out)


def test_the_tip_of_a_wedge_touching_another_ring_stays():
    """A wedge whose point touches the edge of a block below it (a line drawing's fin
    meeting its body): its tip node lies on the block's wall and the line past it runs across
    the wedge, off that wall, but the wedge's walls turn away from that line: no detour."""
    wedge = [[0.0, 0.0], [0.5, 1.0], [-0.5, 1.0]]
    block = [[2.0, 0.0], [-2.0, 0.0], [-2.0, -4.0], [2.0, -4.0]]
    rings = [_polygon_nodes(wedge, 0.1), _polygon_nodes(block, 0.05)]
    pts = np.vstack([_polygon_nodes(wedge, 0.005), _polygon_nodes(block, 0.005)])
    n = len(_polygon_nodes(wedge, 0.005))
    members = [np.arange(n), np.arange(n, len(pts))]
    out = cut_detours(_contours(rings, members), pts, RADIUS)
    assert [len(c.points) for c in out] == [len(r) for r in rings]


def test_a_holes_corner_touching_its_outlines_step_is_no_detour():
    """The round blobs' scene 4 as the validity benchmark samples it (ε 0.05, noise ε / 8):
    a hole's corner touches a step of its outline. The outline's nodes on the step lie on
    the hole's wall, and the outline's line past them cuts the step off; but the outline
    runs away from the hole on either side, and keeps its step."""
    import shapely

    from benchmarks.holes import blob_scene
    from benchmarks.silhouettes import sample

    from .conftest import assert_rings_drawn

    eps, rings = 0.05, blob_scene(4)
    length = sum(shapely.LinearRing(r).length for r in rings)
    pts = sample(rings, int(3 * length / eps), eps / 8, 1004)
    assert_rings_drawn(rings, pts, wavepoly.fit(pts, eps), eps)


@pytest.mark.parametrize(("gap", "noise", "radius", "seed"),
                         [(1.5, 1 / 4, 3.0, 100), (1.5, 1 / 4, 3.0, 114), (1.5, 1 / 4, 8.0, 107),
                          (1.5, 3 / 16, 8.0, 100), (2.0, 1 / 4, 8.0, 104)])
def test_near_rings_have_no_teeth(gap, noise, radius, seed):
    """The validity benchmark's near rings 1.5-2 ε apart with noise up to ε / 4: where the
    inner circle's points thin out the inner ring stepped onto the outer circle for a few
    nodes and back, teeth reaching across to the outer ring (more than a tenth of its
    vertices on the outer circle; the first three). Each ring draws its own circle, and
    where both rings reach across (the last two: the outer ring's own nodes beside the inner
    one's tooth, or its chain zigzagging between its wall and the tooth) the ring that runs
    on along its wall keeps it."""
    eps = 0.1
    circle = _circle(1.0, 720)
    pts = sample_rings([radius * circle, (radius + gap * eps) * circle], spacing=eps / 3,
                       noise=noise * eps, seed=seed)
    result = wavepoly.fit(pts, eps)
    assert [c.closed for c in result.contours] == [True, True]
    assert len(result.outliers) == 0 and independent_problems(result) == []
    inner = sorted(float(np.mean(np.hypot(*c.vertices.T) < radius + 0.5 * gap * eps))
                   for c in result.contours)
    assert inner[0] <= 0.1 and inner[1] >= 0.9
