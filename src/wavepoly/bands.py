"""One layer from its band of the cloud alone: the unit of work that goes to a worker.

A layer's section needs the tangent planes of its slab's points (`wavepoly.sections`), and a
point's tangent plane needs its neighbourhood and its neighbours' (`SurfaceSamples.support`),
which reach a little above and below the slab. So a layer's job carries a *band*: the slab
and whole layers on either side of it. The job knows which heights its band covers, so it can
tell whether what each slab point's plane depends on lies within them (then it is the same as
in the whole cloud); when it does not, the job answers None and the caller sends a wider
band. The answer is thus the same whether the layers run in this process, in a local pool or
on a cluster, and no worker ever holds more of the cloud than a few layers.

The staircase error of a layer (`wavepoly.staircase`) is a job of its own (`ErrorJob`): it
needs the contours of the layers next to it, known only once they are fitted.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np

from .errors import DataError
from .fit import fit
from .flat_faces import section_height
from .geometry import mean_width, nest_contours, orient_by_depth, polyline_length
from .polylines import close_gaps
from .sections import SURFACE_NEIGHBOURS, section_points, surface_samples
from .staircase import farther_layers, outside_distances, slab_errors
from .types import ErrorJob, FitResult, FloatArray, IntArray, LayerJob, LayerSpec
from .validity import check_contours

#: Fewer section points than this make no contour (a speck where a cap grazes the plane).
MIN_SECTION_POINTS = 8
#: Open ends of a layer's section are bridged across gaps up to this many layer thicknesses
#: plus `GAP_TOLERANCES` tolerances: the points missing at a sharp vertical edge or where the
#: surface is nearly in the plane leave gaps of about a layer's thickness.
GAP_LAYERS = 1.0
GAP_TOLERANCES = 4.0
#: A layer is broken (`_broken`) when its open pieces are at least this share as long as its
#: closed contours: a plane along the turbine blade's platform closed the points on one side of
#: it (47 units) and left the other side open (45); a whole section with a stray fragment
#: has a few percent (the bunny's second layer: 6 %).
BROKEN_SHARE = 0.5
#: A closed contour narrower on average (twice its area over its perimeter) than this many
#: tolerances counts as open there: an outline folded onto itself, walked out along one side
#: of a band of points and back along the other (the turbine blade's top face cut by the
#: plane: two such slivers along its walls, 0.56 and 0.65 tolerances), stands for no solid.
FOLDED_SECTION = 1.0
#: Longest run of broken layers held over from their neighbours: a plane nearly touching a
#: face breaks a layer or two; a longer run is a gap in the scan, which a copy would hide.
MAX_HELD_RUN = 2
#: A run at an end of the stack takes its neighbour's contours when its points lie within this
#: many tolerances of their region: the neighbour's contours are within one of its own points,
#: and the walls of the run lean out from them a little more (1.2-1.6 at the bunny's base)...
END_FACE_REACH = 2.0
#: ... all but this share of them: a few flare farther where the base meets the table (0.2 %
#: of the bunny's lowest layer, up to 2.4 tolerances); a side that the scans never saw lies
#: wholly outside (13 tolerances in the raw bunny scans).
END_FACE_STRAYS = 0.01

#: How a layer's fit says that its section was moved off its mid-plane, which lies in a flat
#: face's points (`wavepoly.flat_faces.section_height`).
IN_A_FACE = "the mid-plane lies in a flat face's points"


def max_gap(thickness: float, tolerance: float) -> float:
    """The widest gap in a layer's section that is bridged (see `GAP_LAYERS`)."""
    return GAP_LAYERS * thickness + GAP_TOLERANCES * tolerance


def layer_starts(heights: FloatArray, bottoms: FloatArray) -> IntArray:
    """Row where each layer's slab starts in a cloud sorted by ``heights``, and its end: layer
    ``k`` holds rows ``starts[k]:starts[k + 1]`` (heights in [bottoms[k], bottoms[k + 1]))."""
    return np.append(np.searchsorted(heights, bottoms), len(heights))


def band_of(bottoms: FloatArray, thickness: FloatArray, k: int, reach: int
            ) -> tuple[int, int, float, float]:
    """Layers ``first:stop`` of the band of layer ``k`` with ``reach`` layers either side, and
    the heights it covers (-inf / inf at the cloud's ends)."""
    first, stop = max(0, k - reach), min(len(bottoms), k + reach + 1)
    low = -np.inf if first == 0 else float(bottoms[first])
    high = np.inf if stop == len(bottoms) else float(bottoms[stop - 1] + thickness[stop - 1])
    return first, stop, low, high


def section_rows(heights: FloatArray, spec: LayerSpec) -> slice:
    """Rows of a band (sorted ``heights``) whose points may give section points."""
    half = spec.thickness / 2
    if spec.section_band is not None:
        half = min(spec.section_band, spec.thickness) / 2
    return slice(*np.searchsorted(heights, [spec.z - half, spec.z + half]))


