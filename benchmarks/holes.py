"""A hole by its outline's wall: the validity benchmark's sweep of holes whose corner comes
within a tolerance of the outline (a thin wall between them), where the march runs from the
outline into the hole and back (`wavepoly.ordering.shared_walls`, `wavepoly.ordering.waists`);
its converse, a keyhole: a slit from the outline into a round hole, one outline, which the
march runs through the same way; and small round holes a couple of tolerances from their
outline, alone in a disk or in round blobs, which must not join it as a notch or a limb
(`wavepoly.ordering.mouths`).
"""

from __future__ import annotations

import time

import numpy as np
import shapely
from shapely import affinity

import wavepoly
from wavepoly.samples import sample_rings

from .common import table
from .silhouettes import tally_fits

#: The sweep: the wall's thinnest (the gap between the hole's corner and the outline, in ε),
#: the noise (in ε), and seeds of each (each seed turns the hole and moves it along the wall).
HOLE_GAPS = (0.4, 0.75)
HOLE_NOISE = (0.0, 0.125, 0.25)
HOLE_SEEDS = 12
#: The keyhole sweep: slit widths (in ε), the noise (in ε) and seeds of each (each seed turns
#: the keyhole).
SLIT_WIDTHS = (1.0, 1.5, 2.0, 2.5)
SLIT_NOISE = (0.0, 0.125, 0.25)
SLIT_SEEDS = 8
#: The small holes' sweep: gaps between hole and outline (in ε), the noise (in ε), the holes'
#: diameters (in ε) and seeds of each (each seed moves the hole round the disk).
SMALL_HOLE_GAPS = (1.25, 1.5, 2.0)
SMALL_HOLE_NOISE = (0.0, 0.125, 0.25)
SMALL_HOLE_SIZES = (4.0, 6.0)
SMALL_HOLE_SEEDS = 8
#: Round blobs: (ε as a share of 3 units, about a scene's diagonal; noise in ε), each over
#: `BLOB_SCENES` scenes of 1 to 3 blobs 0.5-1.2 units across, some with a hole.
BLOB_SAMPLINGS = ((60, 0.125), (60, 0.25), (100, 0.25))
BLOB_SCENES = 40


def hole_by_the_wall(gap: float, angle: float = 150.0, turn: float = 10.0, eps: float = 1.0
                     ) -> list[np.ndarray]:
    """An ellipse 84 x 120 ε, and a square hole 14 x 12 ε turned ``turn`` degrees, moved in
    from the wall at ``angle`` degrees until its nearest corner is ``gap`` ε from the wall."""
    outer = affinity.scale(shapely.Point(0, 0).buffer(60.0 * eps, 64), 0.7, 1.0)
    t = np.radians(angle)
    wall = np.array([42 * np.cos(t), 60 * np.sin(t)]) * eps
    inward = -wall / np.linalg.norm(wall)
    square = affinity.rotate(shapely.box(-7 * eps, -6 * eps, 7 * eps, 6 * eps), turn,
                             origin=(0, 0))
    lo, hi = 0.0, 60.0 * eps  # how far inside the wall the hole's centre lies, bisected
    for _ in range(60):
        mid = (lo + hi) / 2
        hole = affinity.translate(square, *(wall + inward * mid))
        if outer.contains(hole) and outer.exterior.distance(hole) >= gap * eps:
            hi = mid
        else:
            lo = mid
    hole = affinity.translate(square, *(wall + inward * hi))
    return [np.asarray(outer.exterior.coords)[:-1], np.asarray(hole.exterior.coords)[:-1]]


def keyhole(width: float, turn: float = 0.0, eps: float = 1.0) -> list[np.ndarray]:
    """A disk 60 ε across with a round hole 16 ε across 5 ε inside its wall, and a slit
    ``width`` ε wide from the wall into the hole, turned ``turn`` degrees: one ring."""
    disk = shapely.Point(0, 0).buffer(30.0 * eps, 64)
    centre = 17.0 * eps
    hole = shapely.Point(centre, 0).buffer(8.0 * eps, 32)
    slit = shapely.box(centre, -width * eps / 2, 31.0 * eps, width * eps / 2)
    shape = affinity.rotate(disk.difference(hole.union(slit)), turn, origin=(0, 0))
    return [np.asarray(shape.exterior.coords)[:-1]]


def one_outline(result, truth) -> tuple[bool, bool, bool]:
    """Whether a fit of one outline is right (one closed contour, valid, no outliers), split
    (more than one contour) and invalid (``truth.independent_problems``)."""
    bad = bool(truth.independent_problems(result))
    right = ([c.closed for c in result.contours] == [True] and not bad
             and len(result.outliers) == 0)
    return right, len(result.contours) > 1, bad


