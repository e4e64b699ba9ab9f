"""Coarse tolerances on sparse samples: where the tolerance's neighbourhoods span parts
thinner than it, the ordering reads the scan again at a finer radius
(`wavepoly.ordering.order_points`)."""

import numpy as np
import pytest

import wavepoly
from benchmarks.silhouettes import star
from wavepoly.ordering import order_points
from wavepoly.samples import sample_rings

from .conftest import distance_to_output
from .truth import independent_problems

EPS = 0.3


def _star_points(spikes: int, spike_width: float, seed: int) -> np.ndarray:
    """The star sampled every ε / 6 with noise ε / 20: the spikes are thinner than ε."""
    return sample_rings([star(spikes, spike_width)], spacing=EPS / 6, noise=EPS / 20,
                        seed=seed)


@pytest.mark.parametrize("spikes", [5, 7])
@pytest.mark.parametrize("spike_width", [0.2, 0.35])
@pytest.mark.parametrize("seed", range(4))
def test_a_star_with_spikes_thinner_than_the_tolerance_is_one_outline(spikes, spike_width,
                                                                       seed):
    """At the tolerance's radius the spikes' walls fell into one neighbourhood, measured as
    noise, and the outline came out open or in pieces (9 of these 16 before)."""
    pts = _star_points(spikes, spike_width, seed)
    result = wavepoly.fit(pts, EPS)
    assert [c.closed for c in result.contours] == [True]
    assert len(result.outliers) == 0
    assert result.validity.valid and independent_problems(result) == []
    assert distance_to_output(pts, result).max() <= EPS * (1 + 1e-9)


def test_the_finer_reading_is_noted_and_its_radius_reported():
    ordering = order_points(_star_points(5, 0.2, 0), EPS, tolerance=EPS)
    assert ordering.radius < EPS
    assert any("read at a radius of" in note for note in ordering.notes)


@pytest.mark.parametrize("per_tolerance", [4, 6, 10])
def test_a_smooth_curve_reads_at_the_tolerance(per_tolerance):
    # its scatter is the same in smaller neighbourhoods: no finer reading
    t = np.linspace(0, 2 * np.pi, 600, endpoint=False)
    pts = sample_rings([3 * np.column_stack([np.cos(t), np.sin(t)])],
                       spacing=EPS / per_tolerance, noise=EPS / 8, seed=0)
    ordering = order_points(pts, EPS, tolerance=EPS)
    assert ordering.radius == EPS and ordering.notes == ()


def test_a_noisy_band_is_not_read_finer():
    # a band whose scatter is a third of the tolerance measures less noise in smaller
    # neighbourhoods too, but is no cleaner there: the finer reading is not kept
    rng = np.random.default_rng(3)
    t = rng.uniform(0, 2 * np.pi, 3000)
    pts = 3 * np.column_stack([np.cos(t), np.sin(t)]) + rng.normal(scale=EPS / 3,
                                                                    size=(3000, 2))
    ordering = order_points(pts, EPS, tolerance=EPS)
    assert not any("read at a radius of" in note for note in ordering.notes)


@pytest.mark.parametrize("name, share", [("dolphin_2percent_noise.txt", 0.07),
                                         ("drill.txt", 0.05)])
def test_shared_silhouettes_at_a_coarse_tolerance_are_one_outline(shared_data, name, share):
    """At 5-7 % of their size the dolphin's fins and the drill's neck are thinner than the
    tolerance: the dolphin came out as two open pieces with 37 % of its points outliers, the
    drill as two rings split at the neck."""
    pts = wavepoly.read_points(shared_data / "curves2d" / "noisy_sets" / name)[:, :2]
    eps = share * float(np.hypot(*np.ptp(pts, axis=0)))
    result = wavepoly.fit(pts, eps)
    assert [c.closed for c in result.contours] == [True]
    assert len(result.outliers) == 0
    assert result.validity.valid and independent_problems(result) == []
    assert distance_to_output(pts, result).max() <= eps * (1 + 1e-9)


def test_outlines_side_by_side_are_counted_and_holes_are_not():
    """The count that keeps a finer reading from splitting a clean one's outline
    (`rereading._outer_rings`): rings inside no other ring; a hole and an open piece are no
    outline of their own."""
    from wavepoly.ordering.rereading import _outer_rings
    from wavepoly.types import OrderedContour, Ordering

    def square(x, half):
        return np.array([[x - half, -half], [x + half, -half], [x + half, half],
                         [x - half, half]], dtype=float)

    one = np.arange(1)
    pieces = [OrderedContour(square(0.0, 1.0), True, one),
              OrderedContour(square(0.0, 0.3), True, one),
              OrderedContour(square(5.0, 1.0), True, one),
              OrderedContour(square(9.0, 1.0)[:3], False, one)]
    ordering = Ordering(pieces, np.empty(0, dtype=np.intp), 0.1)
    assert _outer_rings(ordering) == 2
