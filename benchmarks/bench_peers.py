"""Peers side by side: every method gets the same points and tolerance, and every result is
measured the same way (the distance of every input point to the method's output)."""

from __future__ import annotations

import time

import numpy as np
import shapely

import wavepoly
from wavepoly.baselines import douglas_peucker, min_vertices, min_vertices_covering
from wavepoly.geometry import polyline_distance
from wavepoly.ordering import order_points
from wavepoly.samples import glyph_outlines, sample_rings

from . import otr2
from .common import SHARED, table

EPS = 0.08
HULL_MAX_POINTS = 50_000  # a laser map of open walls is no outline; its hull takes minutes
HAUSDORFF = ("wavepoly", "DP tuned", "VW tuned", "concave hull", "OTR2")


def _largest_within(simplify, error, eps: float, lo: float, hi: float, steps: int = 24):
    """``simplify(p)`` for the largest p in [lo, hi] (bisection, log scale) whose ``error`` is
    within ``eps``; ``simplify(lo)`` if none is."""
    best = simplify(lo)
    for _ in range(steps):
        mid = np.sqrt(lo * hi)
        out = simplify(mid)
        if error(out) <= eps:
            best, lo = out, mid
        else:
            hi = mid
    return best


def _tuned(simplify, ordered: np.ndarray, closed: bool, members: np.ndarray, eps: float,
           lo: float, hi: float) -> np.ndarray:
    """The simplification of one contour, tuned to keep every member point within ``eps``."""
    def error(out):
        return _error(members, out, closed) if len(out) >= (3 if closed else 2) else np.inf

    return _largest_within(lambda p: simplify(ordered, p), error, eps, lo, hi)


def _error(points: np.ndarray, polyline: np.ndarray, closed: bool) -> float:
    if not len(points):
        return 0.0
    return float(polyline_distance(points, polyline, closed and len(polyline) >= 3).max())


def _vw(points: np.ndarray, area: float, closed: bool) -> np.ndarray:
    from simplification.cutil import simplify_coords_vw

    ring = np.vstack([points, points[:1]]) if closed else points
    out = np.asarray(simplify_coords_vw(np.ascontiguousarray(ring), area))
    return out[:-1] if closed and len(out) > 1 else out


def _per_contour(ordering, pts, eps, method) -> tuple[int, float, list]:
    """Run ``method(contour)`` on each ordered contour: vertices, max error, polylines."""
    n, err, lines = 0, 0.0, []
    for c in ordering.contours:
        out = method(c)
        n += len(out)
        err = max(err, _error(pts[c.members], out, c.closed))
        lines.append((out, c.closed))
    return n, err, lines


def _concave_hull(pts: np.ndarray, eps: float) -> tuple:
    """What a Python user does today: shapely.concave_hull, then simplify, tuned to eps."""
    if len(pts) > HULL_MAX_POINTS:
        return None, None, None, f"not run (> {HULL_MAX_POINTS} points)"
    hull = shapely.concave_hull(shapely.multipoints(pts), ratio=0.01, allow_holes=True)
    polys = [p for p in getattr(hull, "geoms", [hull]) if p.geom_type == "Polygon"]
    rings = [np.asarray(r.coords)[:-1] for p in polys for r in [p.exterior, *p.interiors]]
    if not rings:
        return 0, float("inf"), [], "no polygon"

    def simplify(tol: float) -> list[np.ndarray]:
        out = [np.asarray(shapely.simplify(shapely.linearrings(r), tol).coords)[:-1]
               for r in rings]
        return [o if len(o) >= 3 else r for o, r in zip(out, rings)]

    def error(simplified: list[np.ndarray]) -> float:
        dist = np.full(len(pts), np.inf)
        for ring in simplified:
            np.minimum(dist, polyline_distance(pts, ring, True), out=dist)
        return float(dist.max())

    best = _largest_within(simplify, error, eps, 1e-6 * eps, eps, steps=16)
    return sum(len(r) for r in best), error(best), [(r, True) for r in best], \
        f"{len(rings)} ring(s)"


