"""Valid geometry: per case, contours closed/open against the truth, invalid polygons, crossing
pairs (an independent shapely check, as a GIS or CAD user would run it), outliers, and the
vertex count against the covering min-#."""

from __future__ import annotations

import sys
import time

import numpy as np
import shapely

import wavepoly
from wavepoly.baselines import min_vertices_covering
from wavepoly.geometry import turn_backs
from wavepoly.samples import TrueShape, glyph_outlines, sample_rings

from .coarse import coarse_sweep
from .common import ROOT, SHARED, table
from .holes import blob_hole_sweep, hole_sweep, keyhole_sweep, small_hole_sweep
from .near_rings import near_rings_sweep
from .necks import neck_sweep, photo_silhouette_sweep
from .silhouettes import DRAWS_NEAR, MIN_RING_EXTENT, drawn_rings
from .specks import specks_sweep
from .unseen import unseen_sweep

#: A tooth's edges are shorter than this many tolerances.
TOOTH_EDGE = 2.0
#: The truth shapes are sampled at a tolerance of their diagonal / this, with noise ε / 8.
DIAGONAL_PER_TOLERANCE = 150.0


def _truth():
    if str(ROOT) not in sys.path:  # the truth measures live beside the tests
        sys.path.insert(0, str(ROOT))
    from tests import truth

    return truth


def _sample_shape(shape, eps: float, seed: int) -> np.ndarray:
    """Every ring sampled every ε / 3 along its length with Gaussian noise ε / 8."""
    rng = np.random.default_rng(seed)
    out = []
    for ring, closed in zip(shape.rings, shape.closed):
        verts = np.vstack([ring, ring[:1]]) if closed else ring
        cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(verts, axis=0), axis=1))])
        s = rng.uniform(0.0, cum[-1], max(8, int(3 * cum[-1] / eps)))
        out.append(np.column_stack([np.interp(s, cum, verts[:, 0]),
                                    np.interp(s, cum, verts[:, 1])]))
    pts = np.concatenate(out)
    return pts + rng.normal(scale=eps / 8, size=pts.shape)


def _cases():
    truth = _truth()
    for name in ("B8&k", "W", "%", "e@"):
        shape = glyph_outlines(name, height=20.0)
        for spacing in (0.015, 0.03):
            pts = sample_rings(shape.rings, spacing=spacing, noise=0.01, seed=1)
            yield f"glyphs '{name}', spacing {spacing}", pts, 0.08, shape
    yield from _ring_cases()
    svg = SHARED / "curves2d" / "ground_truth_svg"
    for path in sorted(svg.glob("*.svg")) if svg.is_dir() else []:
        shape = truth.svg_shape(path)
        eps = truth.diagonal(shape) / DIAGONAL_PER_TOLERANCE
        yield f"{path.stem} (svg truth)", _sample_shape(shape, eps, 0), eps, shape
    noisy = SHARED / "curves2d"
    for name, eps in (("noisy_sets/crab_2percent_noise.txt", 0.0422),
                      ("noisy_sets/Keyboard0.txt", 0.00609), ("noisy_sets/fish.txt", 0.02),
                      ("noisy_sets/bot.txt", 0.02), ("hnn_crust/crocodile-conf.p2d", 0.02),
                      ("noisy_sets/Cup0.txt", 0.01)):
        if (noisy / name).exists():
            pts = wavepoly.as_planar(wavepoly.read_points(noisy / name))
            yield name.split("/")[-1], pts, eps, None
    # 0.0135 and 0.00406: what `wavepoly info` suggests for the maps (twice their spacing),
    # at half the Intel map's scatter and a ninth of Freiburg's
    for name, eps in (("intel-corrected.log.gz", 0.0135), ("intel-corrected.log.gz", 0.05),
                      ("intel-corrected.log.gz", 0.085),
                      ("intel-corrected.log.gz", 0.1), ("freiburg-079-corrected.log.gz", 0.00406),
                      ("freiburg-079-corrected.log.gz", 0.06),
                      ("freiburg-079-corrected.log.gz", 0.1)):
        path = SHARED / "lidar2d" / name
        if path.exists():
            yield f"{name.split('-')[0]} laser map", wavepoly.read_points(path), eps, None


