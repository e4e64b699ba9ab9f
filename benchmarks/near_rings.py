"""Two circles a couple of tolerances apart, one inside the other, sampled sparsely with noise
up to the issue's clean bound (ε / 4): the validity benchmark's sweep of near-touching rings
(`wavepoly.ordering.walls`, `wavepoly.ordering.waists`). Where one circle's points thin out,
the march may step across to the other and back, and draw the two as one ring.
"""

from __future__ import annotations

import time

import numpy as np

import wavepoly
from wavepoly.samples import sample_rings

from .common import table

#: The sweep: gaps between the circles (in ε), the noise (in ε), the inner circle's radii (in
#: units of 10 ε) and seeds of each; sampled every ε / 3 at random.
RING_GAPS = (1.5, 2.0, 2.5, 3.0)
RING_NOISE = (0.125, 0.1875, 0.25)
#: ... and a thin tube's two walls, closer than the tolerance (`wavepoly.ordering.annuli`):
#: exact, and with noise small against the gap (at 0.8 ε, ε / 16 puts them 13 noise levels
#: apart; at a quarter of that the two bands are one to the eye too).
TUBE_ROWS = ((0.5, 0.0), (0.8, 0.0), (0.8, 0.0625), (1.0, 0.0))
#: ... and walls about a tolerance apart sampled densely, every ε / 6 with noise ε / 20, as a
#: thin shell's sliced wall is (every neighbourhood has the other wall on its rim).
DENSE_ROWS = ((0.95, 0.05), (1.0, 0.05), (1.05, 0.05))
DENSE_SPACING = 1 / 6
RING_RADII = (3.0, 8.0)
RING_SEEDS = 8
#: The tolerance the circles are fitted at.
RING_EPS = 0.1
#: A contour draws one circle where at most this share of its vertices lie nearer the other:
#: a polygon's chords cut inside a circle by up to ε, but its vertices lie on it; a contour
#: folded onto both (walked out along one circle and back along the other) has half on each.
OTHER_CIRCLE_SHARE = 0.1


def near_rings_sweep(truth) -> str:
    """For each gap and noise, fits of the two circles (`RING_RADII` x `RING_SEEDS`
    samplings): *right* (two closed rings, valid, no outliers), *merged* (one ring), *open*
    (results with an open piece) and *invalid* (``truth.independent_problems``)."""
    rows = []
    t = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    circle = np.column_stack([np.cos(t), np.sin(t)])
    rows_asked = ([(g, n, 1 / 3) for g in RING_GAPS for n in RING_NOISE]
                  + [(g, n, 1 / 3) for g, n in TUBE_ROWS]
                  + [(g, n, DENSE_SPACING) for g, n in DENSE_ROWS])
    for gap, noise, spacing in rows_asked:
        right = merged = folded = opened = invalid = 0
        t0 = time.perf_counter()
        for radius in RING_RADII:
            for seed in range(RING_SEEDS):
                rings = [radius * circle, (radius + gap * RING_EPS) * circle]
                pts = sample_rings(rings, spacing=spacing * RING_EPS, noise=noise * RING_EPS,
                                   seed=100 + seed)
                res = wavepoly.fit(pts, RING_EPS)
                bad = bool(truth.independent_problems(res))
                closed = [c.closed for c in res.contours]
                inner = [_inner_share(c.vertices, radius + 0.5 * gap * RING_EPS)
                         for c in res.contours]
                apart = (closed == [True, True]
                         and sorted(round(s) for s in inner) == [0, 1]
                         and all(min(s, 1 - s) <= OTHER_CIRCLE_SHARE for s in inner))
                invalid += bad
                merged += closed == [True]
                folded += closed == [True, True] and not apart
                opened += not all(closed)
                right += apart and not bad and len(res.outliers) == 0
        total = len(RING_RADII) * RING_SEEDS
        label = f"{gap:g} ε" + ("" if spacing == 1 / 3 else f", every ε / {1 / spacing:g}")
        rows.append([label, f"{noise:g} ε", f"{right}/{total}", merged, folded,
                     opened, invalid, time.perf_counter() - t0])
    return ("### Near rings\n\nTwo circles *gap* ε apart, one inside the other (the inner "
            f"{RING_RADII[0] / RING_EPS:g} and {RING_RADII[1] / RING_EPS:g} ε in radius), "
            "sampled every ε / 3 at random with Gaussian noise up to ε / 4, the issue's bound "
            "of a clean sampling (`benchmarks/near_rings.py`). *right*: two closed rings, "
            "each drawing one circle (at most a tenth of its vertices nearer the other), "
            "valid, no outliers; *merged*: one ring, where the march stepped across to the "
            "other circle where one's points thin out and back, or drew both as one zigzag; "
            "*folded*: two closed rings not one on each circle, each walked out along one "
            "circle and back along the other, or one reaching across to the other in teeth; "
            "*open*: results with an open piece. At 1.5 ε with noise ε / 4 each "
            "circle's band (four standard deviations wide) leaves half an ε of empty space "
            "between them. The last rows are a thin tube's walls, closer than ε: one ring "
            "down the middle keeps every point within ε but bounds the bore and the wall "
            "together (*merged*); those sampled every ε / 6 are walls about a tolerance "
            "apart as a thin shell's slice gives them.\n\n"
            + table(["gap", "noise", "right", "merged", "folded", "open", "invalid", "seconds"],
                    rows))


def _inner_share(vertices: np.ndarray, middle: float) -> float:
    """The share of a contour's vertices nearer the inner circle (closer to the centre than
    ``middle``, the radius halfway between the circles)."""
    return float(np.mean(np.hypot(vertices[:, 0], vertices[:, 1]) < middle))