def _otr2(pts: np.ndarray, eps: float) -> tuple:
    """CGAL OTR2's fewest vertices within eps, or why it was not run."""
    if not otr2.available():
        return None, "not built (make bench needs libcgal-dev)"
    if len(pts) > otr2.MAX_POINTS:
        return None, f"not run (> {otr2.MAX_POINTS} points)"
    res = otr2.reconstruct(pts, eps)
    return res, f"{res.fragments} piece(s), {res.open_ends} open end(s)"


def _hausdorff(lines: list | None, truth_rings: list) -> float:
    if not lines:
        return float("inf")
    out = shapely.MultiLineString([np.vstack([v, v[:1]]) if c else v for v, c in lines
                                   if len(v) >= 2])
    truth = shapely.MultiLineString([np.vstack([r, r[:1]]) for r in truth_rings])
    return float(shapely.hausdorff_distance(out, truth, densify=0.05))


def _case(label: str, pts: np.ndarray, eps: float, truth: list | None) -> dict:
    t0 = time.perf_counter()
    res = wavepoly.fit(pts, eps)
    t_wav = time.perf_counter() - t0
    t0 = time.perf_counter()
    auto = wavepoly.fit(pts, eps, relative_tolerance=None)
    t_auto = time.perf_counter() - t0
    ordering = order_points(pts, eps)
    lines_w = [(c.vertices, c.closed) for c in res.contours]
    n_cov, err_cov, _ = _per_contour(ordering, pts, eps, lambda c: c.points[
        min_vertices_covering(c.points, c.closed, pts[c.members], eps)])
    n_min, err_min, _ = _per_contour(ordering, pts, eps,
                                     lambda c: c.points[min_vertices(c.points, eps, c.closed)])
    t0 = time.perf_counter()
    n_dp, err_dp, _ = _per_contour(ordering, pts, eps,
                                   lambda c: douglas_peucker(c.points, eps, c.closed))
    t_dp = time.perf_counter() - t0
    t0 = time.perf_counter()
    n_dpt, err_dpt, lines_dpt = _per_contour(ordering, pts, eps, lambda c: _tuned(
        lambda p, t: douglas_peucker(p, t, c.closed), c.points, c.closed, pts[c.members], eps,
        1e-6 * eps, eps))
    t_dpt = time.perf_counter() - t0
    t0 = time.perf_counter()
    n_vw, err_vw, lines_vw = _per_contour(ordering, pts, eps, lambda c: _tuned(
        lambda p, a: _vw(p, a, c.closed), c.points, c.closed, pts[c.members], eps,
        1e-8 * eps**2, 10 * eps**2))
    t_vw = time.perf_counter() - t0
    t0 = time.perf_counter()
    n_ch, err_ch, lines_ch, note = _concave_hull(pts, eps)
    t_ch = time.perf_counter() - t0
    row = {"case": label, "points": len(pts), "eps": eps,
           "wavepoly": (res.n_vertices, res.max_error, t_wav, lines_w),
           "wavepoly auto": (auto.n_vertices, auto.max_error, t_auto, None),
           "stages": res.timings,
           "covering min-#": (n_cov, None, None, None),
           "covering feasible": err_cov <= eps * (1 + 1e-9), "min-#": (n_min, err_min, None, None),
           "DP": (n_dp, err_dp, t_dp, None), "DP tuned": (n_dpt, err_dpt, t_dpt, lines_dpt),
           "VW tuned": (n_vw, err_vw, t_vw, lines_vw),
           "concave hull": (n_ch, err_ch, t_ch, lines_ch), "hull note": note,
           "contours": len(res.contours), "open": sum(not c.closed for c in res.contours)}
    res_otr, row["otr2 note"] = _otr2(pts, eps)
    row["OTR2"] = ((res_otr.n_vertices, res_otr.max_error, res_otr.seconds, res_otr.lines)
                   if res_otr else (None, None, None, None))
    row["hausdorff"] = ({k: _hausdorff(row[k][3], truth) for k in HAUSDORFF} if truth else {})
    return row