def _ring_cases():
    """Near-touching rings: two concentric circles 1.5-4 ε apart, sampled every ε / 3 at
    random, with no noise or Gaussian noise ε / 8 (the issue's "two walls closer than 2 ε")."""
    eps = 0.1
    for gap in (1.5, 2.0, 3.0, 4.0):
        for noise in (0.0, eps / 8):
            for radius in (3.0, 8.0):
                t = np.linspace(0, 2 * np.pi, 720, endpoint=False)
                rings = [r * np.column_stack([np.cos(t), np.sin(t)])
                         for r in (radius, radius + gap * eps)]
                pts = sample_rings(rings, spacing=eps / 3, noise=noise, seed=0)
                yield (f"rings {gap:g} ε apart, R {radius:g}, noise {noise / eps:g} ε", pts,
                       eps, TrueShape(rings, [True, True]))


def _covering_min(pts: np.ndarray, eps: float) -> int | None:
    """Fewest ordered points covering every input point, or None where no subset can."""
    ordering = wavepoly.order_points(pts, eps)
    total = 0
    for c in ordering.contours:
        keep = min_vertices_covering(c.points, c.closed, pts[c.members], eps)
        line = c.points[keep]
        geom = (shapely.linearrings(line) if c.closed and len(line) >= 3
                else shapely.linestrings(line))
        if shapely.distance(shapely.points(pts[c.members]), geom).max() > eps * (1 + 1e-9):
            return None
        total += len(keep)
    return total


def _against_truth(shape, result, eps: float) -> str:
    """Closed/open against the truth where its rings are disjoint (every ring one closed
    contour); where they meet (a line drawing's junctions), the Hausdorff distance between
    the drawn lines and the true ones, in ε."""
    rings = [shapely.linearrings(r) if c else shapely.linestrings(r)
             for r, c in zip(shape.rings, shape.closed)]
    disjoint = not any(shapely.intersects(rings[i], rings[j]) for i in range(len(rings))
                       for j in range(i + 1, len(rings)))
    if disjoint:
        n_closed = sum(shape.closed)
        got = sum(c.closed for c in result.contours)
        ok = got == n_closed and len(result.contours) == len(rings)
        return "yes" if ok else f"no ({n_closed}/{len(rings) - n_closed})"
    drawn = shapely.union_all([shapely.linearrings(c.vertices) if c.closed else
                               shapely.linestrings(c.vertices) for c in result.contours])
    hausdorff = shapely.hausdorff_distance(shapely.union_all(rings), drawn, densify=0.1)
    return f"junctions: Hausdorff {hausdorff / eps:.2f} ε"