def keyhole_sweep(truth) -> str:
    """For each slit width and noise, fits of `SLIT_SEEDS` keyholes sampled every ε / 3:
    *one outline* (right: one closed contour, valid, no outliers), *split* (the outline and
    the hole apart, the slit closed) and *invalid* (``truth.independent_problems``)."""
    rows = []
    for width in SLIT_WIDTHS:
        for noise in SLIT_NOISE:
            right = split = invalid = 0
            for seed in range(SLIT_SEEDS):
                pts = sample_rings(keyhole(width, 37.0 * seed), spacing=1 / 3, noise=noise,
                                   seed=seed)
                one, apart, bad = one_outline(wavepoly.fit(pts, 1.0), truth)
                right, split, invalid = right + one, split + apart, invalid + bad
            rows.append([f"{width:g} ε", f"{noise:g} ε", f"{right}/{SLIT_SEEDS}", split,
                         invalid])
    return ("### A keyhole\n\nThe converse of a hole by the wall: a disk 60 ε across with a "
            "round hole 16 ε across 5 ε inside its wall and a slit *width* ε wide from the "
            "wall into the hole (`benchmarks/holes.py`), turned at random, sampled every ε / 3 "
            "with Gaussian noise: one outline. *right*: one closed outline, valid, no "
            "outliers; *split*: more than one contour (the outline and the hole, the slit "
            "closed). Where the slit is about as narrow as ε and its walls are noisy, the "
            "points read as a hole by a thin wall as well.\n\n"
            + table(["slit", "noise", "right", "split", "invalid"], rows))


def hole_sweep(truth) -> str:
    """For each gap and noise, fits of `HOLE_SEEDS` samplings every ε / 3: *right* (the
    outline and its hole, nested, valid, no outliers), *notch* (one closed outline: the hole
    read as a notch across the thin wall), *open* (any open piece) and *invalid*
    (``truth.independent_problems``)."""
    rows = []
    for gap in HOLE_GAPS:
        for noise in HOLE_NOISE:
            right = notch = opened = invalid = 0
            t0 = time.perf_counter()
            for seed in range(HOLE_SEEDS):
                rng = np.random.default_rng(seed)
                rings = hole_by_the_wall(gap, rng.uniform(0, 360), rng.uniform(0, 90))
                pts = sample_rings(rings, spacing=1 / 3, noise=noise, seed=seed)
                res = wavepoly.fit(pts, 1.0)
                closed = [c.closed for c in res.contours]
                bad = bool(truth.independent_problems(res))
                invalid += bad
                opened += not all(closed)
                notch += closed == [True]
                right += (closed == [True, True] and sorted(res.parents) == [-1, 0]
                          and not bad and len(res.outliers) == 0)
            rows.append([f"{gap:g} ε", f"{noise:g} ε", f"{right}/{HOLE_SEEDS}", notch, opened,
                         invalid, time.perf_counter() - t0])
    return ("### A hole by the wall\n\nAn ellipse 84 x 120 ε with a square hole 14 x 12 ε, "
            "turned and moved along the wall at random, whose nearest corner comes *gap* ε "
            "from the outline (`benchmarks/holes.py`), sampled every ε / 3 with Gaussian "
            "noise. *right*: the outline and its hole, nested, valid, no outliers; *notch*: "
            "one closed outline, the hole read as a notch across the thin wall (from the "
            "points alone a short slit from the outline into the hole, a keyhole, reads the "
            "same); *open*: results with an open piece.\n\n"
            + table(["gap", "noise", "right", "notch", "open", "invalid", "seconds"], rows))


def small_hole(diameter: float, gap: float, angle: float, eps: float = 1.0
               ) -> list[np.ndarray]:
    """A disk 24 ε across and a round hole ``diameter`` ε across whose wall comes ``gap`` ε
    from the disk's, towards ``angle`` degrees."""
    t = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    circle = np.column_stack([np.cos(t), np.sin(t)])
    towards = np.array([np.cos(np.radians(angle)), np.sin(np.radians(angle))])
    centre = (12.0 - gap - diameter / 2) * eps * towards
    return [12.0 * eps * circle, centre + diameter / 2 * eps * circle[::-1]]