def fit_layer_job(job: LayerJob) -> FitResult | None:
    """The fit of a layer's mid-plane section from its band, or None when the band is too
    narrow for some slab point's neighbourhood (the caller sends a wider one)."""
    spec, uvh = job.spec, job.points
    rows = section_rows(uvh[:, 2], spec)
    section, face = np.empty((0, 2)), None
    if rows.stop > rows.start:
        surface = surface_samples(uvh, SURFACE_NEIGHBOURS, rows)
        h = surface.uvh[:, 2]
        complete = (h - surface.support >= spec.low) & (h + surface.support <= spec.high)
        if not np.all(complete):
            return None
        height, face = section_height(surface, spec.bottom, spec.bottom + spec.thickness,
                                      spec.tolerance)
        section = section_points(surface, slice(None), height)
    res = fit_layer(section, spec.tolerance, spec.relative_tolerance, spec.z, spec.max_gap)
    if face is not None:
        res = replace(res, notes=(*res.notes, f"{IN_A_FACE} (at {face:.6g}): the section "
                                  f"is taken at {height:.6g}"))
    return res


def fit_layer(points: FloatArray, tolerance: float, relative_tolerance: float | None,
              z: float, gap: float = 0.0) -> FitResult:
    """The fit of one layer's section points (a pure function: safe in any worker), its open
    pieces bridged across gaps up to ``gap`` (`wavepoly.polylines.close_gaps`).

    Too few points (the plane misses the object, or grazes a cap) give a layer with no contour
    and a note, not an error.
    """
    if len(points) < MIN_SECTION_POINTS:
        return FitResult([], tolerance, 0.0, 0.0, np.arange(len(points)), len(points),
                         notes=(f"no contour: {len(points)} section point(s)",), z=z)
    try:
        res = fit(points, tolerance, relative_tolerance=relative_tolerance)
    except DataError as exc:
        return FitResult([], tolerance, 0.0, 0.0, np.arange(len(points)), len(points),
                         notes=(f"no contour: {exc}",), z=z)
    return replace(closed_up(res, gap), z=z)


def closed_up(res: FitResult, gap: float) -> FitResult:
    """The fit with its open pieces bridged across gaps up to ``gap`` into closed sections,
    where that stays valid (a cloud's section, or a mesh's across a hole in the scan)."""
    if gap <= 0 or all(c.closed for c in res.contours):
        return res
    contours, bridges = close_gaps(res.contours, gap)
    validity = check_contours(contours)
    if not bridges or not validity.valid:
        return res
    parents = nest_contours(contours)
    note = f"{bridges} gap(s) in the section bridged (up to {gap:.3g})"
    return replace(res, contours=orient_by_depth(contours, parents), parents=parents,
                   reports=[], validity=validity, notes=(*res.notes, note))


def held_over(fits: list[FitResult], bottoms: FloatArray, tops: FloatArray,
              errors_of: Callable[[list[tuple[int, ErrorJob]]], list[float]],
              tolerance: float | None = None) -> list[FitResult]:
    """The fits of a stack of layers, where layers whose sections gave mostly open pieces (the
    plane nearly touches a face, as at a ledge, and the section is ill-posed there) take the
    closed contours of a neighbour: a layer model is a solid, and an open layer would cut it
    in two. A run of such layers between two closed ones is split where the staircase error
    of the run and of the layers either side is smallest: the layers below the split take
    the contours under the run, the others those over it (a ledge's top face is exposed only
    where the layer over it is not a copy of it); runs longer than `MAX_HELD_RUN` are left
    as they are (a gap in the scan, not a face). A run at an end of the stack takes its one
    neighbour's contours where all its points lie near that neighbour's region (within
    `END_FACE_REACH` tolerances: an end face that the scan saw full of holes, as a base on
    the scanner's table; left as it is, its fragments would stand apart from the solid),
    or, for a short run, where that lowers the error. Their own section points are then
    outliers, and their staircase errors say how far the kept contours are.

    ``errors_of`` computes the `ErrorJob` of each layer ``k`` (their slabs left empty: the caller
    holds the points, or the workers do).
    """
    out = list(fits)
    for a, b in _broken_runs(fits):
        anchors = [j for j in (a - 1, b + 1) if 0 <= j < len(fits) and _solid(fits[j])]
        if not anchors:
            continue
        if len(anchors) == 2:  # the run must not cut the solid: it is split between them
            split = _best_split(fits, a, b, bottoms, tops, errors_of)
        else:
            split = _end_split(fits, a, b, anchors[0], bottoms, tops, errors_of, tolerance)
        if split is None:
            continue
        for k in range(a, b + 1):
            j = a - 1 if k <= split else b + 1
            out[k] = _kept(fits[k], fits[j], "below" if j < k else "above")
    return out


def _best_split(fits: list[FitResult], a: int, b: int, bottoms: FloatArray, tops: FloatArray,
                errors_of: Callable) -> int | None:
    """Where a run between two closed layers is split (None: too long, left as it is)."""
    if b - a + 1 > MAX_HELD_RUN:
        return None
    return _least_error(list(range(a - 1, b + 1)), fits, a, b, bottoms, tops, errors_of)


