"""Full decomposition of 2^16 + 3 and 2^20 + 3 control points (goal: <= 0.05 s and <= 1 s)."""

from __future__ import annotations

import time

import numpy as np

from wavepoly import wavelets

from .common import best_time, table


def run() -> str:
    rows = []
    rng = np.random.default_rng(0)
    for closed in (False, True):
        for level in (12, 14, 16, 18, 20):
            c = rng.normal(size=(wavelets.n_coefficients(level, closed), 2))
            depth = level - wavelets.MIN_LEVEL[closed]
            for cache in (wavelets.synthesis_p, wavelets.synthesis_q, wavelets.gram,
                          wavelets.analysis_solver):
                cache.cache_clear()
            t0 = time.perf_counter()
            wavelets.decompose(c, depth, closed=closed)
            cold = time.perf_counter() - t0
            warm, (coarse, details) = best_time(
                lambda c=c, depth=depth, closed=closed: wavelets.decompose(c, depth,
                                                                           closed=closed))
            rec, back = best_time(
                lambda coarse=coarse, details=details, closed=closed: wavelets.reconstruct(
                    coarse, details, closed=closed))
            err = float(np.abs(back - c).max() / np.abs(c).max())
            rows.append(["closed" if closed else "open", f"2^{level}", len(c), cold, warm,
                         len(c) / warm / 1e6, rec, err])
    return ("## Wavelet decomposition\n\nAll levels down to the coarsest, (m, 2) control "
            "points. *cold*: first call, building the filters and LU factors of every level; "
            "*warm*: factors cached (the case of many contours).\n\n" +
            table(["flavour", "size", "m", "cold s", "warm s", "M coeff/s warm",
                   "reconstruct s", "round-trip rel. error"], rows))


if __name__ == "__main__":
    print(run())
