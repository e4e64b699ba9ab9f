"""The OTR2 peer harness: reading the C++ driver's output and picking the fewest vertices within
the tolerance (benchmarks/otr2.py). The driver itself runs only where ``make bench`` built it."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks import otr2

# A unit square traced by OTR2 at 4 vertices (closed) and a 3-vertex open L with an isolated
# vertex, in the driver's format.
DRIVER_OUTPUT = """\
T 5 4 1 2 0.250000
0 0
1 0
1 1
5 5
3
0 1
1 2
T 4 4 0 4 0.500000
0 0
1 0
1 1
0 1
0 1
1 2
2 3
3 0
"""
SQUARE = np.array([[0.5, -0.05], [1.02, 0.5], [0.5, 1.0], [-0.03, 0.5], [0.0, 0.0]])


def test_parse_output_reads_every_snapshot():
    first, second = otr2.parse_output(DRIVER_OUTPUT)
    assert (first.target, len(first.vertices), second.target) == (5, 4, 4)
    assert first.isolated.tolist() == [3] and first.segments.tolist() == [[0, 1], [1, 2]]
    assert second.seconds == 0.5
    assert first.fragments_and_open_ends() == (2, 2)  # the L and the isolated vertex
    assert second.fragments_and_open_ends() == (1, 0)  # one closed ring


def test_fewest_within_picks_the_smallest_output_inside_the_tolerance():
    snaps = otr2.parse_output(DRIVER_OUTPUT)
    best = otr2.fewest_within(snaps, SQUARE, eps=0.06)
    assert best.n_vertices == 4 and best.max_error == pytest.approx(0.05)
    assert (best.fragments, best.open_ends) == (1, 0)
    # The L misses the left side: when no output is within the tolerance, the closest one is
    # reported with its error, never passed off as within.
    closest = otr2.fewest_within(snaps[:1], SQUARE, eps=0.06)
    assert closest.max_error == pytest.approx(np.hypot(0.03, 0.5)) and closest.max_error > 0.06


def test_targets_decrease_and_reach_three_vertices():
    t = otr2.targets(5000)
    assert t == sorted(set(t), reverse=True) and t[-1] == 3 and t[0] == 2500
    assert otr2.targets(10) == [5, 4, 3]


@pytest.mark.skipif(not otr2.available(), reason="OTR2 driver not built (make bench builds it)")
def test_driver_reconstructs_a_noisy_circle_as_one_closed_ring():
    rng = np.random.default_rng(0)
    t = rng.uniform(0, 2 * np.pi, 400)
    pts = np.c_[np.cos(t), np.sin(t)] + rng.normal(0, 0.005, (400, 2))
    res = otr2.reconstruct(pts, eps=0.05)
    assert res.max_error <= 0.05 and (res.fragments, res.open_ends) == (1, 0)
    assert 8 <= res.n_vertices <= 30
