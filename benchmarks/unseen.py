"""Silhouettes that nobody in the project made: scikit-image's horse, its random shapes and
two of its photographs thresholded.

The made-up silhouettes (`benchmarks.silhouettes`) were drawn to hold the hard cases, and the
ordering was tuned on them; these were not. `skimage.data.horse` is a traced photograph's
silhouette (ears a slit apart, a thin tail, hooves); `skimage.draw.random_shapes` draws
rectangles, triangles, circles and ellipses that overlap and touch (sharp corners, necks,
shapes a few tolerances across). Both are traced at half a pixel's height and sampled every
ε / 3 along the outline with Gaussian noise; ε is a share of the image's diagonal (the
horse's 517 pixels: ε 5.2, 3.4 and 2.6 px; the shapes' 362: ε 2.4 to 7.2 px).
"""

from __future__ import annotations

import time

import numpy as np
import shapely

import wavepoly

from .common import table
from .silhouettes import drawn_rings, sample, shape_distance, tally_fits, traced_mask

#: The horse's samplings: ε as a share of the image's diagonal, noise in ε, seeds of each.
HORSE_DIVISIONS = (100, 150, 200)
HORSE_NOISE = (0.0, 0.125, 0.25)
HORSE_SEEDS = 3
#: Random shapes in a 256-pixel image: (diagonal / ε, noise in ε), each over `SHAPE_SEEDS`
#: images of 2 to 6 shapes 30 to 120 pixels across.
SHAPE_SAMPLINGS = ((150, 0.125), (100, 0.25), (75, 0.0), (50, 0.25))
SHAPE_SEEDS = 30
SHAPE_PIXELS = 256
#: *by shape*: within this many ε of the true outlines both ways, measured along the lines (as
#: the blob sweep's shapes): forgives two shapes drawn as one outline where they touch or come
#: within an ε (a gap or an overlap narrower than the tolerance is no shape the points tell),
#: not a line across empty space.
SHAPE_HAUSDORFF = 1.5
#: Photographs thresholded at Otsu's level, specks of at most `SPECK_PIXELS` pixels removed,
#: each by the side that is its subject (True: the dark side): the coins (24 coins, an
#: interior hole or two, a strip of background along the border), the cameraman's dark parts
#: (a coat, a camera, a tripod of legs one to three pixels thin), and two photographs of
#: printed text (letters' strokes a few pixels thick, thinner than the coarser tolerance),
#: and the Hubble deep field's bright galaxies and stars (59 specks and blobs 1-10 tolerances
#: across at the finer tolerance, most under 2 at the coarser one, a few tolerances apart).
PHOTOS = {"coins": False, "camera": True, "text": True, "page": True,
          "hubble_deep_field": False}
SPECK_PIXELS = 64
#: Their samplings: (diagonal / ε, noise in ε), or None: the tracer's own points (one where
#: the outline crosses each pixel edge, on a staircase), as a user who traces a mask has them.
PHOTO_SAMPLINGS = ((300, 0.0), (300, 0.25), (150, 0.125), (300, None), (150, None))


