"""One slice end to end: ordering (§2) -> decomposition (§3) -> reconstruction (§4) -> verified.

>>> from wavepoly.samples import glyph_outlines, sample_rings
>>> pts = sample_rings(glyph_outlines("O").rings, spacing=0.02, noise=0.01, seed=3)
>>> result = fit(pts, tolerance=0.08)
>>> len(result.contours), result.max_error <= 0.08
(2, True)
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import replace

import numpy as np
import shapely

from .errors import ParameterError
from .geometry import (
    nest_contours,
    orient_by_depth,
    polyline_distance,
    segments_distance,
)
from .junctions import meet_at_junctions
from .levels import decompose_contour
from .ordering import SPACINGS_PER_RADIUS, order_points
from .ordering.islands import ISLAND_EXTENT
from .ordering.neighbourhoods import group_extents, point_clusters
from .ordering.noise import BELL_MARGIN, NOISE_MARGIN, NOISE_NOTE, below_the_bell
from .pieces import join_at_ends, noded_contours, split_crossings
from .reconstruction import reconstruct_contour
from .stubs import STUB_LENGTH, redundant_stubs
from .types import (
    DEFAULT_RELATIVE_TOLERANCE,
    SLACK,
    Contour,
    ContourReport,
    FitResult,
    FloatArray,
    IntArray,
    OrderedContour,
    Ordering,
    Pyramid,
    Reconstruction,
    within,
)
from .validate import check_relative_tolerance, check_tolerance, column_bounds, validate_points
from .validity import check_contours, contour_segments, obstacle_tree, without_repeats

STAGES = ("ordering", "decomposition", "reconstruction", "verification")
#: Points farther from the origin than this many times their extent are fitted about their own
#: centre: a UTM northing (5e6 m) or the same in mm leaves a tolerance of a few mm only some
#: thousand float steps there, and silhouettes 5e9 from the origin came out open (2 of 30).
FAR_FROM_ORIGIN = 1e3
#: A halo about a thin core leaves its fainter part beyond the tolerance from the core (the
#: Intel map at 0.05: 7.8 % of the points); where running through the middle would leave more
#: than this share out, no core holds the points, the spread over a neighbourhood is the
#: curves' own shape (fish.txt's fins at 0.71: 25 %), and the curves follow it.
HALO_SHARE = 0.15
#: A tolerance below the point spacing along the curves makes nearly every point a vertex:
#: the fit says so and suggests this many spacings (as ``wavepoly info`` does).
SPACING_MARGIN = 2.0


def fit(points: FloatArray, tolerance: float, *,
        relative_tolerance: float | None = DEFAULT_RELATIVE_TOLERANCE,
        radius: float | None = None, seed: int = 0,
        progress: Callable[[int, int], None] | None = None) -> FitResult:
    """Concise polygons within ``tolerance`` of unorganized planar points.

    Parameters
    ----------
    points : (N, 2) unorganized points of one slice (any number of contours, closed or open).
    tolerance : shape tolerance, in the points' units: every input point that is not an outlier
        ends within this distance of the output.
    relative_tolerance : threshold of the relative shape error (eq. 7) that stops the
        decomposition, or None to try a few starting levels (`auto_start_levels`) and keep the
        fewest vertices.
    radius : neighbourhood radius of the ordering stage (default: ``tolerance``; read at half
        of it, with a note, where it spans parts thinner than it, `order_points`).
    seed : seed of the ordering's random choices.
    progress : called as ``progress(done, total)`` after each contour.

    Returns
    -------
    `FitResult`; closed contours are counter-clockwise, their holes clockwise.

    Notes
    -----
    Points farther from the origin than `FAR_FROM_ORIGIN` x their extent (GIS coordinates)
    are fitted about their own centre, and the contours shifted back.
    """
    pts = validate_points(points, source="points", min_points=3)
    if pts.shape[1] != 2:
        raise ParameterError("fit takes (N, 2) planar points; slice 3D clouds with slice_cloud")
    origin = _local_origin(pts)
    if origin is not None:  # fitted about their own centre, the result shifted back
        result = fit(pts - origin, tolerance, relative_tolerance=relative_tolerance,
                     radius=radius, seed=seed, progress=progress)
        return _shifted(result, origin)
    tolerance = check_tolerance(tolerance)
    relative_tolerance = check_relative_tolerance(relative_tolerance)
    radius = tolerance if radius is None else check_tolerance(radius, "radius")
    whole = _one_segment(pts, tolerance)
    if whole is not None:
        return whole
    timings = dict.fromkeys(STAGES, 0.0)
    t0 = time.perf_counter()
    ordering = order_points(pts, radius, seed=seed, tolerance=tolerance)
    beyond = np.empty(0, dtype=np.intp)
    if ordering.through_the_middle:
        middle, beyond = beyond_the_tolerance(pts, ordering, tolerance)
        if _halo_only(tolerance, ordering) and len(beyond) > HALO_SHARE * len(pts):
            # no thin core holds the points: the spread is the curves' own shape
            ordering = order_points(pts, radius, seed=seed)
            beyond = np.empty(0, dtype=np.intp)
        else:
            ordering = middle
    timings["ordering"] = time.perf_counter() - t0
    n = len(ordering.contours)
    contours: list[Contour | None] = [None] * n
    reports: list[ContourReport | None] = [None] * n
    near = _neighbours(pts, ordering.contours, tolerance)
    # the longest first: each later contour keeps clear of the ones already fixed near it,
    # and of the ordered rings of the closed ones still to come, so that those keep their
    # ordered points as a valid path (where two rings nearly touch, the first would otherwise
    # cut its corner across the second's points)
    for done, k in enumerate(np.argsort([-len(oc.members) for oc in ordering.contours],
                                        kind="stable")):
        fixed = [contours[j] if contours[j] is not None else _ordered_ring(ordering.contours[j])
                 for j in near[k] if contours[j] is not None or ordering.contours[j].closed]
        contours[k], reports[k], times = fit_contour(pts, ordering.contours[k], tolerance,
                                                     relative_tolerance, obstacle_tree(fixed),
                                                     clean=ordering.clean)
        for stage, seconds in times.items():
            timings[stage] += seconds
        if progress:
            progress(done + 1, n)
    t0 = time.perf_counter()
    validity = check_contours(contours)
    if not validity.valid:  # the fallback: junctions where polygons still cross
        contours, reports = split_crossings(contours, reports)
        validity = check_contours(contours)
    if not validity.valid:  # folds and overlaps, which meet along a stretch, not at a point
        contours, reports = noded_contours(contours, reports, validity)
        validity = check_contours(contours)
    n_before = len(contours)
    contours, reports, stub_error = _without_stubs(pts, ordering.outliers, contours, reports,
                                                   tolerance)
    n_stubs = n_before - len(contours)
    contours, grown = meet_at_junctions(contours, tolerance)
    for k in grown:
        reports[k] = replace(reports[k], final_vertices=len(contours[k].vertices))
    n_pieces = len(contours)
    contours, reports = join_at_ends(contours, reports)
    if n_stubs or grown or len(contours) < n_pieces:  # the counts, or the junctions, change
        validity = check_contours(contours)
    outliers, lost, covered_error = _outliers_left(pts, ordering.outliers, contours, tolerance)
    parents = nest_contours(contours)
    contours = orient_by_depth(contours, parents)
    errors = np.concatenate([[c.max_error] for c in contours] + [[stub_error, covered_error]])
    counted = [k == (r.first_piece if r.first_piece is not None else k)
               for k, r in enumerate(reports)]  # the pieces of a split contour share its points
    n_members = sum(r.input_points for r, once in zip(reports, counted) if once)
    mean = (sum(c.mean_error * r.input_points for c, r, once in zip(contours, reports, counted)
                if once) / n_members if n_members else 0.0)
    timings["verification"] += time.perf_counter() - t0
    notes = list(ordering.notes) + _lost_notes(pts, lost)
    if n_stubs:
        notes.append(f"{n_stubs} open stub(s) shorter than {STUB_LENGTH:g} x "
                     "the tolerance left out: other contours hold their points within it")
    if not contours:
        notes.append("no contour found: every point is an outlier at this radius")
    suggested, tolerance_notes = _tolerance_notes(tolerance, ordering, len(beyond))
    notes += tolerance_notes + _speck_notes(pts, outliers, ordering, tolerance)
    return FitResult(contours, tolerance, float(errors.max()), float(mean), outliers,
                     len(pts), parents, reports, timings, tuple(notes), validity=validity,
                     suggested_tolerance=suggested)


def _local_origin(pts: FloatArray) -> FloatArray | None:
    """The centre of the points' box where they lie farther from the origin than
    `FAR_FROM_ORIGIN` x their extent, else None."""
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    extent = float((hi - lo).max())
    if float(np.abs(pts).max()) <= FAR_FROM_ORIGIN * extent:
        return None
    return (lo + hi) / 2


def _shifted(result: FitResult, origin: FloatArray) -> FitResult:
    """The result with its contours and the places of its problems moved by ``origin``."""
    contours = [replace(c, vertices=c.vertices + origin) for c in result.contours]
    validity = result.validity
    if validity is not None and validity.problems:
        validity = replace(validity, problems=tuple(
            replace(p, where=(p.where[0] + origin[0], p.where[1] + origin[1]))
            for p in validity.problems))
    return replace(result, contours=contours, validity=validity)


def _halo_only(tolerance: float, ordering: Ordering) -> bool:
    """Whether the curves run through the middle only because of a halo about a thin core:
    the tolerance is not below the points' own scatter nor a bell of noise
    (`wavepoly.ordering.noise.runs_through_the_middle`)."""
    return not (tolerance < NOISE_NOTE * ordering.scatter
                or below_the_bell(tolerance, ordering.noise, ordering.scatter))


def _tolerance_notes(tolerance: float, ordering: Ordering, beyond: int
                     ) -> tuple[float | None, list[str]]:
    """A suggested tolerance, and why, when this one is below the scan's scatter or the
    spread of a halo about it (`wavepoly.ordering.noise.runs_through_the_middle`), or below
    its point spacing. A spread over a neighbourhood that is the curves' own turns (a crab's
    legs) draws no note: the curves follow those turns."""
    # suggested from the spread over a neighbourhood, the larger figure: over wider windows a
    # band with flat sides (fish.txt) measures wider, and the smaller figure, once tried,
    # would draw a new suggestion
    spread = max(ordering.noise, ordering.scatter)
    suggested = _two_digits_up(NOISE_MARGIN * spread)
    bell = below_the_bell(tolerance, ordering.noise, ordering.scatter)
    if not _halo_only(tolerance, ordering):
        factor, scale = (NOISE_NOTE, ordering.scatter) if not bell else (BELL_MARGIN, spread)
        return suggested, [
            f"the tolerance {tolerance:.4g} is below {factor:g} x the scatter about the "
            f"curves ({scale:.3g}): the curves run through the middle of the noise, "
            f"and {beyond} noisy points farther than the tolerance from them are listed with "
            f"the outliers; a tolerance of {suggested:g} keeps nearly all of them"]
    if ordering.through_the_middle:  # a halo about a thin core
        return suggested, [
            f"the tolerance {tolerance:.4g} is below {NOISE_NOTE:g} x the spread of the points "
            f"about the curves over a neighbourhood ({spread:.3g}), a halo about a core of "
            f"scatter {ordering.scatter:.3g}: the curves run through the middle, and {beyond} "
            f"points of the halo farther than the tolerance from them are listed with the "
            f"outliers; a tolerance of {suggested:g} keeps nearly all of them"]
    spacing = ordering.radius / SPACINGS_PER_RADIUS  # the radius was widened to 3 spacings
    if tolerance < spacing:
        suggested = float(f"{SPACING_MARGIN * spacing:.2g}")
        return suggested, [
            f"the tolerance {tolerance:.4g} is below the point spacing along the curves "
            f"({spacing:.3g}): the polygons pass through nearly every point; a tolerance of "
            f"{suggested:g} simplifies them"]
    return None, []


def _two_digits_up(value: float) -> float:
    """``value`` rounded up to two significant digits: a suggestion above the tolerance it
    replaces, which is below ``value``.

    >>> _two_digits_up(0.07531)
    0.076
    """
    if value <= 0:
        return 0.0
    unit = 10.0 ** (np.floor(np.log10(value)) - 1)
    return float(f"{np.ceil(value / unit - 1e-9) * unit:.2g}")


def beyond_the_tolerance(points: FloatArray, ordering: Ordering, tolerance: float
                         ) -> tuple[Ordering, IntArray]:
    """``ordering`` without the members farther than ``tolerance`` from their ordered contour,
    and those members.

    Below the scatter, a polygon that kept every noisy point within the tolerance would
    zigzag from side to side of the band. The ordered points are neighbourhood centroids,
    the middle of the band: the polygon follows them, and the points that lie farther than the
    tolerance from that middle are noise beyond the tolerance, listed with the outliers (and
    a contour left with none of its points goes).
    """
    kept, beyond = [], [ordering.outliers]
    for oc in ordering.contours:
        far = polyline_distance(points[oc.members], oc.points, oc.closed) > tolerance
        beyond.append(oc.members[far])
        if not far.all():  # a contour none of whose points is left would be drawn from nothing
            kept.append(replace(oc, members=oc.members[~far]))
    outliers = np.sort(np.concatenate(beyond)).astype(np.intp)
    return (replace(ordering, contours=kept, outliers=outliers),
            outliers[~np.isin(outliers, ordering.outliers)])


def _one_segment(points: FloatArray, tolerance: float) -> FitResult | None:
    """When the tolerance is as large as the points' extent, the smallest valid result: one
    segment along their principal axis, if it keeps every point within the tolerance."""
    low, high = column_bounds(points)
    if (high - low).max() > 2 * tolerance:  # some point is farther than that from any centre
        return None
    centre = points.mean(axis=0)
    if np.linalg.norm(points - centre, axis=1).max() > tolerance:
        return None
    axis = np.linalg.svd(points - centre, full_matrices=False)[2][0]
    t = (points - centre) @ axis
    ends = centre + np.outer([t.min(), t.max()], axis)
    dist = polyline_distance(points, ends, False)
    if not within(float(dist.max()), tolerance):
        return None
    contour = Contour(ends, False, float(dist.max()), float(dist.mean()))
    note = (f"the tolerance {tolerance:.4g} is as large as the points' extent: one segment "
            "keeps every point within it")
    return FitResult([contour], tolerance, contour.max_error, contour.mean_error,
                     np.empty(0, dtype=np.intp), len(points), [-1], notes=(note,),
                     validity=check_contours([contour]))


def _without_stubs(points: FloatArray, outliers: IntArray, contours: list[Contour],
                   reports: list[ContourReport], tolerance: float
                   ) -> tuple[list[Contour], list[ContourReport], float]:
    """The result without its redundant stubs (`wavepoly.stubs`), and the largest distance
    of the points near them to what stays (for the result's error)."""
    gone, farthest = redundant_stubs(points, outliers, contours, tolerance)
    if not gone.any():
        return contours, reports, 0.0
    new_index = np.cumsum(~gone) - 1
    first_left: dict[int, int] = {}  # a split contour's first piece that stays
    for k, r in enumerate(reports):
        if not gone[k] and r.first_piece is not None:
            first_left.setdefault(r.first_piece, int(new_index[k]))
    kept_c, kept_r = [], []
    for k, (c, r) in enumerate(zip(contours, reports)):
        if not gone[k]:
            kept_c.append(c)
            kept_r.append(r if r.first_piece is None
                          else replace(r, first_piece=first_left[r.first_piece]))
    return kept_c, kept_r, farthest


def _outliers_left(points: FloatArray, outliers: IntArray, contours: list[Contour],
                   tolerance: float) -> tuple[IntArray, IntArray, float]:
    """The guarantee checked over every input point: the outliers that no output contour
    passes within ``tolerance`` of, the points the ordering kept that the output lost, and the
    largest distance of the points within the tolerance to the output.

    The ordering lists as outliers the points far from their own chain; some of them (strays
    beside a wall, the foot of a wall meeting another) lie within the tolerance of the polygons
    drawn all the same, and the guarantee holds for them. Each contour's fit verifies its own
    members, but the steps after it (junctions, noding, stubs) and a contour dropped whole
    could leave a point out: such a point is listed with the outliers, never left silently
    beyond the tolerance.
    """
    if not contours:
        return np.arange(len(points)), np.setdiff1d(np.arange(len(points)), outliers), 0.0
    a, b = _output_segments(contours)
    dist = segments_distance(points, a, b, limit=tolerance * (1 + SLACK))
    beyond = dist > tolerance * (1 + SLACK)  # as `within` tests it
    listed = np.zeros(len(points), dtype=bool)
    listed[outliers] = True
    covered = dist[~beyond]
    return (np.flatnonzero(beyond), np.flatnonzero(beyond & ~listed),
            float(covered.max()) if len(covered) else 0.0)


def _lost_notes(points: FloatArray, lost: IntArray) -> list[str]:
    """A note on the points that the ordering kept and the output lost (`_outliers_left`)."""
    if not len(lost):
        return []
    x, y = points[lost[0]]
    return [f"{len(lost)} point(s) that the ordering kept are farther than the tolerance from "
            f"the output (the first at ({x:.6g}, {y:.6g})): listed with the outliers"]


def _output_segments(contours: list[Contour]) -> tuple[FloatArray, FloatArray]:
    """The start and end points of every edge of the output (a lone vertex as an edge of
    no length)."""
    ends = [contour_segments(c) if len(c.vertices) > 1 else (c.vertices, c.vertices)
            for c in contours]
    return np.vstack([e[0] for e in ends]), np.vstack([e[1] for e in ends])


def _speck_notes(points: FloatArray, outliers: IntArray, ordering: Ordering,
                 tolerance: float) -> list[str]:
    """On a clean scan, a note on the outliers that are specks: groups (points within the
    radius of one another) under `ISLAND_EXTENT` tolerances across, such as a traced mask's
    holes of a pixel, with too few points for a polygon of their own (a speck of
    `ISLAND_POINTS` or more, clear of other points, is one: `speck_contours`).
    """
    if not ordering.clean or not len(outliers):
        return []
    xy = points[outliers]
    label = point_clusters(xy, ordering.radius)
    small = group_extents(xy, label) < ISLAND_EXTENT * tolerance
    in_specks = int(small[label].sum())
    if not in_specks:
        return []
    speck = xy[label == np.flatnonzero(small)[0]]
    first = (speck.min(axis=0) + speck.max(axis=0)) / 2
    return [f"{in_specks} of the {len(outliers)} outlier(s) lie in {int(small.sum())} "
            f"speck(s) under {ISLAND_EXTENT:g} x the tolerance across (the first by "
            f"({first[0]:.4g}, {first[1]:.4g})): too few points for a polygon of their own"]


def _ordered_ring(oc: OrderedContour) -> Contour:
    """A closed contour's ordered points as a polygon (an obstacle to its neighbours' fits)."""
    return Contour(oc.points, True, 0.0, 0.0)


def _neighbours(points: FloatArray, ordered: list[OrderedContour], tolerance: float
                ) -> list[IntArray]:
    """For each contour, the other contours whose boxes come within 2 x tolerance of its own:
    the only ones its polygon could meet (it lies within the tolerance of its points)."""
    if not ordered:
        return []
    boxes = []
    for oc in ordered:
        xy = np.vstack([oc.points, points[oc.members]]) if len(oc.members) else oc.points
        lo, hi = column_bounds(xy)
        lo, hi = lo - 2 * tolerance, hi + 2 * tolerance
        boxes.append(shapely.box(lo[0], lo[1], hi[0], hi[1]))
    tree = shapely.STRtree(boxes)
    mine, other = tree.query(boxes, predicate="intersects")
    keep = mine != other
    order = np.argsort(mine[keep], kind="stable")
    bounds = np.searchsorted(mine[keep][order], np.arange(len(ordered) + 1))
    return [other[keep][order][bounds[k]:bounds[k + 1]] for k in range(len(ordered))]


def fit_contour(points: FloatArray, oc: OrderedContour, tolerance: float,
                relative_tolerance: float | None, obstacles: shapely.STRtree | None = None,
                clean: bool = False) -> tuple[Contour, ContourReport, dict[str, float]]:
    """Decompose (§3) and reconstruct (§4) one ordered contour, verified within tolerance and
    clear of the ``obstacles`` (the edges of contours already fixed near it). ``clean``: the
    scan is a clean sampling, whose ordered points may serve as a simple backbone
    (`wavepoly.reconstruction.reconstruct_contour`).

    Returns the contour, its report and the seconds spent in each stage.
    """
    members = points[oc.members]
    t0 = time.perf_counter()
    pyramid = decompose_contour(oc.points, oc.closed, tolerance, relative_tolerance)
    t1 = time.perf_counter()
    rec = _best_reconstruction(pyramid, oc.points, members, tolerance, relative_tolerance,
                               obstacles, clean)
    times = {"decomposition": t1 - t0, "reconstruction": time.perf_counter() - t1}
    if not within(rec.max_error, tolerance):  # the repair makes this impossible; never hide it
        raise RuntimeError(f"internal error: contour error {rec.max_error} > {tolerance}")
    contour = Contour(without_repeats(rec.vertices, oc.closed), oc.closed, rec.max_error,
                      rec.mean_error)
    report = ContourReport(
        input_points=len(oc.members), ordered_points=len(oc.points), closed=oc.closed,
        levels_decomposed=pyramid.finest - rec.start_level, finest_level=pyramid.finest,
        coarsest_level=rec.start_level, mscs_per_level=rec.mscs_per_level,
        wavelet_vertices=rec.wavelet_vertices, final_vertices=len(rec.vertices),
        max_error=rec.max_error, mean_error=rec.mean_error)
    return contour, report, times


def _best_reconstruction(pyramid: Pyramid, ordered: FloatArray, members: FloatArray,
                         tolerance: float, relative_tolerance: float | None,
                         obstacles: shapely.STRtree | None, clean: bool = False
                         ) -> Reconstruction:
    if relative_tolerance is not None:
        return reconstruct_contour(pyramid, ordered, members, tolerance, obstacles=obstacles,
                                   simple_backbone=clean)
    best = None
    for level in auto_start_levels(pyramid, tolerance):
        rec = reconstruct_contour(pyramid, ordered, members, tolerance, start_level=level,
                                  obstacles=obstacles, simple_backbone=clean)
        if best is None or len(rec.vertices) < len(best.vertices):
            best = rec
    assert best is not None
    return best


def auto_start_levels(pyramid: Pyramid, tolerance: float) -> list[int]:
    """Start levels that ``relative_tolerance=None`` tries: the coarsest, the one that the
    default relative tolerance (eq. 7) picks, and the level between them.

    Trying every level costs one reconstruction each for rarely more than a vertex or two (the
    final selection takes the ordered points as candidates whatever the level); see
    docs/benchmarks.md for the measurements.
    """
    by_eq7 = pyramid.finest
    for level in range(pyramid.finest - 1, pyramid.coarsest - 1, -1):
        if pyramid.errors[level].violates(tolerance, DEFAULT_RELATIVE_TOLERANCE):
            break
        by_eq7 = level
    return sorted({pyramid.coarsest, (pyramid.coarsest + by_eq7) // 2, by_eq7})
