"""A clean reading that left a ladder of open pieces between two walls about a radius apart
is read again a fifth tighter (`wavepoly.ordering.rereading.tighter_reading`); a line
drawing's strokes, which meet at junctions and run beside nothing, are not."""

import numpy as np
import pytest

import wavepoly
from wavepoly.ordering.rereading import _run_beside
from wavepoly.samples import sample_rings
from wavepoly.types import OrderedContour, Ordering

from .conftest import distance_to_output
from .truth import diagonal, independent_problems, svg_shape

#: A clean curve's scatter in these made-up scans, in radii (a line drawing's eighth of a
#: tolerance).
SCATTER = 0.125


def _scan(*lines: np.ndarray, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    pts = np.vstack(lines)
    return pts + rng.normal(scale=SCATTER, size=pts.shape)


def _line(a, b, step=0.1) -> np.ndarray:
    a, b = np.asarray(a, float), np.asarray(b, float)
    n = int(np.linalg.norm(b - a) / step) + 1
    return a + np.linspace(0.0, 1.0, n)[:, None] * (b - a)


def _open_pieces(*pieces: np.ndarray) -> Ordering:
    return Ordering([OrderedContour(p, False, np.arange(0)) for p in pieces], np.arange(0),
                    1.0, clean=True)


def test_a_ladders_pieces_run_beside_the_other_wall():
    """Two walls a radius apart, the march's pieces stepping from one to the other."""
    pts = _scan(_line((0, 0), (30, 0)), _line((0, 1), (30, 1)))
    ladder = _open_pieces(np.vstack([_line((0, 0), (8, 0)), _line((8, 1), (15, 1))]),
                          np.vstack([_line((15, 0), (22, 0)), _line((22, 1), (30, 1))]))
    assert _run_beside(ladder, pts)


def test_strokes_meeting_at_junctions_run_beside_nothing():
    """A T and an X of strokes, each piece a stroke: only where another meets it does a
    piece have points a radius away."""
    bar, stem = _line((0, 0), (20, 0)), _line((10, 0.1), (10, 12))
    cross = _line((30, -8), (30, 8))
    across = _line((22, 0.5), (38, 0.5))
    pts = _scan(bar, stem, cross, across)
    assert not _run_beside(_open_pieces(bar, stem, cross, across), pts)


def test_a_line_drawing_sampled_densely_keeps_its_strokes_open(shared_data):
    """Fishi, sampled every tenth of a tolerance with noise an eighth: its first reading
    draws the strokes as they are, 2 closed and 4 open. A fifth tighter, they closed into
    4 rings through their junctions; that reading is no longer tried, since the open
    strokes run beside no other wall (`_run_beside`)."""
    path = shared_data / "curves2d" / "ground_truth_svg" / "Fishi.svg"
    if not path.exists():
        pytest.skip(f"{path} is not here")
    shape = svg_shape(path)
    eps = diagonal(shape) / 150
    rng = np.random.default_rng(0)
    parts = []
    for ring, closed in zip(shape.rings, shape.closed):
        verts = np.vstack([ring, ring[:1]]) if closed else ring
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(verts, axis=0), axis=1))])
        s = rng.uniform(0.0, arc[-1], int(10 * arc[-1] / eps))
        parts.append(np.column_stack([np.interp(s, arc, verts[:, 0]),
                                      np.interp(s, arc, verts[:, 1])]))
    pts = np.concatenate(parts)
    pts = pts + rng.normal(scale=eps / 8, size=pts.shape)
    result = wavepoly.fit(pts, eps)
    closed = [c.closed for c in result.contours]
    assert (closed.count(True), closed.count(False)) == (2, 4)
    assert not any("walls about a radius apart" in n for n in result.notes)


@pytest.mark.parametrize(("radius", "gap", "seed"), [(5.0, 1.0, 4), (10.0, 1.05, 9)])
def test_a_ladders_lenses_and_middle_pieces_do_not_stop_the_tighter_reading(radius, gap, seed):
    """Two circles about a tolerance apart, sampled every sixth of one with noise a
    twentieth. At (5, 1, 4) the first reading left 15 pieces open and closed 3 lenses,
    which the tighter reading rightly drops: they are walls, not outlines it must keep. At
    (10, 1.05, 9) most pieces run down the middle between the walls, with neither wall
    farther than half a radius from them: the walls are told by the points' spread across
    a piece, not by their distance from it."""
    t = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    circle = np.column_stack([np.cos(t), np.sin(t)])
    rings = [radius * circle, (radius - gap * 0.1) * circle]
    pts = sample_rings(rings, spacing=0.1 / 6, noise=0.1 / 20, seed=seed)
    result = wavepoly.fit(pts, 0.1)
    assert [c.closed for c in result.contours] == [True, True]
    assert sorted(result.parents) in ([-1, 0], [-1, 1])
    assert not independent_problems(result)
    assert distance_to_output(pts, result).max() <= 0.1 * (1 + 1e-9)