def _glyph_cases():
    for text in ("B", "8", "&", "S", "%", "kx"):
        shape = glyph_outlines(text)
        for noise in (0.0, 0.02, 0.04):
            pts = sample_rings(shape.rings, spacing=0.012, noise=noise, seed=2)
            yield f"glyph '{text}' noise {noise}", pts, EPS, shape.rings
    for text in ("B", "8", "&"):  # sparser, so that OTR2 (about 2.5 ms a point) can run too
        shape = glyph_outlines(text)
        for noise in (0.0, 0.02):
            pts = sample_rings(shape.rings, spacing=0.02, noise=noise, seed=2)
            yield f"glyph '{text}' noise {noise}, spacing 0.02", pts, EPS, shape.rings


def _slice(points3d: np.ndarray, axis: int, frac: float, half_width: float) -> np.ndarray:
    """The points within ``half_width`` of a plane across ``axis``, projected onto it."""
    h = points3d[:, axis]
    band = np.abs(h - (h.min() + frac * np.ptp(h))) <= half_width
    return np.delete(points3d[band], axis, axis=1)


def _real_cases():
    from wavepoly.io import read_points
    from wavepoly.ordering import curve_spacing

    noisy = SHARED / "curves2d" / "noisy_sets"
    for name in ("Keyboard0.txt", "Cup0.txt", "apple_2percent_noise.txt",
                 "butterfly_2percent_noise.txt", "dolphin_2percent_noise.txt"):
        pts = read_points(noisy / name)[:, :2]
        yield name, pts, 3 * curve_spacing(pts), None
    scans = SHARED / "scans3d"
    blade = read_points(scans / "turbineblade.ply")
    eps = 0.005 * float(np.ptp(blade, axis=0).max())
    for label, frac in (("root block", 0.05), ("airfoil", 0.6)):
        yield f"turbine blade slice, {label}", _slice(blade, 2, frac, eps), eps, None
    for label, path in (("bunny slice (merged)", scans / "bunny_zipper.ply"),
                        ("bunny range scan bun000 slice (open)",
                         scans / "bunny_range_scans" / "bun000.ply")):
        bunny = read_points(path)
        eps = 0.01 * float(np.ptp(bunny, axis=0).max())
        yield label, _slice(bunny, 1, 0.5, eps), eps, None
    yield "Intel lab laser map", read_points(SHARED / "lidar2d" / "intel-corrected.log.gz"), \
        0.05, None


def _cases():
    yield from _glyph_cases()
    if SHARED.exists():
        yield from _real_cases()


def _cell(r: dict, m: str) -> str:
    n, err, _, _ = r[m]
    if n is None:
        return "—"
    if m == "covering min-#" and not r["covering feasible"]:
        return "infeasible"
    if err is None:
        return str(n)
    flag = "" if err <= r["eps"] * (1 + 1e-9) else " **breaks ε**"
    return f"{n} ({err / r['eps']:.2f}ε){flag}"


def _seconds(r: dict, m: str) -> str:
    n, _, t, _ = r[m]
    return "—" if t is None or n is None else f"{t:.3g}"  # a method not run has no time


def _summary(rows: list[dict]) -> str:
    feasible = [r for r in rows if r["covering feasible"]]
    ratios = np.array([r["wavepoly"][0] / r["covering min-#"][0] for r in feasible])
    auto = np.array([r["wavepoly auto"][0] / r["covering min-#"][0] for r in feasible])
    ratios_min = np.array([r["wavepoly"][0] / r["min-#"][0] for r in rows])
    worst = feasible[int(ratios.argmax())]["case"]
    otr = [r for r in rows if r["OTR2"][0] is not None]
    otr_within = [r for r in otr if r["OTR2"][1] <= r["eps"] * (1 + 1e-9)]
    text = (f"**wavepoly / covering min-#: mean {ratios.mean():.3f}, worst {ratios.max():.3f}** "
            f"({worst}) over the {len(feasible)} cases where some subset of the ordered points "
            f"covers every input point (goal ≤ 1.10 mean, ≤ 1.3 worst; "
            f"{len(rows) - len(feasible)} case(s) have no such subset, because the ordering "
            "widened its radius beyond ε or a merged wall leaves points out of reach). "
            f"With the automatic relative tolerance: mean {auto.mean():.3f}, worst "
            f"{auto.max():.3f}. wavepoly / classic min-#: mean {ratios_min.mean():.3f}, worst "
            f"{ratios_min.max():.3f}.")
    if otr:
        text += (f" OTR2 ran on {len(otr)} cases and kept every point within ε on "
                 f"{len(otr_within)}" + (
                     "; wavepoly / OTR2 there: " + ", ".join(
                         f"{r['wavepoly'][0] / r['OTR2'][0]:.2f} ({r['case']})"
                         for r in otr_within)
                     if otr_within else "") + ".")
    return text


