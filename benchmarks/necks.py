"""Lobes on narrow necks: one outline, not two rings (`wavepoly.ordering.necks`).

A made-up sweep, a disk with a round lobe joined to it by a neck narrower than a few
tolerances, and silhouettes that nobody here drew: the largest regions of scikit-image's
photographs thresholded, where a lobe often hangs on a neck a pixel or two wide.
"""

from __future__ import annotations

import time

import numpy as np
import shapely
from shapely import affinity

import wavepoly
from wavepoly.samples import sample_rings

from .common import table
from .holes import one_outline
from .silhouettes import sample, traced_mask

#: The made-up sweep: the body's radius, the lobes' radii, the necks' widths and lengths (all
#: in ε), the noise (in ε) and seeds of each (each seed turns the shape and samples it anew).
NECK_BODY = 30.0
NECK_LOBES = (3.0, 6.0)
NECK_WIDTHS = (0.5, 0.8, 1.2, 2.0)
NECK_LENGTHS = (1.0, 3.0, 6.0)
NECK_NOISE = (0.0, 0.125, 0.25)
NECK_SEEDS = 3
#: Photographs (scikit-image's, none needing a download) thresholded at Otsu's level, each
#: side, opened by a disk of `OPENING` pixels (no one-pixel spurs), the `PHOTO_REGIONS`
#: largest regions of at least `MIN_PIXELS` pixels of each, holes filled: one outline each.
PHOTOS = ("astronaut", "chelsea", "coffee", "rocket", "logo", "cell", "moon", "retina",
          "clock", "immunohistochemistry", "microaneurysms", "brick", "grass", "gravel",
          "camera", "coins", "horse")
OPENING = 2
PHOTO_REGIONS = 2
MIN_PIXELS = 2000
#: Their samplings: (diagonal of the region / ε, noise in ε), sampled every ε / 3.
PHOTO_SAMPLINGS = ((150, 0.125), (100, 0.25), (300, 0.0))


def lobe_on_a_neck(width: float, length: float, lobe: float, turn: float = 0.0
                   ) -> list[np.ndarray]:
    """A disk `NECK_BODY` ε in radius with a round lobe joined to it by a neck ``width`` ε
    wide and ``length`` ε long, turned by ``turn`` degrees: its outline."""
    body = shapely.Point(0, 0).buffer(NECK_BODY, 128)
    head = shapely.Point(NECK_BODY + length + lobe, 0).buffer(lobe, 64)
    neck = shapely.box(NECK_BODY - 1, -width / 2, NECK_BODY + length + 1, width / 2)
    shape = affinity.rotate(shapely.union_all([body, head, neck]), turn, origin=(0, 0))
    return [np.asarray(shape.exterior.coords)[:-1]]


def neck_sweep(truth) -> str:
    """For each neck, fits of both lobes and `NECK_SEEDS` turns at each noise: right (one
    closed outline, valid, no outliers), with the results split into rings and the invalid
    ones (``truth.independent_problems``)."""
    rows = []
    for width in NECK_WIDTHS:
        for length in NECK_LENGTHS:
            cells, split, invalid = [], 0, 0
            t0 = time.perf_counter()
            for noise in NECK_NOISE:
                right = 0
                for lobe in NECK_LOBES:
                    for seed in range(NECK_SEEDS):
                        rings = lobe_on_a_neck(width, length, lobe, 47.0 * seed)
                        pts = sample_rings(rings, spacing=1 / 3, noise=noise, seed=seed)
                        one, apart, bad = one_outline(wavepoly.fit(pts, 1.0), truth)
                        right, split, invalid = right + one, split + apart, invalid + bad
                cells.append(f"{right}/{len(NECK_LOBES) * NECK_SEEDS}")
            rows.append([f"{width:g} ε", f"{length:g} ε", *cells, split, invalid,
                         time.perf_counter() - t0])
    return ("### Lobes on necks\n\nA disk 60 ε across with a round lobe 6 or 12 ε across "
            "joined to it by a neck *width* ε wide and *length* ε long (`benchmarks/necks.py`), "
            "turned at random, sampled every ε / 3 with Gaussian noise: one outline, pinched "
            "at the neck. The march may close the lobe on itself across the neck and run the "
            "body's outline past its mouth. *right* (of 6 at each noise): one closed outline, "
            "valid, no outliers; *split*: results of more than one contour.\n\n"
            + table(["width", "length", *(f"right, noise {n:g} ε" for n in NECK_NOISE),
                     "split", "invalid", "seconds"], rows))


def photo_regions() -> list[tuple[str, list[np.ndarray]]]:
    """The photographs' regions (`PHOTOS`), each named and as its one traced outline."""
    from scipy import ndimage
    from skimage import color, data, filters, morphology

    out = []
    for name in PHOTOS:
        image = getattr(data, name)()
        if image.ndim == 3:
            image = color.rgb2gray(image[..., :3])
        dark = image < filters.threshold_otsu(image)
        for side, mask in (("dark", dark), ("light", ~dark)):
            mask = morphology.opening(mask, morphology.disk(OPENING))
            labels, _ = ndimage.label(mask)
            sizes = np.bincount(labels.ravel())[1:]
            for k in np.argsort(-sizes)[:PHOTO_REGIONS]:
                if sizes[k] < MIN_PIXELS:
                    continue
                rings = traced_mask(ndimage.binary_fill_holes(labels == k + 1))
                if len(rings) == 1:  # regions a bitmap joins only at a pixel's corner left out
                    out.append((f"{name} {side} {k}", rings))
    return out


def photo_silhouette_sweep(truth) -> str:
    """For each sampling, fits of every region of `photo_regions`: right (one closed
    outline, valid, no outliers), split into rings, and invalid
    (``truth.independent_problems``)."""
    try:
        regions = photo_regions()
    except ImportError:
        return ("### Silhouettes from photographs\n\nSkipped: scikit-image is not installed "
                "(`make bench` installs it).")
    rows = []
    for div, noise in PHOTO_SAMPLINGS:
        right = split = invalid = 0
        missed = []
        t0 = time.perf_counter()
        for name, rings in regions:
            eps = float(np.hypot(*np.ptp(rings[0], axis=0))) / div
            length = shapely.LinearRing(rings[0]).length
            res = wavepoly.fit(sample(rings, int(3 * length / eps), noise * eps, 7), eps)
            ok, apart, bad = one_outline(res, truth)
            right, split, invalid = right + ok, split + apart, invalid + bad
            if not ok:
                missed.append(name)
        rows.append([f"diagonal / {div}", f"{noise:g} ε", f"{right}/{len(regions)}", split,
                     invalid, ", ".join(missed), time.perf_counter() - t0])
    return ("### Silhouettes from photographs\n\nThe largest regions of scikit-image's "
            "photographs, thresholded at Otsu's level, opened by a disk of 2 pixels, holes "
            "filled (`benchmarks/necks.py`): one outline each, often with a lobe on a neck a "
            "pixel or two wide; ε a share of the region's diagonal, sampled every ε / 3 with "
            "Gaussian noise. *right*: one closed outline, valid, no outliers; *split*: "
            "results of more than one contour.\n\n"
            + table(["ε", "noise", "right", "split", "invalid", "missed", "seconds"], rows))