def run() -> str:
    truth = _truth()
    rows = []
    for name, pts, eps, expected in _cases():
        t0 = time.perf_counter()
        res = wavepoly.fit(pts, eps)
        seconds = time.perf_counter() - t0
        problems = truth.independent_problems(res)
        crossing = sum(" meet" in p for p in problems)
        n_closed = sum(c.closed for c in res.contours)
        got = f"{n_closed}/{len(res.contours) - n_closed}"
        right = "—" if expected is None else _against_truth(expected, res, eps)
        cover = _covering_min(pts, eps) if len(pts) <= 200_000 else None
        teeth = _teeth(res.contours, eps)
        free = _free_space_share(res.contours, pts, eps)
        rows.append([name, len(pts), f"{eps:.4g}", got, right, len(problems) - crossing,
                     crossing, teeth, f"{100 * free:.1f} %",
                     f"{100 * len(res.outliers) / len(pts):.2f} %",
                     res.n_vertices,
                     "infeasible" if cover is None else f"{res.n_vertices / cover:.3f}",
                     seconds])
    return ("## Valid geometry\n\nEvery result checked with shapely directly (not with "
            "wavepoly's own check): *invalid* counts closed contours that are not valid "
            "polygons and open ones that are not simple; *crossing* counts pairs of contours "
            "that meet other than at an open contour's end (a junction). *teeth*: vertices "
            f"where a contour turns back by more than 135° between edges under {TOOTH_EDGE:g} ε, "
            "the teeth of a zigzag through a band of points (not counted on a contour no wider "
            f"than {TOOTH_EDGE:g} ε: a chair leg's triangle). *free space*: share of the drawn "
            "length farther than ε from every input point: lines across space where the scan "
            "saw nothing. On the laser maps that is clutter (chairs, desks) drawn as lines "
            "hopping between its sparse points; on a sample sparser than 2 ε (crocodile, "
            "fish.txt and bot.txt at a tenth of their scatter) every edge runs that far from "
            "the points between its ends, and the column says only that. "
            "*closed/open* is what "
            "the fit gives; *right* compares it with the truth where it is known (glyphs, and "
            "the SVG truth shapes sampled every ε/3 with noise ε/8, ε = diagonal / "
            f"{DIAGONAL_PER_TOLERANCE:g}): where the true rings are disjoint, every ring must "
            "be one closed contour; where they meet (a line drawing's T and X junctions, which "
            "no valid set of closed polygons can draw), the pieces meet at the junctions and "
            "the column gives the Hausdorff distance between the drawn and the true lines. "
            "*vs covering min-#*: vertices over the fewest ordered points that keep every "
            "input point within ε, with no validity constraint; *infeasible* where no subset "
            "of the ordered points can (a tolerance far below the point spacing); the "
            "Freiburg map is too big for that baseline. *outliers*: where the tolerance is "
            "below twice the points' own scatter (fish.txt and bot.txt at 0.02, a tenth of "
            "their scatter), they include the points farther than the tolerance from the "
            "curve through the middle of the band, which a polygon could only reach by "
            "zigzagging across it.\n\n"
            + table(["case", "points", "ε", "closed/open", "right", "invalid", "crossing",
                     "teeth", "free space", "outliers", "vertices", "vs covering min-#",
                     "seconds"], rows)
            + "\n\n" + glyph_sweep() + "\n\n" + silhouette_sweep() + "\n\n" + blob_sweep()
            + "\n\n" + near_rings_sweep(truth) + "\n\n" + specks_sweep(truth)
            + "\n\n" + hole_sweep(truth)
            + "\n\n" + keyhole_sweep(truth)
            + "\n\n" + small_hole_sweep(truth) + "\n\n" + blob_hole_sweep(truth, _one_per_ring)
            + "\n\n" + neck_sweep(truth)
            + "\n\n" + unseen_sweep(truth, _one_per_ring) + "\n\n" + photo_silhouette_sweep(truth)
            + "\n\n" + coarse_sweep(truth)
            + "\n\n" + laser_sweep())


#: The glyph sweep: fonts bundled with matplotlib, and samplings (spacing, noise, ε) of glyphs
#: 20 units high: noise ε / 4 at spacing ε / 3 (the issue's clean bound); a coarse ε with
#: the glyph 67 ε high (narrow slits and notches under 2 ε); and a coarser one, the glyph 25
#: ε high with noise ε / 8, where a serif font's hairlines are under half an ε wide.
#: Computer Modern (cmr10, TeX's serif) was never tuned on.
SWEEP_FONTS = ("DejaVu Sans", "DejaVu Serif", "STIXGeneral", "cmr10")
SWEEP_SAMPLINGS = ((0.03, 0.025, 0.1), (0.05, 0.02, 0.3), (0.1, 0.1, 0.8))
SWEEP_TEXT = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789&%@#$?"


