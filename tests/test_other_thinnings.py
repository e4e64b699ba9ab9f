"""Clean scans whose march left outlines open are read again with other seeds of the
thinning (`wavepoly.ordering.order_points`, `OTHER_THINNINGS`): where walls run within the
radius of each other, which centroids the thinning keeps decides whether the march steps
across to the other wall."""

import numpy as np
import pytest

import wavepoly
import wavepoly.ordering.rereading as rereading
from benchmarks.silhouettes import bitmap, sample, silhouette
from wavepoly.ordering.rereading import _free_end
from wavepoly.types import OrderedContour, Ordering

from .conftest import assert_rings_drawn

#: Silhouette sweep samplings whose seed-0 reading left pieces of the outline open: (seed,
#: bitmap pixels or None, points or None for the traced ones, diagonal / ε, noise in ε).
#: The thinned silhouettes' first readings now close across the gaps a sparse sampling
#: leaves (`wavepoly.ordering.gaps.chance_gaps`; seed 16 at 1000 points was one).
BROKEN = [(28, None, 3000, 300, 1 / 8), (35, None, 1000, 150, 1 / 4), (0, 600, None, 300, 0.0),
          (45, 300, None, 150, 0.0)]


def _case(seed, pixels, n, division, noise):
    rings = silhouette(seed)
    eps = 1 / division
    if pixels is not None:
        rings = bitmap(rings, pixels)
    pts = np.vstack(rings) if n is None else sample(rings, n, noise * eps, 1000 + seed)
    return rings, pts, eps


@pytest.mark.parametrize("case", BROKEN)
def test_an_outline_the_first_thinning_broke_comes_out_closed(case):
    rings, pts, eps = _case(*case)
    result = wavepoly.fit(pts, eps)
    assert_rings_drawn(rings, pts, result, eps)
    assert any("thinning seed" in n for n in result.notes)


def test_without_other_thinnings_those_outlines_break(monkeypatch):
    """The cases above are no luck of the default seed: read once, each leaves pieces open."""
    monkeypatch.setattr(rereading, "OTHER_THINNINGS", 0)
    for case in BROKEN:
        _, pts, eps = _case(*case)
        result = wavepoly.fit(pts, eps)
        assert not all(c.closed for c in result.contours), case


def test_an_open_curve_is_read_once_and_stays_open():
    """A truly open stroke is open in every reading: no other thinning is taken."""
    t = np.linspace(0, 3 * np.pi, 900)
    pts = np.column_stack([t, np.sin(t)])
    result = wavepoly.fit(pts, 0.05)
    assert [c.closed for c in result.contours] == [False]
    assert not any("thinning seed" in n for n in result.notes)


def _pieces(*lines, closed=()) -> Ordering:
    return Ordering([OrderedContour(np.asarray(line, float), k in closed, np.arange(0))
                     for k, line in enumerate(lines)], np.arange(0), 1.0, clean=True)


def test_a_free_end_marks_a_broken_outline_and_junctions_a_network():
    """`_free_end`: strokes that end on other lines (a bar across a ring, its ends at T
    junctions) are a network; an end standing `FREE_END` radii from every line is a break,
    or a stroke's own tip (read again, a lone stroke stays open: the test above)."""
    t = np.linspace(0, 2 * np.pi, 120, endpoint=False)
    ring = 10 * np.column_stack([np.cos(t), np.sin(t)])
    bar = np.column_stack([np.linspace(-10, 10, 41), np.zeros(41)])
    assert not _free_end(_pieces(ring, bar, closed=(0,)))
    assert not _free_end(_pieces(ring, bar * [0.97, 1], closed=(0,)))
    assert _free_end(_pieces(ring, bar * [0.5, 1], closed=(0,)))
    # a U whose arms end 6 radii apart: its own line is near each end only along the arc
    u = np.vstack([np.column_stack([np.zeros(21), np.linspace(10, 0, 21)]),
                   np.column_stack([np.linspace(0.5, 6, 12), np.zeros(12)]),
                   np.column_stack([np.full(20, 6.0), np.linspace(0.5, 10, 20)])])
    assert _free_end(_pieces(u))
    assert not _free_end(_pieces(u, [[0, 10], [3, 12], [6, 10]]))


def test_a_line_drawings_strokes_stay_strokes(shared_data):
    """Deery's strokes meet at T junctions: no end stands free, so other thinnings (one of
    which closed them into two rings walking the strokes out and back) are not tried."""
    from benchmarks.bench_validity import DIAGONAL_PER_TOLERANCE, _sample_shape

    from .truth import diagonal, svg_shape

    path = shared_data / "curves2d" / "ground_truth_svg" / "Deery.svg"
    if not path.exists():
        pytest.skip(f"{path} is not here")
    shape = svg_shape(path)
    eps = diagonal(shape) / DIAGONAL_PER_TOLERANCE
    result = wavepoly.fit(_sample_shape(shape, eps, 0), eps)
    assert sum(not c.closed for c in result.contours) == 6
    assert not any("thinning seed" in n for n in result.notes)
