"""Made-up silhouettes for the validity sweep: an elliptic body with limbs of any width (down
to a fifth of the tolerance), a head, thin wedge slits cut into it and now and then a hole,
the kind of outline whose walls run closer than the tolerance (`wavepoly.ordering.stems`)."""

from __future__ import annotations

import time

import numpy as np
import shapely
from shapely import affinity

import wavepoly


def silhouette(seed: int) -> list[np.ndarray]:
    """The rings (outer first, then holes) of silhouette ``seed``, about 1 unit across."""
    rng = np.random.default_rng(seed)
    parts = [affinity.scale(shapely.Point(0, 0).buffer(1.0, 64), rng.uniform(1.0, 2.0),
                            rng.uniform(0.5, 1.0))]
    for _ in range(rng.integers(0, 7)):  # limbs: bent strokes
        a = rng.uniform(0, 2 * np.pi)
        d, start = np.array([np.cos(a), np.sin(a)]), np.array([np.cos(a) * 1.2, np.sin(a) * 0.6])
        n, length, bend = np.array([-d[1], d[0]]), rng.uniform(0.5, 2.0), rng.uniform(-0.8, 0.8)
        line = shapely.LineString([start, start + d * length / 2 + n * bend * 0.3,
                                   start + d * length + n * bend * 0.6])
        parts.append(line.buffer(rng.uniform(0.04, 0.25), 16,
                                 cap_style="flat" if seed % 4 == 1 else "round"))
    if rng.uniform() < 0.7:  # a head
        parts.append(shapely.Point(rng.uniform(-2.2, 2.2), rng.uniform(0.4, 1.0)).buffer(
            rng.uniform(0.3, 0.6), 32))
    shape = shapely.unary_union(parts)
    if rng.uniform() < 0.5:  # slits: thin wedges cut in
        for _ in range(rng.integers(1, 4)):
            a = rng.uniform(0, 2 * np.pi)
            d = np.array([np.cos(a), np.sin(a)])
            n = np.array([-d[1], d[0]]) * rng.uniform(0.02, 0.15)
            shape = shape.difference(shapely.Polygon([d * rng.uniform(0.2, 0.7), 3 * d + n,
                                                      3 * d - n]))
    if seed % 4 == 3 and rng.uniform() < 0.6:  # a hole
        shape = shape.difference(shapely.Point(rng.uniform(-0.5, 0.5), rng.uniform(-0.2, 0.2))
                                 .buffer(rng.uniform(0.1, 0.3), 32))
    if shape.geom_type == "MultiPolygon":
        shape = max(shape.geoms, key=lambda g: g.area)
    scale = 1.0 / np.hypot(*np.ptp(np.asarray(shape.exterior.coords), axis=0))
    shape = affinity.scale(shape, scale, scale, origin=(0, 0))
    return [np.asarray(r.coords)[:-1] for r in (shape.exterior, *shape.interiors)]


def sample(rings: list[np.ndarray], n: int, sigma: float, seed: int) -> np.ndarray:
    """About ``n`` points spread uniformly along the rings, with Gaussian noise ``sigma``."""
    rng = np.random.default_rng(seed)
    closed = [np.vstack([r, r[:1]]) for r in rings]
    arcs = [np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(v, axis=0), axis=1))])
            for v in closed]
    total = sum(a[-1] for a in arcs)
    out = []
    for v, arc in zip(closed, arcs):
        s = rng.uniform(0, arc[-1], max(8, round(n * arc[-1] / total)))
        out.append(np.column_stack([np.interp(s, arc, v[:, 0]), np.interp(s, arc, v[:, 1])]))
    pts = np.concatenate(out)
    return pts + rng.normal(0.0, sigma, pts.shape) if sigma > 0 else pts


def thinned(rings: list[np.ndarray], n: int, sigma: float, floor: float, seed: int
            ) -> np.ndarray:
    """The rings sampled as `sample` does (``n`` points at full density), then thinned
    linearly across x from every point kept to a share ``floor`` of them: a scan whose
    density varies across the part (a turntable's far side)."""
    pts = sample(rings, int(n / ((1 + floor) / 2)), sigma, 1000 + seed)
    t = (pts[:, 0] - pts[:, 0].min()) / np.ptp(pts[:, 0])
    keep = np.random.default_rng(seed).uniform(size=len(pts)) < 1 - (1 - floor) * t
    return pts[keep]