def glyph_sweep() -> str:
    """Silhouettes not tuned for: every glyph of a few fonts, sampled cleanly (noise at most
    ε / 4), must come out as its true number of closed outlines, valid, with no outliers."""
    truth = _truth()
    rows, failed = [], []
    for font in SWEEP_FONTS:
        for k, (spacing, noise, eps) in enumerate(SWEEP_SAMPLINGS):
            right = total = 0
            wrong = []
            t0 = time.perf_counter()
            for ch in SWEEP_TEXT:
                shape = glyph_outlines(ch, height=20.0, family=font)
                pts = sample_rings(shape.rings, spacing=spacing, noise=noise, seed=k + 11)
                res = wavepoly.fit(pts, eps)
                ok = (not truth.independent_problems(res) and len(res.outliers) == 0
                      and [c.closed for c in res.contours] == [True] * len(shape.rings))
                total += 1
                right += ok
                if not ok:
                    closed = sum(c.closed for c in res.contours)
                    out = f", {len(res.outliers)} out" if len(res.outliers) else ""
                    wrong.append(f"'{ch}' {closed}/{len(res.contours) - closed} of "
                                 f"{len(shape.rings)}{out}")
            rows.append([font, spacing, noise, eps, f"{right}/{total}",
                         time.perf_counter() - t0])
            if wrong:
                failed.append(f"{font} at ε {eps:g}: " + ", ".join(wrong))
    return ("### Glyph sweep\n\nEvery letter and digit (and `&%@#$?`) of four fonts bundled "
            "with matplotlib, 20 units high, sampled at random along the outline with "
            "Gaussian noise; *right*: as many closed outlines as the glyph has rings, valid "
            "(the shapely check above), and no outliers. At ε 0.8 a serif font's hairlines "
            "are under half an ε wide.\n\n"
            + table(["font", "spacing", "noise", "ε", "right", "seconds"], rows)
            + ("\n\nNot right (closed/open of the true rings): " + "; ".join(failed) + "."
               if failed else ""))


if __name__ == "__main__":
    print(run())


#: The silhouette sweep: (bitmap pixels across the diagonal or None for the exact outline,
#: points or None for the tracer's own (one where the outline crosses a pixel edge), ε as a
#: share of the diagonal, noise in ε).
SILHOUETTE_SAMPLINGS = ((None, 3000, 1 / 300, 1 / 8), (None, 1000, 1 / 150, 0.0),
                        (None, 1000, 1 / 150, 1 / 4), (300, 3000, 1 / 150, 1 / 8),
                        (200, 2000, 1 / 100, 1 / 4), (300, None, 1 / 150, 0.0),
                        (600, None, 1 / 300, 0.0))
SILHOUETTES = 60
#: ... and exact outlines thinned across x to a share of their density (points at full
#: density, ε, noise in ε, the share kept on the sparse side).
THINNED_SAMPLINGS = ((1000, 1 / 150, 0.0, 0.25), (3000, 1 / 300, 1 / 8, 0.25))
def _one_per_ring(rings: list[np.ndarray], contours, eps: float) -> bool:
    """Whether every ring at least `MIN_RING_EXTENT` ε across is drawn by exactly one
    contour, no contour draws two of them, and there are no more contours than rings
    (`benchmarks.silhouettes.drawn_rings`). Counting alone lets a ring drawn in two pieces
    make up for two rings drawn as one."""
    draws = drawn_rings(rings, contours, eps)
    return (bool((draws.sum(axis=1) <= 1).all() and (draws.sum(axis=0) == 1).all())
            and len(contours) <= len(rings))


