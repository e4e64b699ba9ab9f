"""The scan's noise level, and neighbourhoods wide enough to see the curve through it.

On a noisy scan (bell-shaped scatter about the curves) the neighbourhoods reach `NOISE_REACH`
x the noise instead of the radius, up to `MAX_REACH` radii, so that the tangent follows the
curve, not the scatter across it.
"""

from __future__ import annotations

import numpy as np

from ..types import FloatArray
from .neighbourhoods import (
    ATOM_DIVISIONS,
    Atoms,
    Nodes,
    cell_atoms,
    cells,
    perpendicular_kurtosis,
    perpendicular_offsets,
    regression_step,
)
from .walls import two_walls_spread

#: On noisy scans the neighbourhoods reach this many times the noise level (at most
#: `MAX_REACH` radii): wide enough that the regression line follows the curve, not the scatter.
NOISE_REACH = 5.0
#: Widest neighbourhood, in radii: wider ones would round off features of a few radii.
MAX_REACH = 4.0
#: Kurtosis of the perpendicular scatter above which it counts as noise (a Gaussian has 3; two
#: sharp walls side by side have 1, a flat band 1.8).
NOISE_KURTOSIS = 2.2
#: The noise is measured over this many radii: wide enough that a scatter of up to radius / 2
#: is not cut off.
NOISE_WINDOW = 3.0
#: A seed's offsets fill its window when their RMS exceeds this fraction of it (a flat band
#: as wide as the window has 0.58): the scatter may then be wider than the window...
FILLED_BAND = 0.25
#: ... and where most seeds not counted as noise fill their windows, the noise is measured
#: again over windows twice as wide, up to this many times, where the scatter shows its bell
#: shape (fish.txt: a scatter of 0.29 looked like walls at radius 0.18).
WIDER_WINDOWS = 2
#: Seeds at which the noise is measured: fewer (600) made the estimate wobble enough to raise
#: false merge notes on noisy glyphs.
NOISE_SEEDS = 2000
#: Regression passes: later passes see a neighbourhood centred on the curve.
REGRESSION_PASSES = 3


def noise_adaptive_nodes(pts: FloatArray, radius: float, sparse: bool = False
                         ) -> tuple[Nodes, Atoms]:
    """Centroid and principal axes of the neighbourhood of each occupied cell of radius / 2,
    and the atoms they were summed over.

    The neighbourhoods have the fixed ``radius``, or on a noisy scan `NOISE_REACH` x the noise
    level (up to `MAX_REACH` x radius), so that they stay longer along the curve than across it.
    A ``sparse`` sample (its radius set by the point spacing, not the tolerance) has no
    measurable noise: a window of a few points measures the curve's turns.
    """
    atoms = cell_atoms(pts, radius)
    inverse, counts = cells(atoms.cell // (ATOM_DIVISIONS // 2), atoms.weight)  # radius / 2
    xy = np.column_stack([np.bincount(inverse, atoms.weight * atoms.xy[:, k])
                          for k in range(2)]) / counts[:, None]
    noise = 0.0 if sparse else noise_level(xy, atoms, radius)
    reach = min(max(radius, NOISE_REACH * noise), MAX_REACH * radius)
    if reach > radius:  # coarser atoms keep the wider neighbourhoods' sums cheap
        atoms = cell_atoms(pts, reach, min_per_cell=1.0)
    for _ in range(REGRESSION_PASSES):
        xy, tangent, ratio, spread = regression_step(xy, atoms, reach)
    return Nodes(xy, tangent, ratio, spread, reach, noise), atoms


def noise_level(seeds: FloatArray, atoms: Atoms, radius: float, sample: int = NOISE_SEEDS) -> float:
    """Typical scatter of the points about their curve: the median perpendicular spread about
    the regression lines at a sample of the seeds, over `NOISE_WINDOW` radii.

    Only bell-shaped scatter is noise: where the perpendicular offsets have a kurtosis below
    `NOISE_KURTOSIS` (two walls side by side, each sharp, or a flat band) the spread is a shape
    of the data, counted as no noise, so that neighbourhoods stay narrow enough to see it;
    unless the band fills the window (`FILLED_BAND`) at most seeds, when the scatter is
    measured again over wider windows (`WIDER_WINDOWS`). Where the window holds two walls
    side by side (`wavepoly.ordering.walls.two_walls_spread`), the noise is each wall's own
    scatter, not their spread about a line between them (a heavy tail, as noise has).
    """
    pick = np.random.default_rng(0).choice(len(seeds), min(sample, len(seeds)), replace=False)
    window = NOISE_WINDOW * radius
    for _ in range(WIDER_WINDOWS + 1):
        xy = seeds[pick]
        for _ in range(2):
            xy, tangent, _, spread = regression_step(xy, atoms, window)
        offsets = perpendicular_offsets(xy, tangent, atoms, window)
        kurtosis = perpendicular_kurtosis(xy, tangent, atoms, window, offsets)
        # two walls in one window (rings 3 tolerances apart): the noise is each wall's own
        # scatter, not the spread of both about a line between them
        two, own = two_walls_spread(xy, tangent, atoms, window, radius, offsets)
        spread = np.where(two, own, spread)
        noise = float(np.median(np.where((kurtosis >= NOISE_KURTOSIS) | two, spread, 0.0)))
        # a band that fills the window from side to side may be noise wider than the window
        shape = kurtosis < NOISE_KURTOSIS
        filled = shape & (spread > FILLED_BAND * window)
        if noise > 0 or filled.sum() <= 0.5 * shape.sum():
            return noise
        window *= 2
    return noise
