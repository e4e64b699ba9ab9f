"""The scan's noise level, and neighbourhoods wide enough to see the curve through it.

On a noisy scan (bell-shaped scatter about the curves) the neighbourhoods reach `NOISE_REACH`
x the noise instead of the radius, up to `MAX_REACH` radii, so that the tangent follows the
curve, not the scatter across it. Where the curves bend within the windows the noise is
measured over (a crab's legs, shapes a few tolerances across), the noise that sizes them is
the spread about a parabola along each window, not about its line (`BEND_SHARE`).
"""

from __future__ import annotations

import numpy as np

from ..types import FloatArray
from .neighbourhoods import (
    ATOM_DIVISIONS,
    Atoms,
    Nodes,
    bend_free_spread,
    cell_atoms,
    cells,
    coarser_atoms,
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
#: shape (fish.txt: a scatter of 0.29 looked like walls at radius 0.18). A spread found so
#: must fit its window as a bell (`_bell_fits`; fish.txt: 0.16 of it): a page of text traced
#: at 1.4 pixels measured 0.31, the letters of a line packed side by side, each sharp.
WIDER_WINDOWS = 2
#: Where a wider window's spread does not fit it as a bell, the windows widen on, up to this
#: many times in all: a laser map's walls, seen from many poses, spread more the wider the
#: window (Freiburg at a radius of 0.006 filled windows of 3-12 radii, 0.35-0.29 of each, and
#: fitted one of 24-48 radii as a bell of 0.2-0.18), while the letters' spread stays a third
#: of the window, or is no bell once the window outgrows the lines of text.
WIDEST_WINDOWS = 4
#: The points' own scatter is measured over this many times the scatter found: a window that
#: holds the bell of Gaussian noise out to 3 sigma across the curve and bends little along
#: it (fish.txt measured 0.18, 0.33 and 0.54 over the windows of tolerances 0.12, 0.53 and
#: 0.88, each suggesting the next; the crab's legs made 0.042 of a scatter of 0.013)...
NOISE_SIGMAS = 3.0
#: ... when that is narrower than this share of the last window, up to this many times.
NARROWER = 0.8
NARROWER_WINDOWS = 2
#: A tolerance below this many times the scatter leaves about 5 % of noisy points outside it
#: (2 sigma): a polygon that kept them all would zigzag through the noise, so the curves then
#: run through the middle of the band (and the fit says so and suggests `NOISE_MARGIN` x).
NOISE_NOTE = 2.0
#: The suggested tolerance, in spreads over a neighbourhood: 3 sigma holds 99.7 % of
#: Gaussian scatter.
NOISE_MARGIN = 3.0
#: A spread over a neighbourhood at most this many times the points' own scatter is one bell of
#: noise about the curve (the made-up laser maps of `benchmarks.laser`: 1.16), not a halo about
#: a thin core nor a wall with a fainter one beside it, which the march follows as curves of
#: their own (the Intel map: 1.67 at a tolerance of 0.075, Freiburg: 1.73 at 0.1). Below
#: `BELL_MARGIN` x such a bell, more than 0.6 % of the points lie beyond the tolerance from
#: the middle, and reaching them zigzagged the walls (24-27 teeth per made-up map at 0.05).
BELL_SPREAD = 1.3
#: ... below the suggested `NOISE_MARGIN`, so that the suggestion, its spread measured again
#: over its own wider neighbourhoods (a ring's spread grows by 1-5 %), draws no new one.
BELL_MARGIN = 2.75
#: A spread over a neighbourhood at most this many times the points' own scatter is a halo
#: about a thin core (the Intel map's walls, seen from many poses: 1.5), not the curve's own
#: shape, which makes it wider (the crab's legs: 3.2).
HALO_SPREAD = 2.5
#: Where the spread about a parabola along the window (`bend_free_spread`) is below this share
#: of the spread about its line, the curves' own bends make up the rest, and the parabola's
#: spread sizes the neighbourhoods: the crab's legs 0.75, random shapes 4-8 tolerances across
#: 0.59-0.79 (a spread of 0.65 tolerances where the noise was 0.25), fish.txt's wide band
#: 0.82. On straight walls the parabola takes out nothing but its own sampling error (laser
#: maps: 0.96-1.0), and the line's spread stays, so that those neighbourhoods keep their size.
BEND_SHARE = 0.9
#: Seeds at which the noise is measured: fewer (600) made the estimate wobble enough to raise
#: false merge notes on noisy glyphs.
NOISE_SEEDS = 2000
#: Regression passes: later passes see a neighbourhood centred on the curve.
REGRESSION_PASSES = 3


def noise_adaptive_nodes(pts: FloatArray, radius: float, sparse: bool = False,
                         min_window: float = 0.0) -> tuple[Nodes, Atoms, float]:
    """Centroid and principal axes of the neighbourhood of each occupied cell of radius / 2,
    the atoms they were summed over, and the points' own scatter (`noise_level`).

    The neighbourhoods have the fixed ``radius``, or on a noisy scan `NOISE_REACH` x the noise
    level (up to `MAX_REACH` x radius), so that they stay longer along the curve than across it;
    the noise level less the curves' bends where those make up much of it (`BEND_SHARE`).
    A ``sparse`` sample (its radius set by the point spacing, not the tolerance) has no
    measurable noise: a window of a few points measures the curve's turns. ``min_window``:
    the narrowest window the scatter is measured over.
    """
    atoms = cell_atoms(pts, radius)
    xy = _cell_centroids(atoms)
    noise, scatter, bend_free = ((0.0, 0.0, 0.0) if sparse else
                                 noise_level(xy, atoms, radius, NOISE_SEEDS, min_window))
    sizing = bend_free if bend_free < BEND_SHARE * noise else noise
    reach = min(max(radius, NOISE_REACH * sizing), MAX_REACH * radius)
    if reach > radius:  # coarser atoms keep the wider neighbourhoods' sums cheap
        atoms = cell_atoms(pts, reach, min_per_cell=1.0)
    for _ in range(REGRESSION_PASSES):
        xy, tangent, ratio, spread = regression_step(xy, atoms, reach)
    return Nodes(xy, tangent, ratio, spread, reach, noise), atoms, scatter


def runs_through_the_middle(points: FloatArray, tolerance: float, noise: float,
                            scatter: float) -> bool:
    """Whether, at this tolerance, the curves run through the middle of the noise: the
    tolerance is below `NOISE_NOTE` x the points' own scatter, or below `BELL_MARGIN` x the
    spread of a bell of noise (`below_the_bell`); or below `NOISE_NOTE` x the spread over a
    neighbourhood, where that spread is a halo (`HALO_SPREAD`) and the tolerance it suggests
    holds it measured at its own radius."""
    if tolerance < NOISE_NOTE * scatter or below_the_bell(tolerance, noise, scatter):
        return True
    suggested = NOISE_MARGIN * noise
    return bool(tolerance < NOISE_NOTE * noise and noise <= HALO_SPREAD * scatter
                and suggested >= NOISE_NOTE * neighbourhood_spread(points, suggested))


def below_the_bell(tolerance: float, noise: float, scatter: float) -> bool:
    """Whether the points spread about their curves as one bell of noise (the spread over a
    neighbourhood, ``noise``, within `BELL_SPREAD` x their own ``scatter``) and the tolerance
    is below `BELL_MARGIN` x that spread."""
    return 0 < noise <= BELL_SPREAD * scatter and tolerance < BELL_MARGIN * noise


def neighbourhood_spread(pts: FloatArray, radius: float) -> float:
    """The spread of the points about their curves over neighbourhoods of ``radius`` (the
    first figure of `noise_level`), as the ordering would measure it at that radius."""
    return noise_at(pts, radius)[0]


def noise_at(pts: FloatArray, radius: float, min_window: float = 0.0) -> tuple[float, float]:
    """`noise_level` as `noise_adaptive_nodes` measures it at ``radius``, without the nodes."""
    atoms = cell_atoms(pts, radius)
    return noise_level(_cell_centroids(atoms), atoms, radius, NOISE_SEEDS, min_window)[:2]


def _cell_centroids(atoms: Atoms) -> FloatArray:
    """Centroid of the atoms in each occupied cell of radius / 2: the neighbourhoods' seeds."""
    inverse, counts = cells(atoms.cell // (ATOM_DIVISIONS // 2), atoms.weight)
    return np.column_stack([np.bincount(inverse, atoms.weight * atoms.xy[:, k])
                            for k in range(2)]) / counts[:, None]


def noise_level(seeds: FloatArray, atoms: Atoms, radius: float, sample: int = NOISE_SEEDS,
                min_window: float = 0.0) -> tuple[float, float, float]:
    """Typical spread of the points about their curve over a neighbourhood, and their own
    scatter about it: the median perpendicular spread about the regression lines at a sample
    of the seeds, over `NOISE_WINDOW` radii, then over a window of a few scatters.

    Only bell-shaped scatter is noise: where the perpendicular offsets have a kurtosis below
    `NOISE_KURTOSIS` (two walls side by side, each sharp, or a flat band) the spread is a shape
    of the data, counted as no noise, so that neighbourhoods stay narrow enough to see it;
    unless the band fills the window (`FILLED_BAND`) at most seeds, when the scatter is
    measured again over wider windows (`WIDER_WINDOWS`), and what they find counts only
    where it fits its window as a bell (`_bell_fits`: letters packed side by side spread a
    third of a window widened past them); a bell too wide for its window is measured again
    over wider ones still (`WIDEST_WINDOWS`). Where the window holds two walls
    side by side (`wavepoly.ordering.walls.two_walls_spread`), the noise is each wall's own
    scatter, not their spread about a line between them (a heavy tail, as noise has).

    The first figure sizes the neighbourhoods. A window much wider than the scatter also
    measures the curve's own bend (a crab's legs) and clutter beside it, so that figure grows
    with the radius. The second is measured at the same seeds over `NOISE_SIGMAS` x the
    scatter found (down to ``min_window``, a few point spacings): the points' own scatter,
    about the same whatever the tolerance, against which a tolerance is judged. The third is
    the first about a parabola along each window instead of its line (`bend_free_spread`).
    """
    pick = np.random.default_rng(0).choice(len(seeds), min(sample, len(seeds)), replace=False)
    window = NOISE_WINDOW * radius
    for widened in range(WIDEST_WINDOWS + 1):
        # past the usual widenings, coarser atoms keep a window of dozens of radii cheap
        wide_atoms = coarser_atoms(atoms, 2 ** max(widened - WIDER_WINDOWS, 0))
        spread, noisy, filled, bend_free = _scatter_over(seeds[pick], wide_atoms, window, radius)
        noise = float(np.median(np.where(noisy, spread, 0.0)))
        if widened and not _bell_fits(noise, window):
            # clean shapes packed side by side (letters), or a bell wider than this window
            noise, noisy = 0.0, np.zeros_like(noisy)
        elif noise > 0 or not filled or widened >= WIDER_WINDOWS:
            break
        window *= 2
    bend_free = float(np.median(np.where(noisy, bend_free, 0.0)))
    scatter = noise
    for _ in range(NARROWER_WINDOWS):  # the seeds found noisy, over narrower windows
        narrower = max(NOISE_SIGMAS * scatter, min_window)
        if scatter == 0 or narrower > NARROWER * window:
            break
        window = narrower
        spread = _scatter_over(seeds[pick], atoms, window, radius)[0]
        scatter = float(np.median(np.where(noisy, spread, 0.0)))
    return noise, scatter, bend_free


def _bell_fits(noise: float, window: float) -> bool:
    """Whether a bell of noise of this spread fits within the window out to `NOISE_SIGMAS`
    either side, so that it can be measured again over a narrower one (`NARROWER`)."""
    return NOISE_SIGMAS * noise <= NARROWER * window


def _scatter_over(seeds: FloatArray, atoms: Atoms, window: float, radius: float
                  ) -> tuple[FloatArray, np.ndarray, bool, FloatArray]:
    """`noise_level` over one window: each seed's spread (each wall's own where there are
    two), which seeds' scatter is noise (bell-shaped, or two walls), whether most other
    seeds' bands fill the window, and each seed's spread about a parabola along it (each
    wall's own where there are two)."""
    xy = seeds
    for _ in range(2):
        xy, tangent, _, spread = regression_step(xy, atoms, window)
    offsets = perpendicular_offsets(xy, tangent, atoms, window)
    kurtosis = perpendicular_kurtosis(xy, tangent, atoms, window, offsets)
    # two walls in one window (rings 3 tolerances apart): the noise is each wall's own
    # scatter, not the spread of both about a line between them
    two, own = two_walls_spread(xy, tangent, atoms, window, radius, offsets)
    shape = kurtosis < NOISE_KURTOSIS
    # a band that fills the window from side to side may be noise wider than the window
    filled = shape & (spread > FILLED_BAND * window)
    bend_free = bend_free_spread(xy, tangent, atoms, window, offsets)
    return (np.where(two, own, spread), ~shape | two, bool(filled.sum() > 0.5 * shape.sum()),
            np.where(two, own, bend_free))
