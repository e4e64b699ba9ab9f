"""Slicing a 3D scan into a layer model (paper §1, §5 example 2, Fig. 7).

The cloud is cut by planes across ``axis``. Each layer stands for the slab of the cloud between
its bottom and its top; the points of a band around the layer's mid-plane are projected onto it
and fitted (`wavepoly.fit`: several contours, holes, open curves where the scan has gaps). The
stack of layers, each extruded by its thickness, is the layer-based (stair-step) model for
rapid prototyping.

Uniform layers have one thickness and project the whole slab. Adaptive layers (Wu, Wong, Loh
& Zhang 2004, "Modelling cloud data using an adaptive slicing approach") are as thick as the
shape allows: a candidate slab's mid-plane band is fitted within tolerance / 2 and the slab is
accepted when every slab point lies within the tolerance, in its plane, of those contours; the
thickness grows from the previous layer's while that holds and shrinks when it fails, between
``min_layer`` and ``max_layer``. The error of the layer model is measured either way and
reported per layer; only layers at ``min_layer`` can exceed the tolerance (caps, ledges).

Layers are independent: `fit_layer` is a pure function of (band points, parameters), run in a
local process pool here and ready for a cluster engine.

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

from .errors import DataError, ParameterError
from .fit import fit
from .geometry import distance_to_contours
from .parallel import run_jobs
from .types import (
    DEFAULT_RELATIVE_TOLERANCE,
    FitResult,
    FloatArray,
    Layer,
    LayerJob,
    SliceResult,
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
    """Slice a 3D cloud into layers and fit each layer's contours within ``tolerance``.

    Parameters
    ----------
    points3d : (N, 3) cloud.
    tolerance : shape tolerance, in the cloud's units (in-plane distance).
    axis : slicing direction: ``"x"``, ``"y"``, ``"z"`` or a 3-vector.
    layer_thickness : thickness of uniform layers (required unless ``adaptive``).
    adaptive : choose each thickness in [min_layer, max_layer] to keep the layer model within
        the tolerance (see the module docstring).
    min_layer, max_layer : bounds of adaptive thicknesses (default: 2 and 20 x tolerance).
    band : thickness of the band of points projected onto each layer's mid-plane. Default:
        the whole slab for uniform layers, ``min_layer`` for adaptive ones.
    relative_tolerance : eq. 7 threshold passed to `wavepoly.fit` (None: automatic).
    workers : processes for uniform layers' fits (default: all cores; 1 runs in this process);
        adaptive layers are fitted in sequence, each thickness depending on the fit.
    progress : called as ``progress(done, total)`` after each layer.
    """
    pts = validate_points(points3d, source="cloud", min_points=3)
    if pts.shape[1] != 3:
        raise DataError(f"cloud: slicing needs (N, 3) points, got {pts.shape[1]} columns")
    tolerance = check_tolerance(tolerance)
    relative_tolerance = check_relative_tolerance(relative_tolerance)
    basis = plane_basis(axis)
    t0 = time.perf_counter()
    height = pts @ basis[2]
    order = np.argsort(height, kind="stable")
    height, uv = height[order], pts[order] @ basis[:2].T
    if adaptive:
        lo = check_tolerance(min_layer if min_layer is not None else 2 * tolerance, "min_layer")
        hi = check_tolerance(max_layer if max_layer is not None else 20 * tolerance, "max_layer")
        if lo > hi:
            raise ParameterError(f"min_layer {lo:g} is thicker than max_layer {hi:g}")
        band = check_tolerance(band, "band") if band is not None else lo
        plan = adaptive_layers(height, uv, _Bounds(tolerance, lo, hi, band,
                                                   relative_tolerance), progress)
        bottoms = np.array([p[0] for p in plan])
        thick = np.array([p[1] for p in plan])
        fits = [p[2] for p in plan]
        bands = [_band(height, b + t / 2, min(band, t)) for b, t in zip(bottoms, thick)]
        errors = [_model_error(uv[slice(*np.searchsorted(height, [b, b + t]))], res)
                  for b, t, res in zip(bottoms, thick, fits)]
        planning, fitting = time.perf_counter() - t0, 0.0
    else:
        if layer_thickness is None:
            raise ParameterError("give a layer thickness, or adaptive=True with its bounds")
        step = check_tolerance(layer_thickness, "layer_thickness")
        bottoms, thick = uniform_layers(height[0], height[-1], step)
        band = check_tolerance(band, "band") if band is not None else None
        planning = time.perf_counter() - t0
        bands = [_band(height, b + t / 2, t if band is None else min(band, t)) for b, t in
                 zip(bottoms, thick)]
        slabs = [np.searchsorted(height, [b, b + t]) for b, t in zip(bottoms, thick)]
        jobs = [LayerJob(uv[s0:s1], (int(i0 - s0), int(i1 - s0)), tolerance,
                         relative_tolerance, float(b + t / 2))
                for (i0, i1), (s0, s1), b, t in zip(bands, slabs, bottoms, thick)]
        t0 = time.perf_counter()
        fits, errors = zip(*run_jobs(fit_layer_job, jobs, workers, progress))
        fitting = time.perf_counter() - t0
    t0 = time.perf_counter()
    layers = []
    for (i0, i1), b, t, res, err in zip(bands, bottoms, thick, fits, errors):
        s0, s1 = np.searchsorted(height, [b, b + t])
        layers.append(Layer(float(b), float(t), (float(height[i0]) if i1 > i0 else b,
                                                 float(height[i1 - 1]) if i1 > i0 else b),
                            res, int(s1 - s0), err))
    notes = _notes(layers, tolerance)
    timings = {"planning": planning, "fitting": fitting, "model_error": time.perf_counter() - t0}
    return SliceResult(layers, basis, tolerance, adaptive, len(pts), timings, tuple(notes))


def uniform_layers(low: float, high: float, thickness: float) -> tuple[FloatArray, FloatArray]:
    """Bottoms and thicknesses of equal layers covering [low, high]."""
    n = max(1, int(np.ceil((high - low) / thickness - LAYER_COUNT_SLACK)))
    if n > MAX_LAYERS:
        raise ParameterError(f"layer thickness {thickness:g} gives {n} layers: too thin")
    bottoms = low + thickness * np.arange(n)
    return bottoms, np.full(n, thickness)


@dataclass(frozen=True)
class _Bounds:
    """What an adaptive layer must meet: the tolerance, the thickness bounds, the band fitted
    on each trial's mid-plane, and the eq. 7 threshold."""

    tolerance: float
    min_layer: float
    max_layer: float
    band: float
    relative_tolerance: float | None = DEFAULT_RELATIVE_TOLERANCE


