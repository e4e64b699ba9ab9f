"""The coarse-tolerance sweep of the validity benchmark: a tolerance of a few point spacings,
where a neighbourhood of the tolerance's radius may span both walls of a part thinner than it
(stars with thin spikes, and the shared silhouettes at a few hundredths of their size)."""

from __future__ import annotations

import numpy as np

import wavepoly
from wavepoly.samples import sample_rings

from .common import SHARED, table
from .silhouettes import shape_distance, star

#: A star is drawn by its shape when the drawn and the true outlines are within this many ε
#: of each other both ways (as the blob sweep's shapes: noise ε / 10 puts no point that far).
STAR_HAUSDORFF = 1.5

#: The coarse sweep: tolerances as shares of the shared silhouettes' diagonals...
COARSE_SHARES = (0.03, 0.05, 0.07, 0.1)
#: ... the shared point sets of one silhouette each (others are below the scatter there)...
COARSE_SETS = ("Circle0.txt", "Cup0.txt", "Keyboard0.txt", "apple_2percent_noise.txt",
               "butterfly_2percent_noise.txt", "crab_2percent_noise.txt",
               "dolphin_2percent_noise.txt", "drill.txt", "thing.txt", "vase.txt")
#: ... and the crust test sets (`hnn_crust`: clean sparse samples, a spacing a few hundredths
#: of their size, curves that come within a spacing or two of each other).
CRUST_SETS = ("crocodile-conf.p2d", "mushroom.p2d", "ventilator.p2d")
#: ... and stars (`benchmarks.silhouettes.star`): spikes, spike widths, seeds, and samplings
#: (spacing, noise) in ε = 0.3.
STAR_SPIKES = (5, 7)
STAR_WIDTHS = (0.2, 0.35)
STAR_SEEDS = 4
STAR_SAMPLINGS = ((1 / 6, 1 / 20), (1 / 4.5, 1 / 10))
STAR_TOLERANCE = 0.3


def coarse_sweep(truth) -> str:
    """Coarse tolerances on sparse samples: stars whose spikes are thinner than ε, and the
    shared silhouettes at a few hundredths of their size (``truth``: `tests.truth`, whose
    ``independent_problems`` is the shapely check)."""
    rows = []
    eps = STAR_TOLERANCE
    for spacing, noise in STAR_SAMPLINGS:
        right = shaped = invalid = total = 0
        for spikes in STAR_SPIKES:
            for width in STAR_WIDTHS:
                for seed in range(STAR_SEEDS):
                    outline = star(spikes, width)
                    pts = sample_rings([outline], spacing=spacing * eps,
                                       noise=noise * eps, seed=seed)
                    res = wavepoly.fit(pts, eps)
                    problems = truth.independent_problems(res)
                    invalid += bool(problems)
                    ok = (not problems and len(res.outliers) == 0
                          and [c.closed for c in res.contours] == [True])
                    right += ok
                    far = shape_distance([outline], res.contours, eps)
                    shaped += ok and far <= STAR_HAUSDORFF * eps
                    total += 1
        rows.append([f"stars, every ε / {1 / spacing:g}, noise ε / {1 / noise:g}",
                     f"{right}/{total} right ({shaped} by shape), {invalid} invalid"]
                    + [""] * 3)
    sets = [("noisy_sets", name) for name in COARSE_SETS] + [
        ("hnn_crust", name) for name in CRUST_SETS]
    for folder, name in sets:
        path = SHARED / "curves2d" / folder / name
        if not path.exists():
            continue
        pts = wavepoly.read_points(path)[:, :2]
        diag = float(np.hypot(*np.ptp(pts, axis=0)))
        cells = []
        for share in COARSE_SHARES:
            res = wavepoly.fit(pts, share * diag)
            n_closed = sum(c.closed for c in res.contours)
            bad = " invalid" if truth.independent_problems(res) else ""
            cells.append(f"{n_closed}/{len(res.contours) - n_closed}, "
                         f"{100 * len(res.outliers) / len(pts):.0f} %{bad}")
        rows.append([name] + cells)
    return ("### Coarse tolerances\n\nA tolerance of a few point spacings, where a "
            "neighbourhood of the tolerance's radius may span both walls of a part thinner "
            "than it. *Stars*: a unit disk with 5 or 7 wedge spikes reaching 1.5 beyond it, "
            "0.2 or 0.35 wide where they leave it (`benchmarks/silhouettes.py`), ε = "
            f"{eps:g}, {STAR_SEEDS} seeds each; "
            "*right*: one closed outline, valid, no outliers; *by shape*: and within "
            f"{STAR_HAUSDORFF:g} ε of the star both ways, measured along the lines (a spike "
            "drawn as a triangle whose sides cut across the empty space between spikes covers "
            "every point and is still not the star). The shared silhouettes "
            "(one outline each; Keyboard0 and vase have a second ring at finer tolerances) "
            "and the crust test sets (sparse clean samples of curves that come within a "
            "spacing or two of each other) at ε a share of their diagonal: closed/open "
            "contours and outliers.\n\n"
            + table(["case"] + [f"ε = {100 * s:g} % of the diagonal" for s in COARSE_SHARES],
                    rows))