def bitmap(rings: list[np.ndarray], pixels: int) -> list[np.ndarray]:
    """The rings as a bitmap's traced outline, ``pixels`` across the diagonal: staircase walls,
    spurs and notches one pixel wide, as a silhouette image's contour gives them (rings that
    enclose fewer than `BITMAP_MIN_AREA` pixels are left out)."""
    import contourpy

    shape = shapely.Polygon(rings[0], rings[1:])
    lo, hi = np.min(rings[0], axis=0), np.max(rings[0], axis=0)
    step = np.hypot(*(hi - lo)) / pixels
    x = np.arange(lo[0] - 2 * step, hi[0] + 2 * step, step)
    y = np.arange(lo[1] - 2 * step, hi[1] + 2 * step, step)
    gx, gy = np.meshgrid(x, y)
    image = shapely.contains_xy(shape, gx, gy).astype(float)
    lines = contourpy.contour_generator(x, y, image).lines(0.5)
    traced = [line[:-1] for line in lines
              if abs(shapely.Polygon(line).area) >= BITMAP_MIN_AREA * step ** 2]
    return sorted(traced, key=lambda r: -abs(shapely.Polygon(r).area))


#: Traced rings smaller than this many pixels are specks of the rasterizing, not outlines.
BITMAP_MIN_AREA = 20


def blobs(seed: int, size_fraction: float, pixels: int = 256, volume: float = 0.3
          ) -> list[np.ndarray]:
    """The traced outlines of random blobs in a ``pixels`` square image, as scikit-image's
    ``binary_blobs`` makes them (random seeds blurred by a Gaussian a quarter of the blob
    size wide, the densest ``volume`` share of the image kept): rounded shapes a few pixels
    to a third of the image across, touching one another now and then at a pixel's corner.
    Unlike `silhouette`, nobody designed them; in pixel units, outermost first."""
    from scipy.ndimage import gaussian_filter

    rng = np.random.default_rng(seed)
    n_seeds = max(int(1.0 / size_fraction) ** 2, 1)
    mask = np.zeros((pixels, pixels))
    mask[tuple((pixels * rng.random((2, n_seeds))).astype(int))] = 1.0
    mask = gaussian_filter(mask, sigma=0.25 * pixels * size_fraction)
    return traced_mask(mask >= np.percentile(mask, 100 * (1 - volume)))


def traced_mask(mask: np.ndarray) -> list[np.ndarray]:
    """The outlines of a boolean image's True regions, traced at half a pixel's height
    (rings enclosing fewer than `BITMAP_MIN_AREA` pixels left out), in pixel units (x the
    column, y the row, from the padded corner), outermost first."""
    import contourpy

    image = np.pad(np.asarray(mask, dtype=float), 2)
    lines = contourpy.contour_generator(z=image).lines(0.5)
    traced = [line[:-1] for line in lines if abs(shapely.Polygon(line).area) >= BITMAP_MIN_AREA]
    return sorted(traced, key=lambda r: -abs(shapely.Polygon(r).area))


def star(spikes: int, spike_width: float, spike_length: float = 1.5) -> np.ndarray:
    """Outline of a unit disk with ``spikes`` wedges out of it, each ``spike_width`` wide
    where it leaves the disk and ``spike_length`` long: parts thinner than a coarse tolerance
    over most of their length."""
    body = shapely.Point(0, 0).buffer(1.0, quad_segs=32)
    wedges = []
    for angle in np.linspace(0, 2 * np.pi, spikes, endpoint=False):
        along = np.array([np.cos(angle), np.sin(angle)])
        across = np.array([-along[1], along[0]])
        base = 0.9 * along
        wedges.append(shapely.Polygon([base - spike_width / 2 * across,
                                       base + (0.1 + spike_length) * along,
                                       base + spike_width / 2 * across]))
    return np.asarray(shapely.union_all([body, *wedges]).exterior.coords)[:-1]


#: Shape distances are measured along the lines, both cut into pieces of at most this share
#: of the tolerance: a vertex-only distance misses an edge that cuts across empty space.
SHAPE_STEP = 0.1