def adaptive_layers(height: FloatArray, uv: FloatArray, bounds: _Bounds,
                    progress: Callable[[int, int], None] | None = None
                    ) -> list[tuple[float, float, FitResult]]:
    """(bottom, thickness, fit) of adaptive layers over points sorted by ``height``.

    Each layer starts from the previous thickness; it grows by `GROWTH` while the slab stays
    within the tolerance of its band's contours (fitted within tolerance / 2) and shrinks by the
    same factor when it does not, within [min_layer, max_layer].
    """
    plan: list[tuple[float, float, FitResult]] = []
    z, top, t = float(height[0]), float(height[-1]), bounds.max_layer
    total = max(1, int(np.ceil((top - z) / bounds.min_layer)))
    while z < top or not plan:
        res, ok = _try_layer(height, uv, z, t, bounds)
        if ok:
            while t < bounds.max_layer:
                bigger = min(bounds.max_layer, t * GROWTH)
                res2, ok2 = _try_layer(height, uv, z, bigger, bounds)
                if not ok2:
                    break
                t, res = bigger, res2
        else:
            while not ok and t > bounds.min_layer:
                t = max(bounds.min_layer, t / GROWTH)
                res, ok = _try_layer(height, uv, z, t, bounds)
        plan.append((z, t, res))
        z += t
        if progress:
            progress(min(total, int(np.ceil((z - height[0]) / bounds.min_layer))), total)
    return plan


def _try_layer(height: FloatArray, uv: FloatArray, bottom: float, thickness: float,
               bounds: _Bounds) -> tuple[FitResult, bool]:
    """Fit the mid-plane band within tolerance / 2; is every slab point within tolerance?"""
    mid = bottom + thickness / 2
    b0, b1 = _band(height, mid, min(bounds.band, thickness))
    res = fit_layer(uv[b0:b1], bounds.tolerance / 2, bounds.relative_tolerance, mid)
    s0, s1 = np.searchsorted(height, [bottom, bottom + thickness])
    if s1 == s0:
        return res, True
    return res, within(_model_error(uv[s0:s1], res), bounds.tolerance)


def _model_error(slab: FloatArray, res: FitResult) -> float:
    if not len(slab):
        return 0.0
    return float(distance_to_contours(slab, res.contours).max())


def _band(height: FloatArray, mid: float, width: float) -> tuple[int, int]:
    i0, i1 = np.searchsorted(height, [mid - width / 2, mid + width / 2])
    return int(i0), int(i1)


def fit_layer(points: FloatArray, tolerance: float, relative_tolerance: float | None,
              z: float) -> FitResult:
    """The fit of one layer's projected band points (a pure function: safe in any worker).

    A band with too few points gives a layer with no contour and a note, not an error.
    """
    try:
        res = fit(points, tolerance, relative_tolerance=relative_tolerance)
    except DataError as exc:
        return FitResult([], tolerance, 0.0, 0.0, np.arange(len(points)), len(points),
                         notes=(f"no contour: {exc}",), z=z)
    return replace(res, z=z)


def fit_layer_job(job: LayerJob) -> tuple[FitResult, float]:
    """Fit a layer's band (``job.slab[band]``) and measure its whole slab against the fit."""
    b0, b1 = job.band
    res = fit_layer(job.slab[b0:b1], job.tolerance, job.relative_tolerance, job.z)
    return res, _model_error(job.slab, res)


def _notes(layers: list[Layer], tolerance: float) -> list[str]:
    notes = []
    empty = [k for k, la in enumerate(layers) if not la.fit.contours and la.slab_points]
    if empty:
        notes.append(f"{len(empty)} layer(s) with points but no contour (too few or too "
                     f"scattered), e.g. layer {empty[0]}")
    over = [k for k, la in enumerate(layers) if la.fit.contours and la.model_error > tolerance]
    if over:
        notes.append(f"{len(over)} layer(s) where slab points lie beyond the tolerance of the "
                     "layer's contours (caps and ledges inside a slab, or thick layers on slopes)")
    return notes
