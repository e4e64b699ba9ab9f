"""The small typed records that the pipeline's stages hand to each other.

Data flows one way: points -> `Ordering` (of `OrderedContour`) -> wavelet levels -> `Contour`
-> `FitResult` -> writers; for 3D clouds, `Layer` records in a `SliceResult`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]


@dataclass(frozen=True)
class OrderedContour:
    """One contour found by the ordering stage (paper §2).

    points: (k, 2) ordered, thinned points along the contour.
    closed: whether the contour closes on itself.
    members: indices into the input points of every point this contour stands for.
    """

    points: FloatArray
    closed: bool
    members: IntArray


@dataclass(frozen=True)
class Ordering:
    """Result of `wavepoly.ordering.order_points`.

    contours: the ordered contours.
    outliers: indices of input points that belong to no contour.
    radius: the neighbourhood radius actually used (may be wider than asked, see `notes`).
    merged_walls: (m, 2) positions where two nearby walls appear merged into one contour.
    notes: human-readable remarks (radius widened, walls merged, ...).
    """

    contours: list[OrderedContour]
    outliers: IntArray
    radius: float
    merged_walls: FloatArray = field(default_factory=lambda: np.empty((0, 2)))
    notes: tuple[str, ...] = ()


@dataclass(frozen=True)
class Contour:
    """A polygon (closed) or polyline (open) in the output.

    vertices: (k, 2) vertices in order; a closed contour does not repeat its first vertex.
    closed: polygon (True) or polyline (False).
    max_error / mean_error: distance of the contour's own input points to it.
    """

    vertices: FloatArray
    closed: bool
    max_error: float = 0.0
    mean_error: float = 0.0

    @property
    def n_vertices(self) -> int:
        return int(len(self.vertices))

    @property
    def signed_area(self) -> float:
        """Shoelace area: > 0 for counter-clockwise closed contours, 0 for open ones."""
        if not self.closed or len(self.vertices) < 3:
            return 0.0
        x, y = self.vertices[:, 0], self.vertices[:, 1]
        return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


@dataclass(frozen=True)
class ContourReport:
    """Per-contour figures of a fit (the report JSON holds these)."""

    input_points: int
    ordered_points: int
    closed: bool
    levels_decomposed: int
    finest_level: int
    coarsest_level: int
    mscs_per_level: dict[int, int]
    wavelet_vertices: int
    final_vertices: int
    max_error: float
    mean_error: float


@dataclass(frozen=True)
class FitResult:
    """Result of `wavepoly.fit` over one slice of 2D points.

    contours: the output contours (closed ones counter-clockwise when outer, clockwise for holes).
    parents: for each contour, the index of the closed contour that contains it, or -1.
    tolerance: the shape tolerance that every non-outlier input point is within.
    max_error / mean_error: achieved distances of the input points to the output.
    outliers: indices of input points outside the guarantee (reported by the ordering).
    reports: per-contour figures; timings: seconds per stage; notes: remarks of the stages.
    """

    contours: list[Contour]
    tolerance: float
    max_error: float
    mean_error: float
    outliers: IntArray
    n_points: int
    parents: list[int] = field(default_factory=list)
    reports: list[ContourReport] = field(default_factory=list)
    timings: dict[str, float] = field(default_factory=dict)
    notes: tuple[str, ...] = ()
    z: float | None = None

    @property
    def n_vertices(self) -> int:
        return sum(c.n_vertices for c in self.contours)
