"""Slicing a 3D scan into a layer model (paper §1, §5 example 2, Fig. 7).

The cloud is cut by planes across ``axis``. Each layer stands for the slab of the cloud between
its bottom and its top, and its contours are the object's cross-section at the layer's
mid-plane: every slab point whose surface crosses the mid-plane slides along its tangent plane
onto it (`wavepoly.sections`), and those points are fitted within the tolerance
(`wavepoly.fit`: several contours, holes, open curves where the scan has gaps). The stack of
layers, each its contours extruded from its bottom to its top, is the layer-based (stair-step)
model for rapid prototyping; its error is 3D: the distance from each cloud point to the
surface of the stack (`wavepoly.staircase`), reported per layer.

Uniform layers have one thickness; where a flat face across the axis falls so near a
layer's mid-plane that the plane lies in the face's noisy points, the layer's section is
taken in the middle of its larger part beside the face (`wavepoly.flat_faces.section_height`).
Adaptive layers (Wu, Wong, Loh & Zhang 2004) are as thick
as the shape allows: a candidate layer's section is fitted within tolerance / 2 and the layer
is accepted when the staircase error of its slab stays within the tolerance; the thickness
grows from the previous layer's while that holds and shrinks when it fails, between
``min_layer`` and ``max_layer``; they end on the flat faces across the axis, so that no
mid-plane lies in a face's points (`wavepoly.flat_faces`).

Layers are independent once planned: `wavepoly.bands.fit_layer_job` is a pure function of a
`LayerJob` (the layer's parameters and its band of the cloud), run here in a local process pool
and, for tiles, on a Dask cluster (`wavepoly.tiled`).

>>> import numpy as np
>>> rng = np.random.default_rng(0)
>>> t, h = rng.uniform(0, 2 * np.pi, 20000), rng.uniform(0, 10, 20000)
>>> cylinder = np.column_stack([5 * np.cos(t), 5 * np.sin(t), h])
>>> res = slice_cloud(cylinder, 0.1, layer_thickness=2.0, workers=1)
>>> len(res.layers), [c.closed for c in res.layers[0].fit.contours]
(5, [True])
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from .bands import (
    IN_A_FACE,
    band_of,
    closed_up,
    farther_jobs,
    fit_layer,
    fit_layer_job,
    held_over,
    layer_error_job,
    layer_starts,
    max_gap,
)
from .errors import DataError, ParameterError
from .flat_faces import flat_faces, stack_ends
from .geometry import to_plane
from .parallel import resolve_workers, run_jobs
from .polylines import fit_polylines
from .sections import mesh_section, section_points, surface_samples
from .staircase import layer_errors, slab_errors
from .types import (
    DEFAULT_RELATIVE_TOLERANCE,
    ErrorJob,
    FitResult,
    FloatArray,
    IntArray,
    Layer,
    LayerJob,
    LayerSpec,
    SliceResult,
    SurfaceSamples,
    within,
)
from .validate import check_relative_tolerance, check_tolerance, validate_points

AXES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}
#: Refuse plans of more layers than this: a thickness that small is a unit mistake.
MAX_LAYERS = 100_000
#: Layers per range are rounded up unless the range is within this fraction of a whole count.
LAYER_COUNT_SLACK = 1e-9
#: Adaptive thicknesses grow and shrink by this factor per trial (Wu et al. use a similar step).
GROWTH = 1.25
#: A note names this many flat faces' heights.
FACES_SHOWN = 5
#: A uniform layer's first band holds this many layers on either side of its slab: enough for
#: the neighbourhoods of its points and of their neighbours (whose planes a point may take,
#: `wavepoly.sections`), about two radii, where the scan's spacing is below a layer's
#: thickness. It doubles for the layers whose slab points reach beyond it. With one layer, the
#: turbine blade's 85 bands (600,000 points, layers of 1/100 of its diagonal) were sent 172
#: times, and the fits took 62 s instead of 38 (in one process).
BAND_REACH = 2


def plane_basis(axis: str | FloatArray) -> FloatArray:
    """(3, 3) orthonormal rows (e1, e2, axis), right-handed; the identity for ``"z"``."""
    if isinstance(axis, str):
        if axis.lower() not in AXES:
            raise ParameterError(f"axis must be x, y, z or a 3-vector, not {axis!r}")
        axis = AXES[axis.lower()]
    a = np.asarray(axis, dtype=float)
    if a.shape != (3,) or not np.all(np.isfinite(a)) or np.linalg.norm(a) == 0:
        raise ParameterError(f"axis must be x, y, z or a non-zero 3-vector, not {axis!r}")
    a = a / np.linalg.norm(a)
    helper = np.array([1.0, 0.0, 0.0]) if abs(a[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    if np.allclose(a, [0.0, 0.0, 1.0]):
        return np.eye(3)
    e1 = helper - a * (helper @ a)
    e1 /= np.linalg.norm(e1)
    return np.vstack([e1, np.cross(a, e1), a])


def slice_cloud(points3d: FloatArray, tolerance: float, *, axis: str | FloatArray = "z",
                layer_thickness: float | None = None, adaptive: bool = False,
                min_layer: float | None = None, max_layer: float | None = None,
                band: float | None = None,
                relative_tolerance: float | None = DEFAULT_RELATIVE_TOLERANCE,
                workers: int | None = None,
                progress: Callable[[int, int], None] | None = None) -> SliceResult:
    """Slice a 3D cloud into layers whose contours are its cross-sections within ``tolerance``.

    Parameters
    ----------
    points3d : (N, 3) cloud; float32 stays float32 (half the memory) until a band is fitted.
    tolerance : shape tolerance, in the cloud's units: each layer's contours are within it of
        the section points; adaptive layers also keep the 3D staircase error within it.
    axis : slicing direction: ``"x"``, ``"y"``, ``"z"`` or a 3-vector.
    layer_thickness : thickness of uniform layers (required unless ``adaptive``).
    adaptive : choose each thickness in [min_layer, max_layer] to keep the layer model within
        the tolerance (see the module docstring).
    min_layer, max_layer : bounds of adaptive thicknesses (default: 2 and 20 x tolerance).
    band : if given, only slab points within ``band / 2`` of the mid-plane are used for the
        section (default: every point whose surface reaches the mid-plane).
    relative_tolerance : eq. 7 threshold passed to `wavepoly.fit` (None: automatic).
    workers : processes for uniform layers' fits (default: all cores; 1 runs in this process);
        adaptive layers are fitted in sequence, each thickness depending on the fit.
    progress : called as ``progress(done, total)`` after each layer.
    """
    pts = validate_points(points3d, source="cloud", min_points=3, keep_float32=True)
    if pts.shape[1] != 3:
        raise DataError(f"cloud: slicing needs (N, 3) points, got {pts.shape[1]} columns")
    tolerance = check_tolerance(tolerance)
    relative_tolerance = check_relative_tolerance(relative_tolerance)
    band = check_tolerance(band, "band") if band is not None else None
    basis = plane_basis(axis)
    t0 = time.perf_counter()
    uvh = to_plane(pts, basis)
    uvh = uvh[np.argsort(uvh[:, 2], kind="stable")]
    faces = (np.empty(0), np.empty(0))  # flat faces across the axis: adaptive layers end on them
    if adaptive:
        lo = check_tolerance(min_layer if min_layer is not None else 2 * tolerance, "min_layer")
        hi = check_tolerance(max_layer if max_layer is not None else 20 * tolerance, "max_layer")
        if lo > hi:
            raise ParameterError(f"min_layer {lo:g} is thicker than max_layer {hi:g}")
        surface = surface_samples(uvh)
        faces = flat_faces(surface, tolerance)
        plan = adaptive_layers(surface, _Bounds(tolerance, lo, hi, band, relative_tolerance),
                               progress, faces)
        bottoms = np.array([p[0] for p in plan])
        thick = np.array([p[1] for p in plan])
        fits = held_over([p[2] for p in plan], bottoms, bottoms + thick,
                         lambda asks: [layer_error_job(replace(job, slab=_slab(uvh, job)))
                                       for _, job in asks], tolerance)
        timings = {"planning": time.perf_counter() - t0, "fitting": 0.0}
        t0 = time.perf_counter()
        errors = layer_errors(uvh, bottoms, bottoms + thick, [f.contours for f in fits])
    else:
        if layer_thickness is None:
            raise ParameterError("give a layer thickness, or adaptive=True with its bounds")
        step = check_tolerance(layer_thickness, "layer_thickness")
        bottoms, thick = uniform_layers(uvh[0, 2], uvh[-1, 2], step)
        specs = layer_specs(bottoms, thick, tolerance, relative_tolerance, band)
        starts = layer_starts(uvh[:, 2], bottoms)
        timings = {"planning": time.perf_counter() - t0}
        t0 = time.perf_counter()
        fits = fit_bands(specs, lambda tasks: run_jobs(
            fit_layer_job, band_jobs(uvh, starts, tasks), workers, progress))
        fits = held_over(fits, bottoms, bottoms + thick, lambda asks: run_jobs(
            layer_error_job, [replace(job, slab=uvh[starts[k]:starts[k + 1]])
                              for k, job in asks], workers), tolerance)
        timings["fitting"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        jobs = error_jobs(specs, [f.contours for f in fits],
                          lambda k: uvh[starts[k]:starts[k + 1]])
        errors = run_jobs(layer_error_job, jobs, workers)
        again = farther_jobs(jobs, errors, bottoms, bottoms + thick, [f.contours for f in fits])
        for (k, _), err in zip(again, run_jobs(layer_error_job, [j for _, j in again], workers)):
            errors[k] = err
    counts = np.diff(layer_starts(uvh[:, 2], bottoms)) if not adaptive else np.diff(
        np.searchsorted(uvh[:, 2], np.append(bottoms, bottoms[-1] + thick[-1])))
    timings["model_error"] = time.perf_counter() - t0
    engine = {"kind": "local", "workers": 1 if adaptive else resolve_workers(workers)}
    model = layer_model(bottoms, thick, fits, errors, counts,
                        SliceResult([], basis, tolerance, adaptive, len(pts), timings,
                                    engine=engine))
    if len(faces[0]):
        model = replace(model, notes=(*model.notes, _faces_note(faces[0])))
    return model


def _slab(uvh: FloatArray, job: ErrorJob) -> FloatArray:
    """The points of a cloud sorted by height within a job's slab."""
    return uvh[slice(*np.searchsorted(uvh[:, 2], [job.bottom, job.top]))]