def silhouette_sweep() -> str:
    """Made-up silhouettes with slits and limbs narrower than the tolerance
    (`benchmarks.silhouettes`), exact or traced from a bitmap, sampled uniformly: each must
    come out as its rings, closed and valid, with no outliers."""
    from .silhouettes import bitmap, sample, silhouette, thinned

    truth = _truth()
    rows = []
    for pixels, n, eps, noise in SILHOUETTE_SAMPLINGS:
        right = invalid = 0
        t0 = time.perf_counter()
        for seed in range(SILHOUETTES):
            rings = silhouette(seed) if pixels is None else bitmap(silhouette(seed), pixels)
            pts = np.vstack(rings) if n is None else sample(rings, n, noise * eps, 1000 + seed)
            res = wavepoly.fit(pts, eps)
            problems = truth.independent_problems(res)
            invalid += bool(problems)
            right += (not problems and len(res.outliers) == 0
                      and all(c.closed for c in res.contours)
                      and _one_per_ring(rings, res.contours, eps))
        rows.append(["exact" if pixels is None else f"bitmap {pixels} px",
                     "traced" if n is None else n, f"diagonal / {1 / eps:g}", f"{noise:g} ε",
                     f"{right}/{SILHOUETTES}", invalid, time.perf_counter() - t0])
    for n, eps, noise, floor in THINNED_SAMPLINGS:
        right = invalid = 0
        t0 = time.perf_counter()
        for seed in range(SILHOUETTES):
            rings = silhouette(seed)
            res = wavepoly.fit(thinned(rings, n, noise * eps, floor, seed), eps)
            problems = truth.independent_problems(res)
            invalid += bool(problems)
            right += (not problems and len(res.outliers) == 0
                      and all(c.closed for c in res.contours)
                      and _one_per_ring(rings, res.contours, eps))
        rows.append([f"exact, thinned to {100 * floor:g} % across", n,
                     f"diagonal / {1 / eps:g}", f"{noise:g} ε", f"{right}/{SILHOUETTES}",
                     invalid, time.perf_counter() - t0])
    return ("### Silhouette sweep\n\nMade-up silhouettes (`benchmarks/silhouettes.py`): an "
            "elliptic body with bent limbs, a head, wedge slits cut in "
            "whose walls run closer than ε for most of their length, sometimes a hole; sampled "
            "uniformly along the outline, exact or as a bitmap's traced outline (staircase "
            "walls, spurs and notches a pixel wide, as a silhouette image gives them; *traced*: "
            "the tracer's own points, one where the outline crosses a pixel edge), or with "
            "their density thinned linearly across the part to a quarter on one side (the "
            "points column: at full density). *right*: "
            "every contour closed, one per ring (each ring drawn by one contour of its own, "
            "matched by where the contour runs, not only counted; a ring under "
            f"{MIN_RING_EXTENT:g} ε across, a sliver of a hole that a slit cut, may merge into "
            "its neighbour), valid, no outliers; *invalid*: "
            "results that fail the shapely check.\n\n"
            + table(["outline", "points", "ε", "noise", "right", "invalid", "seconds"], rows))


#: The blob sweep: seeds per row; blob sizes (a share of the image) and noises (in ε).
BLOB_SEEDS = 20
BLOB_ROWS = ((0.1, 0.0), (0.1, 0.25), (0.2, 0.0), (0.2, 0.25))
#: Blob images are this many pixels square; ε is their diagonal over `DIAGONAL_PER_TOLERANCE`.
BLOB_PIXELS = 256
#: A blob sweep result is within the truth when the drawn and the true outlines are within
#: this many ε of each other (Hausdorff both ways; noise ε / 4 puts points 0.75 ε out).
BLOB_HAUSDORFF = 1.5