def _end_split(fits: list[FitResult], a: int, b: int, anchor: int, bottoms: FloatArray,
               tops: FloatArray, errors_of: Callable, tolerance: float | None) -> int | None:
    """The split that gives a run at an end of the stack its anchor's contours, or None."""
    copy = b if anchor == a - 1 else a - 1
    if tolerance is not None:
        asks = [(k, ErrorJob(np.empty((0, 3)), float(bottoms[k]), float(tops[k]),
                             fits[anchor].contours, None, None, outside=True))
                for k in range(a, b + 1)]
        if max(errors_of(asks)) <= END_FACE_REACH * tolerance:
            return copy
    if b - a + 1 > MAX_HELD_RUN:
        return None
    return _least_error([copy, None], fits, a, b, bottoms, tops, errors_of)


def _least_error(options: list, fits: list[FitResult], a: int, b: int, bottoms: FloatArray,
                 tops: FloatArray, errors_of: Callable) -> int | None:
    """The split among ``options`` (None: the run as it is) whose largest staircase error
    over the run and the layers either side is smallest."""
    asks = [job for m in options for job in _split_jobs(fits, a, b, m, bottoms, tops)]
    errors = np.array(errors_of(asks)).reshape(len(options), -1).max(axis=1)
    return options[int(np.argmin(errors))]


def _solid(f: FitResult) -> bool:
    """Can the layer lend its contours: a solid section (closed contours, not broken)?"""
    return any(c.closed for c in f.contours) and not _broken(f)


def _broken(f: FitResult) -> bool:
    """Does the layer's section stand for no solid: open pieces (and closed ones folded onto
    themselves, `FOLDED_SECTION`) at least `BROKEN_SHARE` x as long as its other closed
    contours (a few fragments closed by chance among them do not make it one)?"""
    solid = [c.closed and mean_width(c.vertices) >= FOLDED_SECTION * f.tolerance
             for c in f.contours]
    opened = sum(polyline_length(c.vertices, c.closed) for c, s in zip(f.contours, solid)
                 if not s)
    closed = sum(polyline_length(c.vertices, True) for c, s in zip(f.contours, solid) if s)
    return opened > 0 and opened >= BROKEN_SHARE * closed


def _broken_runs(fits: list[FitResult]) -> list[tuple[int, int]]:
    """First and last index of each run of broken layers (`_broken`)."""
    runs, start = [], None
    for k, f in enumerate([*fits, None]):
        broken = f is not None and _broken(f)
        if broken and start is None:
            start = k
        elif not broken and start is not None:
            runs.append((start, k - 1))
            start = None
    return runs


def _split_jobs(fits: list[FitResult], a: int, b: int, m: int | None, bottoms: FloatArray,
                tops: FloatArray) -> list[tuple[int, ErrorJob]]:
    """The error jobs of layers a-1 .. b+1 when layers a..m take the contours of layer a-1
    and layers m+1..b those of layer b+1 (m None: the layers as they are)."""
    def contours(i: int) -> list | None:
        if not 0 <= i < len(fits):
            return None
        if m is not None and a <= i <= b:
            return fits[a - 1 if i <= m else b + 1].contours
        return fits[i].contours

    return [(i, ErrorJob(np.empty((0, 3)), float(bottoms[i]), float(tops[i]), contours(i),
                         contours(i - 1), contours(i + 1)))
            for i in range(max(a - 1, 0), min(b + 2, len(fits)))]


def _kept(own: FitResult, neighbour: FitResult, where: str) -> FitResult:
    n_open = sum(not c.closed for c in own.contours)
    note = (f"the section gave mostly open pieces ({n_open}): the plane nearly "
            f"touches a face; the contours of the closed layer {where} are kept")
    return replace(neighbour, z=own.z, outliers=np.arange(own.n_points), n_points=own.n_points,
                   max_error=0.0, mean_error=0.0, reports=[], notes=(*own.notes, note),
                   suggested_tolerance=None)


def layer_error_job(job: ErrorJob) -> float:
    """The largest staircase error of a layer's slab (0 without points), or with
    ``job.outside`` how far its points lie outside the region of ``job.own``, all but
    `END_FACE_STRAYS` of them."""
    if not len(job.slab):
        return 0.0
    if job.outside:
        return float(np.quantile(outside_distances(job.slab[:, :2], job.own),
                                 1.0 - END_FACE_STRAYS))
    errs = slab_errors(job.slab, job.bottom, job.top, job.own, job.below, job.above,
                       job.farther_below, job.farther_above)
    return float(errs.max())


def farther_jobs(jobs: list[ErrorJob], errors: list[float], bottoms: FloatArray,
                 tops: FloatArray, contours: list[list]) -> list[tuple[int, ErrorJob]]:
    """The error jobs of the layers whose error reaches past their neighbours, with the layers
    farther out that it reaches (`wavepoly.staircase.farther_layers`): run again, they give
    the distance to the surface of the whole stack, never more than the first answer."""
    again = []
    for k, (job, err) in enumerate(zip(jobs, errors)):
        below, above = farther_layers(k, err, bottoms, tops, contours)
        if below or above:
            again.append((k, replace(job, farther_below=below, farther_above=above)))
    return again