def layer_model(bottoms: FloatArray, thick: FloatArray, fits: list[FitResult],
                errors: list[float], counts: IntArray, frame: SliceResult) -> SliceResult:
    """The layer model of fitted layers: ``frame`` (a result without layers) with the layers,
    less the empty ones at the ends, and the notes on them."""
    layers = [Layer(float(b), float(t), (float(b), float(b + t)), res, int(n), err)
              for b, t, res, err, n in zip(bottoms, thick, fits, errors, counts)]
    layers = _trim_empty_ends(layers, frame.tolerance)
    return replace(frame, layers=layers, notes=tuple(_notes(layers, frame.tolerance)))


def layer_specs(bottoms: FloatArray, thick: FloatArray, tolerance: float,
                relative_tolerance: float | None, band: float | None) -> list[LayerSpec]:
    """The parameters of each uniform layer, with the heights of its first band."""
    specs = []
    for k, (b, t) in enumerate(zip(bottoms, thick)):
        _, _, low, high = band_of(bottoms, thick, k, BAND_REACH)
        specs.append(LayerSpec(float(b), float(t), low, high, tolerance, relative_tolerance,
                               band, max_gap(float(t), tolerance)))
    return specs


def fit_bands(specs: list[LayerSpec], run: Callable[[list[tuple[LayerSpec, int, int]]], list]
              ) -> list[FitResult]:
    """The fit of every layer from its band. ``run(tasks)`` fits each task ``(spec, first,
    stop)`` from the points of layers ``first:stop`` (`wavepoly.bands.fit_layer_job`) on some
    engine (this process, a pool, a cluster). Layers whose band was too narrow for their
    points' neighbourhoods are sent again with twice the reach."""
    bottoms = np.array([s.bottom for s in specs])
    thick = np.array([s.thickness for s in specs])
    fits: list[FitResult | None] = [None] * len(specs)
    pending, reach = list(range(len(specs))), BAND_REACH
    while pending:
        tasks = []
        for k in pending:
            first, stop, low, high = band_of(bottoms, thick, k, reach)
            tasks.append((replace(specs[k], low=low, high=high), first, stop))
        for k, res in zip(pending, run(tasks)):
            fits[k] = res
        pending, reach = [k for k in pending if fits[k] is None], 2 * reach
    return fits  # type: ignore[return-value]