def blob_sweep() -> str:
    """Random blobs traced from a bitmap (`benchmarks.silhouettes.blobs`), sampled every ε / 3:
    counted by rings as the silhouettes are, and by geometry (closed, valid, no outliers,
    within `BLOB_HAUSDORFF` ε of the truth), which forgives two blobs within a couple of ε of
    each other coming out as one outline."""
    from .silhouettes import blobs, tally_fits

    truth = _truth()
    eps = BLOB_PIXELS * np.sqrt(2) / DIAGONAL_PER_TOLERANCE
    rows = []
    for size, noise in BLOB_ROWS:
        images = [blobs(seed, size, BLOB_PIXELS) for seed in range(BLOB_SEEDS)]
        rows.append([f"{size:g}", f"{noise:g} ε",
                     *tally_fits(images, eps, noise, truth, _one_per_ring, BLOB_HAUSDORFF, 0)])
    return ("### Blob sweep\n\nRandom blobs in a 256-pixel image, as scikit-image's "
            "`binary_blobs` makes them (`benchmarks/silhouettes.py`: 7 to 40 rounded outlines "
            "per image, a few pixels to a third of the image across, touching one another now "
            "and then at a pixel's corner), traced, ε = diagonal / "
            f"{DIAGONAL_PER_TOLERANCE:g} (2.4 pixels), sampled every ε / 3 with Gaussian noise. "
            "*by rings*: every contour closed, one per ring (as the silhouettes are counted: "
            f"each ring at least {MIN_RING_EXTENT:g} ε across drawn by one contour, a contour "
            f"drawing a ring where a quarter of its length runs within {DRAWS_NEAR:g} ε of it), "
            f"valid, no outliers; *by shape*: closed, valid, no outliers and within "
            f"{BLOB_HAUSDORFF:g} ε of the true outlines both ways, measured along the lines, "
            "which forgives two blobs "
            "drawn as one outline where they come within a couple of ε of each other (with "
            "noise, a corner of one 1.2-1.9 ε from the other, inside the neighbourhoods "
            "widened to follow the curves through it).\n\n"
            + table(["blob size", "noise", "right by rings", "right by shape", "invalid",
                     "seconds"], rows))


#: The made-up laser maps (`benchmarks.laser`) and the tolerances they are fitted at: 0.1 m,
#: some 4 x their walls' scatter (as the Intel map at 0.1), and 0.05 m, some 2.2 x.
LASER_SEEDS = 5
LASER_TOLERANCES = (0.1, 0.05)
#: Drawn lines farther than this many ε from every true surface are off the walls.
OFF_WALLS = 2.0
#: A drawn edge near a wall running at more than this angle (degrees) to it is askew.
ASKEW = 30.0


def laser_sweep() -> str:
    """Made-up laser maps whose truth is known (`benchmarks.laser`): validity, teeth,
    outliers, and how much of the drawing lies off the true walls."""
    from .laser import BEAMS, FAR_BEAMS, FAR_RANGE, MAX_RANGE, laser_map

    truth = _truth()
    rows = []
    scanners = [(seed, MAX_RANGE, BEAMS) for seed in range(LASER_SEEDS)] + [
        (seed, FAR_RANGE, FAR_BEAMS) for seed in range(LASER_SEEDS, 2 * LASER_SEEDS)]
    for seed, max_range, beams in scanners:
        pts, walls = laser_map(seed, max_range, beams)
        for eps in LASER_TOLERANCES:
            t0 = time.perf_counter()
            res = wavepoly.fit(pts, eps)
            seconds = time.perf_counter() - t0
            lines = [shapely.LineString(np.vstack([c.vertices, c.vertices[:1]]) if c.closed
                                        else c.vertices) for c in res.contours]
            drawn = sum(line.length for line in lines)
            near = walls.buffer(OFF_WALLS * eps)
            off = sum(line.difference(near).length for line in lines)
            askew = _askew_length(res.contours, walls, eps)
            n_closed = sum(c.closed for c in res.contours)
            teeth = _teeth(res.contours, eps)
            rows.append([seed, f"{max_range:g} m, {beams}", len(pts), f"{eps:g}",
                         f"{n_closed}/{len(res.contours) - n_closed}",
                         len(truth.independent_problems(res)), teeth,
                         f"{100 * len(res.outliers) / len(pts):.2f} %",
                         f"{100 * off / drawn:.1f} % of {drawn:.0f} m",
                         f"{100 * askew / drawn:.1f} %", res.n_vertices,
                         res.suggested_tolerance or "—", seconds])
    return ("### Laser map sweep\n\nMade-up laser maps (`benchmarks/laser.py`): a floor of "
            "rooms off a corridor, walls 0.12-0.25 m thick (a room's wall and the next room's "
            "side by side), doors, desks, a table with chair legs, pillars, people standing by; "
            "a robot drives the corridor and into every room, scanning 180° with range noise "
            "0.01 m and the pose error scan matching leaves (0.02 m, 0.3°): each wall a band "
            "of scatter about 0.022 m. Maps 0-4 are scanned to 8 m with 181 beams; maps 5-9 "
            f"(floors the ordering was never tuned on) to {FAR_RANGE:g} m with {FAR_BEAMS} "
            "beams, where the far walls' returns are sparse and the heading error spreads "
            "them over a band as wide as a thin wall. *off the walls*: drawn length farther than "
            f"{OFF_WALLS:g} ε from every true surface (people standing by are no surface, and "
            "a person seen from a few poses is drawn); *askew*: drawn length near the walls "
            f"that runs at more than {ASKEW:g}° to the nearest of them, a zigzag between the "
            "two sides of a thick wall; *suggested*: the tolerance the fit "
            "suggests where the asked one is below the scatter.\n\n"
            + table(["map", "scanner", "points", "ε", "closed/open", "invalid", "teeth",
                     "outliers", "off the walls", "askew", "vertices", "suggested", "seconds"],
                    rows))