def shape_distance(rings: list[np.ndarray], contours, eps: float) -> float:
    """Hausdorff distance between the true ``rings`` and the drawn ``contours`` (closed ones
    as rings, open ones as lines), both cut into pieces of at most `SHAPE_STEP` x ``eps``: the
    farthest of their vertices from the other's nearest, through k-d trees (within half a
    step of the distance between the lines)."""
    from scipy.spatial import cKDTree

    drawn = shapely.MultiLineString([np.vstack([c.vertices, c.vertices[:1]]) if c.closed
                                     else c.vertices for c in contours])
    true = shapely.MultiLineString([np.vstack([r, r[:1]]) for r in rings])
    a, b = (shapely.get_coordinates(shapely.segmentize(g, SHAPE_STEP * eps))
            for g in (true, drawn))
    if not len(a) or not len(b):
        return float("inf")
    return float(max(cKDTree(b).query(a)[0].max(), cKDTree(a).query(b)[0].max()))


#: A ring must come out as a closed contour of its own when it is at least this many ε across
#: (its bounding box's diagonal): the issue's "a loop of at least 4 ε extent is a contour". A
#: smaller one (a sliver of a hole that a slit cut, 1-2 ε across) may merge into its neighbour,
#: its points still within ε and no outliers.
MIN_RING_EXTENT = 4.0
#: A contour draws a ring where at least `DRAWS_SHARE` of its length runs within `DRAWS_NEAR` ε
#: of it: a contour round two blobs draws both, each of two contours round one ring draws it.
DRAWS_NEAR = 1.5
DRAWS_SHARE = 0.25


def drawn_rings(rings: list[np.ndarray], contours, eps: float) -> np.ndarray:
    """Which of the rings at least `MIN_RING_EXTENT` ε across each contour draws: a (contours,
    rings) boolean matrix."""
    required = [r for r in rings if np.hypot(*np.ptp(r, axis=0)) >= MIN_RING_EXTENT * eps]
    zones = shapely.buffer([shapely.LinearRing(r) for r in required], DRAWS_NEAR * eps)
    draws = np.zeros((len(contours), len(required)), dtype=bool)
    for k, c in enumerate(contours):
        line = (shapely.linearrings(c.vertices) if c.closed and len(c.vertices) >= 3
                else shapely.linestrings(c.vertices))
        draws[k] = shapely.length(shapely.intersection(line, zones)) >= DRAWS_SHARE * line.length
    return draws


def judged(rings: list[np.ndarray], result, eps: float, truth, right_rings,
           hausdorff: float) -> tuple[bool, bool, bool]:
    """Whether a fit of the ``rings``' sample is invalid (``truth.independent_problems``),
    right by rings (closed, valid, no outliers and ``right_rings``) and right by shape
    (closed, valid, no outliers and within ``hausdorff`` ε of the rings, `shape_distance`)."""
    problems = truth.independent_problems(result)
    clean = (not problems and len(result.outliers) == 0
             and all(c.closed for c in result.contours))
    return (bool(problems), bool(clean and right_rings(rings, result.contours, eps)),
            bool(clean and shape_distance(rings, result.contours, eps) <= hausdorff * eps))


def tally_fits(cases: list[list[np.ndarray]], eps: float, noise: float, truth, right_rings,
               hausdorff: float, first_seed: int) -> list[object]:
    """Each case's rings sampled every ε / 3 with noise ``noise`` ε (seed ``first_seed`` plus
    its index) and fitted at ``eps``, as a table's cells: right by rings and by shape (of
    all), invalid (`judged`), and the seconds it all took."""
    by_rings = by_shape = invalid = 0
    t0 = time.perf_counter()
    for k, rings in enumerate(cases):
        length = sum(shapely.LinearRing(r).length for r in rings)
        pts = sample(rings, int(3 * length / eps), noise * eps, first_seed + k)
        bad, ringed, shaped = judged(rings, wavepoly.fit(pts, eps), eps, truth, right_rings,
                                     hausdorff)
        invalid, by_rings, by_shape = invalid + bad, by_rings + ringed, by_shape + shaped
    return [f"{by_rings}/{len(cases)}", f"{by_shape}/{len(cases)}", invalid,
            time.perf_counter() - t0]