def band_jobs(uvh: FloatArray, starts: IntArray, tasks: list[tuple[LayerSpec, int, int]]
              ) -> list[LayerJob]:
    """The jobs of ``tasks`` on a cloud in memory (sorted by height, layers from ``starts``)."""
    return [LayerJob(spec, uvh[starts[first]:starts[stop]]) for spec, first, stop in tasks]


def error_jobs(specs: list[LayerSpec], contours: list[list], slab_of: Callable
               ) -> list[ErrorJob]:
    """The staircase-error job of each layer: ``slab_of(k)`` gives layer k's slab points."""
    n = len(specs)
    return [ErrorJob(slab_of(k), s.bottom, s.bottom + s.thickness, contours[k],
                     contours[k - 1] if k > 0 else None, contours[k + 1] if k + 1 < n else None)
            for k, s in enumerate(specs)]


def slice_mesh(mesh, tolerance: float, *, layer_thickness: float,
               axis: str | FloatArray = "z") -> SliceResult:
    """Slice a triangle mesh (trimesh) from its faces: each layer's contours are the exact
    section at its mid-plane, simplified to the fewest vertices within ``tolerance``
    (`wavepoly.polylines`), and bridged across the gaps that a hole in the scanned mesh
    leaves, as a cloud's are (`wavepoly.bands.closed_up`). The model error is the staircase
    error of the mesh's vertices.
    """
    tolerance = check_tolerance(tolerance)
    step = check_tolerance(layer_thickness, "layer_thickness")
    basis = plane_basis(axis)
    t0 = time.perf_counter()
    uvh = np.asarray(mesh.vertices, float) @ basis.T
    uvh = uvh[np.argsort(uvh[:, 2], kind="stable")]
    bottoms, thick = uniform_layers(uvh[0, 2], uvh[-1, 2], step)
    fits = [closed_up(fit_polylines(mesh_section(mesh, basis, b + t / 2), tolerance,
                                    float(b + t / 2)), max_gap(float(t), tolerance))
            for b, t in zip(bottoms, thick)]
    fitting = time.perf_counter() - t0
    t0 = time.perf_counter()
    errors = layer_errors(uvh, bottoms, bottoms + thick, [f.contours for f in fits])
    layers = [Layer(float(b), float(t), (float(b), float(b + t)), res,
                    int(np.diff(np.searchsorted(uvh[:, 2], [b, b + t]))[0]), err)
              for b, t, res, err in zip(bottoms, thick, fits, errors)]
    timings = {"planning": 0.0, "fitting": fitting, "model_error": time.perf_counter() - t0}
    return SliceResult(layers, basis, tolerance, False, len(uvh), timings,
                       tuple(_notes(layers, tolerance)))


