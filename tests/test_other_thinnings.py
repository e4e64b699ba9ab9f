"""Clean scans whose march left outlines open are read again with other seeds of the
thinning (`wavepoly.ordering.order_points`, `OTHER_THINNINGS`): where walls run within the
radius of each other, which centroids the thinning keeps decides whether the march steps
across to the other wall."""

import numpy as np
import pytest

import wavepoly
import wavepoly.ordering.rereading as rereading
from benchmarks.silhouettes import bitmap, sample, silhouette, thinned

from .conftest import assert_rings_drawn

#: Silhouette sweep samplings whose seed-0 reading left pieces of the outline open: (seed,
#: bitmap pixels or None, points or None for the traced ones, diagonal / ε, noise in ε,
#: thinned to a quarter across).
BROKEN = [(28, None, 3000, 300, 1 / 8, False), (13, 200, 2000, 100, 1 / 4, False),
          (0, 600, None, 300, 0.0, False), (16, None, 1000, 150, 0.0, True)]


def _case(seed, pixels, n, division, noise, thin):
    rings = silhouette(seed)
    eps = 1 / division
    if thin:
        return rings, thinned(rings, n, noise * eps, 0.25, seed), eps
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