def unseen_sweep(truth, right_rings) -> str:
    """The sweep's table: for each source and sampling, results right (as the silhouette sweep
    counts them: ``right_rings``) and invalid (``truth.independent_problems``)."""
    try:
        from skimage import data
        from skimage.draw import random_shapes
    except ImportError:
        return ("### Unseen silhouettes\n\nSkipped: scikit-image is not installed (`make "
                "bench` installs it).")
    rows = []
    image = ~data.horse()
    horse, diagonal = traced_mask(image), float(np.hypot(*image.shape))
    for div in HORSE_DIVISIONS:
        for noise in HORSE_NOISE:
            rows.append(_row("horse", [horse] * HORSE_SEEDS, diagonal / div, noise, truth,
                             right_rings))
    for div, noise in SHAPE_SAMPLINGS:
        images = [random_shapes((SHAPE_PIXELS, SHAPE_PIXELS), max_shapes=6, min_shapes=2,
                                min_size=30, max_size=120, channel_axis=None, rng=seed,
                                allow_overlap=True)[0] < 255 for seed in range(SHAPE_SEEDS)]
        rows.append(_row("random shapes", [traced_mask(m) for m in images],
                         np.hypot(SHAPE_PIXELS, SHAPE_PIXELS) / div, noise, truth, right_rings))
    photo_rows = [_photo_row(name, div, noise, truth) for name in PHOTOS
                  for div, noise in PHOTO_SAMPLINGS]
    return ("### Unseen silhouettes\n\n" + __doc__.split("\n\n", 1)[1].strip().replace("\n", " ")
            + " *right*: as the silhouette sweep counts it (every contour closed, one per ring "
            "at least 4 ε across, valid, no outliers); *by shape*: closed, valid, no outliers "
            f"and within {SHAPE_HAUSDORFF:g} ε of the true outlines both ways, measured along "
            "the lines, which forgives two shapes drawn as one outline, or one as two, where "
            "they touch or overlap by less than an ε (the points cannot tell those apart).\n\n"
            + table(["source", "ε", "noise", "right", "by shape", "invalid", "seconds"], rows)
            + "\n\nThe photographs (`PHOTOS`), sampled the same way, and as *traced*: the "
            "tracer's own points (one where the outline crosses a pixel edge, a staircase "
            "spaced 0.5-1 pixel), as a user who traces a mask has them. *rings*: the true "
            "rings at least 4 ε across; *drawn alone*: those drawn by one closed contour that "
            "draws no other (a contour draws a ring where a quarter of its length runs within "
            "1.5 ε of it); *shape*: the Hausdorff distance between the true and the drawn "
            "lines.\n\n"
            + table(["photo", "ε", "noise", "rings", "drawn alone", "closed/open", "outliers",
                     "invalid", "shape", "seconds"], photo_rows))


def _row(name: str, cases: list[list[np.ndarray]], eps: float, noise: float, truth,
         right_rings) -> list[object]:
    """One row of the table: each case's rings sampled (seed 1000 + its index) and fitted."""
    return [name, f"{eps:.3g} px", f"{noise:g} ε",
            *tally_fits(cases, eps, noise, truth, right_rings, SHAPE_HAUSDORFF, 1000)]


def _photo_row(name: str, div: float, noise: float | None, truth) -> list[object]:
    """One photograph (`PHOTOS`) thresholded, traced, sampled (``noise`` None: the traced
    points themselves) and fitted at ε = its diagonal / ``div``: its rings, those drawn alone,
    what the fit gives, and the distance to the truth."""
    from skimage import color, data, filters, morphology

    image = getattr(data, name)()
    if image.ndim == 3:
        image = color.rgb2gray(image)
    dark = image < filters.threshold_otsu(image)
    mask = morphology.remove_small_objects(dark if PHOTOS[name] else ~dark,
                                           max_size=SPECK_PIXELS)
    rings, eps = traced_mask(mask), float(np.hypot(*mask.shape)) / div
    length = sum(shapely.LinearRing(r).length for r in rings)
    pts = (np.vstack(rings) if noise is None
           else sample(rings, int(3 * length / eps), noise * eps, 7))
    t0 = time.perf_counter()
    res = wavepoly.fit(pts, eps)
    seconds = time.perf_counter() - t0
    closed = np.array([c.closed for c in res.contours], dtype=bool)
    draws = drawn_rings(rings, res.contours, eps)
    return [name, f"{eps:.3g} px", "traced" if noise is None else f"{noise:g} ε", draws.shape[1],
            drawn_alone(draws, closed), f"{closed.sum()}/{(~closed).sum()}",
            len(res.outliers), len(truth.independent_problems(res)),
            f"{shape_distance(rings, res.contours, eps) / eps:.2f} ε", seconds]


def drawn_alone(draws: np.ndarray, closed: np.ndarray) -> int:
    """How many rings are drawn by exactly one closed contour that draws no other ring
    (``draws``: `benchmarks.silhouettes.drawn_rings`; ``closed``: each contour's)."""
    alone = draws & closed[:, None] & (draws.sum(axis=1, keepdims=True) == 1)
    return int((alone.sum(axis=0) == 1).sum())