def _section(surface: SurfaceSamples, bottom: float, thickness: float, band: float | None
             ) -> FloatArray:
    """The section points of the layer [bottom, bottom + thickness) at its mid-plane."""
    mid = bottom + thickness / 2
    half = thickness / 2 if band is None else min(band, thickness) / 2
    rows = slice(*np.searchsorted(surface.uvh[:, 2], [mid - half, mid + half]))
    return section_points(surface, rows, mid)


def uniform_layers(low: float, high: float, thickness: float) -> tuple[FloatArray, FloatArray]:
    """Bottoms and thicknesses of equal layers covering [low, high]."""
    n = max(1, int(np.ceil((high - low) / thickness - LAYER_COUNT_SLACK)))
    if n > MAX_LAYERS:
        raise ParameterError(f"layer thickness {thickness:g} gives {n} layers: too thin")
    bottoms = low + thickness * np.arange(n)
    return bottoms, np.full(n, thickness)


@dataclass(frozen=True)
class _Bounds:
    """What an adaptive layer must meet: the tolerance, the thickness bounds, the band of
    section points (None: the slab), and the eq. 7 threshold."""

    tolerance: float
    min_layer: float
    max_layer: float
    band: float | None
    relative_tolerance: float | None = DEFAULT_RELATIVE_TOLERANCE


