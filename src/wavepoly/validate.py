"""Input validation shared by the stages and the readers: points, tolerances, parameters.

Every check raises `DataError` (the data) or `ParameterError` (a parameter) with one line that
names the source and the problem; nothing here imports a stage or `io`.
"""

from __future__ import annotations

import numpy as np

from .errors import DataError, ParameterError
from .types import FloatArray

#: Largest coordinate magnitude accepted: distances are computed from squared differences,
#: which overflow float64 beyond about 1e154; no scan has coordinates near this.
MAX_COORDINATE = 1e150
#: A coordinate column whose extent is below this fraction of the largest extent is constant
#: (a slice written as ``x y 0``): round-off in a file's digits, not a third dimension.
FLAT_EXTENT = 1e-12


def check_tolerance(tolerance: float, name: str = "tolerance") -> float:
    """Return ``tolerance`` as a float, or raise `ParameterError` unless it is finite and > 0."""
    try:
        value = float(tolerance)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a number, got {tolerance!r}") from None
    if not value > 0 or value == float("inf"):
        raise ParameterError(f"{name} must be a finite number > 0, got {tolerance!r}")
    return value


def check_relative_tolerance(relative_tolerance: float | None) -> float | None:
    """The eq. 7 threshold as a float > 0, or None (choose the starting level automatically)."""
    if relative_tolerance is None:
        return None
    if isinstance(relative_tolerance, str):
        raise ParameterError(f"relative_tolerance must be a number > 0 or None (automatic), "
                             f"got {relative_tolerance!r}")
    return check_tolerance(relative_tolerance, "relative_tolerance")


def column_bounds(arr: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Smallest and largest value of each column: ``arr.min(axis=0)``, ``arr.max(axis=0)``,
    one column at a time, which is some 30 times faster on an (N, 2) array."""
    cols = range(arr.shape[1])
    return (np.array([arr[:, k].min() for k in cols]),
            np.array([arr[:, k].max() for k in cols]))


def validate_points(points: object, *, source: str = "points", min_points: int = 2,
                    keep_float32: bool = False) -> FloatArray:
    """Check an array of coordinates and return it as contiguous float64 (N, 2|3), or as the
    float32 it is with ``keep_float32`` (a large cloud, widened later band by band).

    Raises `DataError` for a wrong shape, no points, fewer than ``min_points``, NaN or
    infinite values, or points that are all identical.
    """
    single = keep_float32 and getattr(points, "dtype", None) == np.float32
    try:
        arr = np.asarray(points, dtype=np.float32 if single else np.float64)
    except (TypeError, ValueError):
        raise DataError(f"{source}: coordinates are not numeric") from None
    if arr.ndim != 2 or arr.shape[1] not in (2, 3):
        raise DataError(f"{source}: expected an (N, 2) or (N, 3) array, got shape {arr.shape}")
    if len(arr) == 0:
        raise DataError(f"{source}: contains no points")
    low, high = column_bounds(arr)  # NaN propagates into both
    if not (np.isfinite(low).all() and np.isfinite(high).all()):
        bad = ~np.isfinite(arr).all(axis=1)
        first = int(np.flatnonzero(bad)[0])
        raise DataError(f"{source}: {int(bad.sum())} point(s) have NaN or infinite coordinates "
                        f"(first at row {first})")
    if len(arr) < min_points:
        raise DataError(f"{source}: only {len(arr)} point(s); at least {min_points} are needed")
    big = float(max(np.abs(low).max(), np.abs(high).max()))  # float32 cannot hold the bound
    if big > MAX_COORDINATE:
        raise DataError(f"{source}: coordinates as large as {big:.3g}; distances between "
                        f"them would overflow (at most {MAX_COORDINATE:g} is accepted)")
    if (high - low).max() == 0.0:
        raise DataError(f"{source}: all {len(arr)} points are identical")
    return np.ascontiguousarray(arr)


def as_planar(points: FloatArray, source: str = "points") -> FloatArray:
    """(N, 2) points for a 2D fit: 3D points must lie in a plane of constant x, y or z.

    A constant coordinate column (a slice written as x y 0, or Hoppe's 'p 0 x y') is dropped;
    truly 3D points raise `DataError` pointing to ``wavepoly slice`` and ``--columns``.
    """
    if points.shape[1] == 2:
        return points
    low, high = column_bounds(points)
    extent = high - low
    flat = np.flatnonzero(extent <= FLAT_EXTENT * max(float(extent.max()), 1e-300))
    if len(flat) == 0:
        raise DataError(f"{source}: points are 3D (extents {', '.join(f'{e:.4g}' for e in extent)})"
                        "; slice them with 'wavepoly slice' or pick two columns with --columns")
    keep = [k for k in range(3) if k != flat[0]]
    return validate_points(points[:, keep], source=source, min_points=3)