METHODS = ["wavepoly", "wavepoly auto", "covering min-#", "min-#", "DP", "DP tuned", "VW tuned",
           "concave hull", "OTR2"]
STAGES = ("ordering", "decomposition", "reconstruction", "verification")
TIMED = ["wavepoly", "wavepoly auto", "DP", "DP tuned", "VW tuned", "concave hull", "OTR2"]


def run() -> str:
    rows = [_case(*c) for c in _cases()]
    vert_rows = [[r["case"], r["points"], f"{r['eps']:.3g}", f"{r['contours']} ({r['open']} open)"]
                 + [_cell(r, m) for m in METHODS] + [r["hull note"], r["otr2 note"]]
                 for r in rows]
    time_rows = [[r["case"]] + [f"{r['stages'][k]:.3g}" for k in STAGES]
                 + [_seconds(r, m) for m in TIMED] for r in rows]
    haus_rows = [[r["case"]] + [f"{r['hausdorff'][m]:.3g}" if r[m][0] is not None else "—"
                                for m in HAUSDORFF] for r in rows if r["hausdorff"]]
    return (
        "## Peers: vertices at the same tolerance\n\n"
        "Each cell: vertices (max distance of any input point to the output, in ε); "
        "*wavepoly auto* is `fit(..., relative_tolerance=None)`. Every "
        "method but the concave hull and OTR2 works on the same ordered contours (§2); *tuned* "
        "means its parameter is the largest (bisection) that keeps every input point within ε. "
        "*covering min-#*: the fewest ordered points that keep every input point within ε "
        "(the limit for a polygon through ordered points); *min-#*: the classic optimum that "
        "only keeps the ordered points within ε (on noisy scans it leaves input points out). "
        "The concave hull (`shapely.concave_hull`, ratio 0.01, holes allowed, then "
        "`simplify` tuned per ring) sees the raw points; it cannot give open curves, and it "
        "bridges separate islands. *OTR2* is CGAL's optimal-transport reconstruction (de Goes "
        "et al. 2011, `benchmarks/peers/otr2.cpp`) on the raw points, decimated by `run_until` "
        "and reported at the fewest vertices that keep every point within ε, or, where no "
        "vertex count does, at its smallest error; its pieces and open ends are in the last "
        "column (a closed glyph outline should be one piece with no open end per ring). It "
        f"runs only on cases of at most {otr2.MAX_POINTS} points.\n\n"
        + table(["case", "points", "ε", "contours"] + METHODS + ["hull", "OTR2 output"],
                vert_rows)
        + "\n\n" + _summary(rows) + "\n\n"
        "### Hausdorff distance to the true curve (glyphs)\n\n"
        + table(["case", *HAUSDORFF], haus_rows)
        + "\n\n### Wall time (s)\n\nThe first four columns are wavepoly's stages (default "
        "settings); *wavepoly* is its whole pipeline, *wavepoly auto* the same with the "
        "automatic relative tolerance (eq. 7, three start levels). The simplifiers start from "
        "wavepoly's ordered contours; OTR2's time is to the reported vertex count, from reading "
        "the points.\n\n"
        + table(["case", *STAGES, *TIMED], time_rows))


if __name__ == "__main__":
    print(run())