def adaptive_layers(surface: SurfaceSamples, bounds: _Bounds,
                    progress: Callable[[int, int], None] | None = None,
                    faces: tuple[FloatArray, FloatArray] | None = None
                    ) -> list[tuple[float, float, FitResult]]:
    """(bottom, thickness, fit) of adaptive layers over a cloud sorted by height.

    Each layer starts from the previous thickness; it grows by `GROWTH` while its slab's
    staircase error stays within the tolerance (the section fitted within tolerance / 2) and
    shrinks by the same factor when it does not, within [min_layer, max_layer]. A layer
    does not cross the ``faces`` (heights of flat faces across the axis and the thickness
    that keeps a mid-plane clear of each, `wavepoly.flat_faces`): it ends on the next one,
    or far enough short of it for the next layer to end on it, so that a face is one layer's
    top and the next one's bottom; the stack starts and stops on the part's bottom and top
    faces where it has them (`wavepoly.flat_faces.stack_ends`).
    """
    heights, clear = faces if faces is not None else (np.empty(0), np.empty(0))
    z, top, inside = stack_ends(surface, heights, bounds.tolerance)
    lo = bounds.min_layer
    first = max([lo, *clear[heights == z]])  # the thinnest layer from here: on a face, more
    # the faces to end on: those inside, and the top where it is one
    land = inside | ((heights == top) & (top < surface.uvh[-1, 2]))
    heights, need = heights[land], np.maximum(clear[land], lo)
    start, t = z, bounds.max_layer
    plan: list[tuple[float, float, FitResult]] = []
    total = max(1, int(np.ceil((top - z) / lo)))
    while z < top or not plan:
        below = plan[-1][2].contours if plan else None
        k = _next_face(heights, need, z, first)
        gap, near = (heights[k] - z, need[k]) if k >= 0 else (np.inf, lo)
        hi = max(first, min(bounds.max_layer, gap))
        t = _toward_face(min(max(t, first), hi), gap, near, first, hi)
        res, ok = _try_layer(surface, z, t, bounds, below)
        if ok:
            while t < hi:
                bigger = _toward_face(min(hi, t * GROWTH), gap, near, first, hi)
                if bigger <= t:  # only short of the face, which it already is
                    break
                res2, ok2 = _try_layer(surface, z, bigger, bounds, below)
                if not ok2:
                    break
                t, res = bigger, res2
        else:
            while not ok and t > first:
                t = max(first, t / GROWTH)
                res, ok = _try_layer(surface, z, t, bounds, below)
        onto = _toward_face(t, gap, near, first, hi)
        if onto != t:  # the next layer would straddle the face: this one ends on it
            t, (res, _) = onto, _try_layer(surface, z, onto, bounds, below)
        plan.append((z, t, res))
        on_face = t == gap
        z, first = (heights[k], need[k]) if on_face else (z + t, lo)  # on it, not a ulp off
        if progress:
            progress(min(total, int(np.ceil((z - start) / lo))), total)
    return plan