def _teeth(contours, eps: float) -> int:
    """Vertices where a contour turns back by more than 135° between edges under
    `TOOTH_EDGE` ε: the teeth of a zigzag through a band. A contour no wider than that (a
    speck's ring, a chair leg's triangle on a laser map) draws no band and has none."""
    return sum(turn_backs(c.vertices, c.closed, TOOTH_EDGE * eps) for c in contours
               if np.ptp(c.vertices, axis=0).max() > TOOTH_EDGE * eps)


def _askew_length(contours, walls, eps: float) -> float:
    """Drawn length within `OFF_WALLS` ε of the true ``walls`` that runs at more than `ASKEW`
    degrees to the nearest of them (measured every ε / 2 along each edge)."""
    from wavepoly.geometry import nearest_of_segments

    coords = [np.asarray(line.coords) for line in shapely.get_parts(walls)]
    wa = np.vstack([c[:-1] for c in coords])
    wb = np.vstack([c[1:] for c in coords])
    at, direction, weight = _edge_samples(contours, eps / 2)
    seg, dist = nearest_of_segments(at, wa, wb)
    d = (wb - wa)[seg]
    cos = np.abs(np.einsum("ij,ij->i", d, direction)) / np.maximum(
        np.linalg.norm(d, axis=1) * np.linalg.norm(direction, axis=1), 1e-300)
    askew = (dist <= OFF_WALLS * eps) & (cos < np.cos(np.radians(ASKEW)))
    return float(np.sum(weight * askew))


def _free_space_share(contours, pts: np.ndarray, eps: float) -> float:
    """Share of the drawn length farther than ε from every input point (measured every
    ε / 4 along each edge): lines drawn across space where the scan saw nothing."""
    from scipy.spatial import cKDTree

    if not contours:
        return 0.0
    at, _, weight = _edge_samples(contours, eps / 4)
    dist, _ = cKDTree(pts[:, :2]).query(at, distance_upper_bound=eps)
    return float(np.sum(weight * np.isinf(dist)) / np.sum(weight))


def _edge_samples(contours, step: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Points at most ``step`` apart along every edge of the contours (at the middles of equal
    pieces), each with its edge's direction and the length it stands for."""
    from wavepoly.geometry import polyline_segments

    a, b = (np.vstack(e) for e in zip(*(polyline_segments(c.vertices, c.closed)
                                        for c in contours)))
    length = np.linalg.norm(b - a, axis=1)
    samples = np.maximum(1, np.ceil(length / step)).astype(int)
    edge = np.repeat(np.arange(len(a)), samples)
    within = np.arange(len(edge)) - np.repeat(np.cumsum(samples) - samples, samples)
    at = a[edge] + ((within + 0.5) / samples[edge])[:, None] * (b - a)[edge]
    return at, (b - a)[edge], (length / samples)[edge]