def small_hole_sweep(truth) -> str:
    """For each gap and noise, fits of the small holes (`SMALL_HOLE_SIZES` x
    `SMALL_HOLE_SEEDS` samplings every ε / 3): *right* (the outline and its hole, nested,
    valid, no outliers), *joined* (one closed outline: the hole drawn as a notch of it) and
    *invalid* (``truth.independent_problems``)."""
    rows = []
    for gap in SMALL_HOLE_GAPS:
        for noise in SMALL_HOLE_NOISE:
            right = joined = invalid = 0
            t0 = time.perf_counter()
            for size in SMALL_HOLE_SIZES:
                for seed in range(SMALL_HOLE_SEEDS):
                    rings = small_hole(size, gap, 360.0 * seed / SMALL_HOLE_SEEDS + 7.0)
                    pts = sample_rings(rings, spacing=1 / 3, noise=noise, seed=seed)
                    res = wavepoly.fit(pts, 1.0)
                    closed = [c.closed for c in res.contours]
                    bad = bool(truth.independent_problems(res))
                    invalid += bad
                    joined += closed == [True]
                    right += (closed == [True, True] and sorted(res.parents) == [-1, 0]
                              and not bad and len(res.outliers) == 0)
            total = len(SMALL_HOLE_SIZES) * SMALL_HOLE_SEEDS
            rows.append([f"{gap:g} ε", f"{noise:g} ε", f"{right}/{total}", joined, invalid,
                         time.perf_counter() - t0])
    return ("### Small holes\n\nA disk 24 ε across with a round hole 4 or 6 ε across whose "
            "wall comes *gap* ε from the disk's, moved round it (`benchmarks/holes.py`), "
            "sampled every ε / 3 at random with Gaussian noise: where the disk's points leave a "
            "gap beside the hole (a random sampling does now and then), the hole reads like a "
            "notch closed off at its mouth, or a limb closed across its root. *right*: the "
            "outline and its hole, nested, valid, no outliers; *joined*: one closed outline, "
            "the hole drawn as a notch of it.\n\n"
            + table(["gap", "noise", "right", "joined", "invalid", "seconds"], rows))


def round_blob(rng: np.random.Generator, centre: np.ndarray, size: float) -> shapely.Polygon:
    """A star-shaped blob ``size`` in mean radius whose radius wanders with the angle (a
    Fourier series of orders 2-8, amplitudes falling as the order grows)."""
    t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    r = np.ones_like(t)
    for k in range(2, 9):
        r += rng.normal(0, 0.35 / k ** 1.2) * np.cos(k * t + rng.uniform(0, 2 * np.pi))
    r = np.clip(r, 0.15, None)
    return shapely.Polygon(np.column_stack([centre[0] + size * r * np.cos(t),
                                            centre[1] + size * r * np.sin(t)])).buffer(0)


def blob_scene(seed: int) -> list[np.ndarray]:
    """The rings of 1 to 3 round blobs in a 2 x 2 square, apart, 4 in 10 with a small blob
    cut out as a hole where it lies inside at least 0.03 units from the outline (often
    within a couple of tolerances of it)."""
    rng = np.random.default_rng(seed)
    shapes: list[shapely.Polygon] = []
    for _ in range(rng.integers(1, 4)):
        for _attempt in range(20):
            blob = round_blob(rng, rng.uniform(-1, 1, 2), rng.uniform(0.25, 0.6))
            if all(blob.distance(other) > 0.03 for other in shapes):
                break
        else:
            continue
        if rng.uniform() < 0.4:
            inner = round_blob(rng, np.asarray(blob.representative_point().coords[0]),
                               rng.uniform(0.05, 0.15))
            if blob.buffer(-0.03).contains(inner):
                blob = blob.difference(inner)
        if blob.geom_type == "Polygon":
            shapes.append(blob)
    return [np.asarray(r.coords)[:-1] for b in shapes for r in (b.exterior, *b.interiors)]


def blob_hole_sweep(truth, right_rings) -> str:
    """For each sampling, fits of `BLOB_SCENES` scenes of round blobs (`blob_scene`) sampled
    every ε / 3: *right* (as the silhouette sweep counts it: ``right_rings``), *by shape*
    (within 1.5 ε of the true outlines both ways) and *invalid*."""
    rows = []
    for div, noise in BLOB_SAMPLINGS:
        scenes = [blob_scene(seed) for seed in range(BLOB_SCENES)]
        rows.append([f"{3.0 / div:.3g}", f"{noise:g} ε",
                     *tally_fits(scenes, 3.0 / div, noise, truth, right_rings, 1.5, 1000)])
    return ("Round blobs (`benchmarks/holes.py`): 1 to 3 blobs 0.5-1.2 units across in a 2 x 2 "
            "square, their radius wandering with the angle, 4 in 10 with a small round hole "
            "0.1-0.3 units across that often comes within a couple of tolerances of its "
            "outline; sampled every ε / 3 at random with Gaussian noise. *right* and *by "
            "shape* as the unseen silhouettes count them.\n\n"
            + table(["ε", "noise", "right", "by shape", "invalid", "seconds"], rows))