def _next_face(heights: FloatArray, need: FloatArray, z: float, first: float) -> int:
    """Index of the first face a layer starting at ``z`` could end on: at least ``first``
    above it and the face's own ``need``; -1 where there is none."""
    ahead = np.flatnonzero(heights >= z + np.maximum(need, first))
    return int(ahead[0]) if len(ahead) else -1


def _toward_face(t: float, gap: float, need: float, first: float, hi: float) -> float:
    """Thickness ``t`` moved so that the layer ends on the face ``gap`` above it or leaves
    at least the face's ``need`` to it (a thinner layer next to it would have its mid-plane
    in the face's noise): up to the face where it may be that thick (``hi``), else short of
    it, but no thinner than ``first``."""
    if not 0 < gap - t < need:
        return t
    return gap if gap <= hi else max(first, gap - need)


def _try_layer(surface: SurfaceSamples, bottom: float, thickness: float, bounds: _Bounds,
               below: list | None) -> tuple[FitResult, bool]:
    """Fit the section within tolerance / 2; is the slab's staircase error within tolerance
    (against the layer below, and with the top face taken as exposed)?"""
    mid = bottom + thickness / 2
    res = fit_layer(_section(surface, bottom, thickness, bounds.band), bounds.tolerance / 2,
                    bounds.relative_tolerance, mid, max_gap(thickness, bounds.tolerance))
    s0, s1 = np.searchsorted(surface.uvh[:, 2], [bottom, bottom + thickness])
    if s1 == s0:
        return res, True
    errs = slab_errors(surface.uvh[s0:s1], bottom, bottom + thickness, res.contours, below,
                       None)
    return res, within(float(errs.max()), bounds.tolerance)


def _trim_empty_ends(layers: list[Layer], tolerance: float) -> list[Layer]:
    """Without the first and last layers that have no section and whose points all lie within
    the tolerance of their neighbour's face (the tip of a dome): they add nothing."""
    def empty(la: Layer) -> bool:
        return not la.fit.contours and within(la.model_error, tolerance)

    lo, hi = 0, len(layers)
    while hi - lo > 1 and empty(layers[hi - 1]):
        hi -= 1
    while hi - lo > 1 and empty(layers[lo]):
        lo += 1
    return layers[lo:hi]


def _faces_note(heights: FloatArray) -> str:
    """What the adaptive plan made of the flat faces across the axis."""
    shown = ", ".join(f"{h:.4g}" for h in heights[:FACES_SHOWN])
    more = f" and {len(heights) - FACES_SHOWN} more" if len(heights) > FACES_SHOWN else ""
    return (f"{len(heights)} flat face(s) across the axis, at {shown}{more}: adaptive layers "
            "end on them (the stack on the part's bottom and top faces)")


def _notes(layers: list[Layer], tolerance: float) -> list[str]:
    notes = []
    empty = [k for k, la in enumerate(layers) if not la.fit.contours and la.slab_points]
    if empty:
        notes.append(f"{len(empty)} layer(s) with points but no section at the mid-plane "
                     f"(caps, or too few points), e.g. layer {empty[0]}")
    moved = [k for k, la in enumerate(layers) if any(IN_A_FACE in n for n in la.fit.notes)]
    if moved:
        notes.append(f"{len(moved)} layer(s) whose mid-plane lies in a flat face's points, "
                     f"e.g. layer {moved[0]}: each is the section of its larger part beside "
                     "the face (adaptive layers end on faces instead)")
    over = [k for k, la in enumerate(layers) if la.model_error > tolerance]
    if over:
        notes.append(f"{len(over)} layer(s) whose staircase error exceeds the tolerance "
                     "(thick layers on slopes, or caps inside a slab): thinner or adaptive "
                     "layers keep it within")
    return notes
