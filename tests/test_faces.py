"""Outlines read as regions (`wavepoly.ordering.faces`), where no walk of the cycle can draw
the stems: a branching slit, a slit's walls followed apart into a face of their own."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

import wavepoly
from wavepoly.ordering.faces import outline_of_faces
from wavepoly.ordering.stems import close_outlines
from wavepoly.types import OrderedContour

from .conftest import distance_to_output
from .truth import independent_problems

RADIUS = 0.05
FORK = np.array([0.5, 0.0])
#: The slit runs in from (1, 0) to the fork, then its two branches to these tips.
TIPS = np.array([[0.3, 0.15], [0.3, -0.15]])


def _walls(a: np.ndarray, b: np.ndarray, two: bool) -> np.ndarray:
    """Points along each wall of a slit from ``a`` to ``b`` (0.4 radii apart), or along its
    middle alone (one stroke), as many per length as on the ring."""
    length = np.linalg.norm(b - a)
    n = int(round(600 / (2 * np.pi) * length))
    d = (b - a) / length
    normal = np.array([-d[1], d[0]])
    line = a + np.linspace(0.0, 1.0, n)[:, None] * (b - a)
    if not two:
        return line
    return np.vstack([line + s * 0.2 * RADIUS * normal for s in (-1, 1)])


def _ring_with_forked_slit(two_walls: bool):
    """A unit ring in two pieces meeting at (1, 0) and (-1, 0), and a Y-shaped slit cut in
    from (1, 0) whose chains meet at the fork: its points hold two walls each or one."""
    t = np.linspace(0, 2 * np.pi, 600, endpoint=False)
    ring = np.column_stack([np.cos(t), np.sin(t)])
    ends = [np.array([1.0, 0.0]), *TIPS]
    starts = [FORK, FORK, FORK]
    walls = [_walls(a, b, two_walls) for a, b in zip(starts, ends)]
    pts = np.vstack([ring, *walls])
    first = np.cumsum([600] + [len(w) for w in walls])
    pieces = [OrderedContour(ring[:301:5], False, np.arange(300)),
              OrderedContour(np.vstack([ring[300::5], ring[:1]]), False, np.arange(300, 600))]
    for k, (a, b) in enumerate(zip(starts, ends)):
        chain = a + np.linspace(0.0, 1.0, 12)[:, None] * (b - a)
        pieces.append(OrderedContour(chain, False, np.arange(first[k], first[k + 1])))
    return pts, pieces


def test_a_forked_slit_is_cut_out_of_the_region_it_hangs_in():
    # the walk draws stems that end at a dead end; a stem that forks it left open
    pts, pieces = _ring_with_forked_slit(two_walls=True)
    out = close_outlines(pieces, pts, RADIUS)
    assert [c.closed for c in out] == [True]
    polygon = shapely.Polygon(out[0].points)
    assert polygon.is_valid
    assert np.array_equal(np.sort(out[0].members), np.arange(len(pts)))
    # the outline runs down the slit and up each branch to its tip
    for tip in TIPS:
        assert shapely.distance(polygon.exterior, shapely.Point(tip)) < RADIUS
    assert not polygon.contains(shapely.Point(0.75, 0.0))
    assert not polygon.contains(shapely.Point((FORK + TIPS[0]) / 2))
    ring = shapely.LinearRing(out[0].points)
    assert shapely.distance(shapely.points(pts), ring).max() < RADIUS


def test_a_forked_stroke_stays_a_stroke():
    # a line drawing's strokes meeting a ring hold one line's points: no outline
    pts, pieces = _ring_with_forked_slit(two_walls=False)
    out = close_outlines(pieces, pts, RADIUS)
    assert not any(c.closed for c in out)
    lines = [c.points for c in pieces]
    assert outline_of_faces(lines, pts, RADIUS) is None


def test_faces_joined_by_a_bar_or_no_face_give_no_outline():
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]], dtype=float)
    bar = np.array([[1.0, 0.5], [2.0, 0.5]])
    pts = np.vstack([square, square + [2, 0], bar])
    assert outline_of_faces([square, square + [2, 0], bar], pts, RADIUS) is None
    assert outline_of_faces([bar], bar, RADIUS) is None


@pytest.mark.parametrize(("row", "seed"), [(4, 21), (1, 6), (1, 110)])
def test_silhouettes_whose_slits_no_walk_could_draw_come_out_closed(row, seed):
    """Silhouette 21 traced from a 200-pixel bitmap, with noise: a slit's chain forked where
    its walls part by the mouth (5 open pieces before). Silhouette 6, sampled exactly: two
    wedge slits side by side, whose walls the march followed apart into a thin face of its
    own, which the largest face leaves out (3 open pieces before). Silhouette 110, exact:
    three wedge slits whose first passes cross the walk 11 times by their roots (2 open
    pieces before: the walk was left crossed, and the fit opened it)."""
    from benchmarks.bench_validity import SILHOUETTE_SAMPLINGS
    from benchmarks.silhouettes import bitmap, sample, silhouette

    pixels, n, eps, noise = SILHOUETTE_SAMPLINGS[row]
    rings = silhouette(seed) if pixels is None else bitmap(silhouette(seed), pixels)
    pts = sample(rings, n, noise * eps, 1000 + seed)
    result = wavepoly.fit(pts, eps)
    assert [c.closed for c in result.contours] == [True]
    assert independent_problems(result) == []
    assert len(result.outliers) == 0
    assert distance_to_output(pts, result).max() <= eps * (1 + 1e-9)


def test_slits_rooted_a_hair_apart_share_one_root():
    # two slits whose roots lie 1e-13 apart on the outline: the walk between them had no
    # length, and shapely refused a line of one point (a turbine blade's adaptive layer)
    from wavepoly.ordering.faces import _walk_and_paths

    square = shapely.Polygon([(0, 0), (1, 0), (1, 1), (0, 1)]).segmentize(RADIUS / 2)
    slits = [np.linspace([1.0, 0.5], [0.6, 0.45], 8),
             np.linspace([1.0, 0.5 + 1e-13], [0.6, 0.55], 8)]
    paths, walk = _walk_and_paths(square, slits, RADIUS)
    assert [len(p) for p in paths.values()] == [2]
    assert len(walk) == 1 and shapely.LineString(walk[0][1]).length == pytest.approx(4.0)
    ring = np.asarray(square.exterior.coords)
    pts = np.vstack([ring, *[_walls(s[0], s[-1], True) for s in slits]])
    outline = outline_of_faces([ring, *slits], pts, RADIUS)
    assert outline is not None and shapely.Polygon(outline).is_valid
    assert shapely.Polygon(outline).area < 1.0


def _legs_with_a_slit_between():
    """A unit ring in two pieces meeting at (1, 0) and (-1, 0), and a slit cut in from (1, 0):
    its walls followed apart (2.4 radii at the widest) down to (0.6, 0), where they merge into
    one chain that runs on to a tip 2.4 radii from the ring's far side: the slit between two
    legs, reaching down near the body's edge. The upper wall's chain ends on the lower one's,
    which runs on as the merged chain."""
    t = np.linspace(0, 2 * np.pi, 600, endpoint=False)
    ring = np.column_stack([np.cos(t), np.sin(t)])
    mouth, fork, tip = np.array([1.0, 0.0]), np.array([0.6, 0.0]), np.array([-0.05, -0.88])
    upper = [mouth, np.array([0.8, 0.06]), fork]
    lower = [mouth, np.array([0.8, -0.06]), fork]
    walls = [_walls(a, b, False) for a, b in zip(upper[:-1], upper[1:])]
    walls += [_walls(a, b, False) for a, b in zip(lower[:-1], lower[1:])]
    walls.append(_walls(fork, tip, True))
    pts = np.vstack([ring, *walls])
    first = np.cumsum([600] + [len(w) for w in walls])

    def chain(corners):
        return np.vstack([a + np.linspace(0.0, 1.0, 8)[:-1, None] * (b - a)
                          for a, b in zip(corners[:-1], corners[1:])] + [corners[-1][None]])

    pieces = [OrderedContour(ring[:301:5], False, np.arange(300)),
              OrderedContour(np.vstack([ring[300::5], ring[:1]]), False, np.arange(300, 600)),
              OrderedContour(chain(upper), False, np.arange(first[0], first[2])),
              OrderedContour(chain(lower + [tip]), False, np.arange(first[2], first[5]))]
    return pts, pieces, tip


def test_a_slit_whose_tip_nears_the_far_wall_is_cut_out_to_its_tip():
    # the tip's end met the ring at a T, closing a cycle through the slit's walls
    pts, pieces, tip = _legs_with_a_slit_between()
    out = close_outlines(pieces, pts, RADIUS)
    assert [c.closed for c in out] == [True]
    polygon = shapely.Polygon(out[0].points)
    assert polygon.is_valid
    assert np.array_equal(np.sort(out[0].members), np.arange(len(pts)))
    assert not polygon.contains(shapely.Point(0.8, 0.0))  # the slit's wide part
    assert not polygon.contains(shapely.Point(0.3, -0.4))  # its narrow part
    assert polygon.contains(shapely.Point(0.0, -0.96))  # the wall beyond its tip
    assert shapely.distance(polygon.exterior, shapely.Point(tip)) < RADIUS
    assert shapely.distance(shapely.points(pts), polygon.exterior).max() < RADIUS


def test_a_limb_that_ends_in_a_loop_joins_the_region_with_the_slit():
    # an ear's walls merged along its length and followed apart at its end: a cut edge of the
    # polygonized pieces (to the loop), which the region with a slit adds as a limb
    pts, pieces, tip = _legs_with_a_slit_between()
    root, end = np.array([-0.6, 0.8]), np.array([-0.75, 1.05])
    limb = _walls(root, end, True)
    t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    loop = end + [0.0, 0.06] + 0.06 * np.column_stack([np.sin(t), -np.cos(t)])  # from end
    pts = np.vstack([pts, limb, loop])
    n = len(pts) - len(limb) - len(loop)
    stem = root + np.linspace(0.0, 1.0, 6)[:, None] * (end - root)
    pieces.append(OrderedContour(np.vstack([stem, loop[1:], end[None]]), False,
                                 np.arange(n, len(pts))))
    out = close_outlines(pieces, pts, RADIUS)
    assert [c.closed for c in out] == [True]
    polygon = shapely.Polygon(out[0].points)
    assert polygon.is_valid
    assert not polygon.contains(shapely.Point(0.8, 0.0))
    assert shapely.distance(shapely.points(pts), polygon.exterior).max() < RADIUS
