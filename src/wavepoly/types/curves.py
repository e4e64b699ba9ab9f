"""Records of the planar pipeline: ordering, wavelet levels, reconstruction, contours, fits;
the guarantee's slack and the defaults."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]

#: Relative slack on the tolerance for floating-point round-off in distance computations: a
#: point at ``tolerance * (1 + SLACK)`` still counts as within the tolerance.
SLACK = 1e-9

#: Eq. 7 threshold of the relative shape error that stops the decomposition (§3); the paper
#: leaves it to the user. ``relative_tolerance=None`` chooses the starting level instead
#: (like PyWavelets' ``level=None``).
DEFAULT_RELATIVE_TOLERANCE = 0.05


def within(distance: float, tolerance: float) -> bool:
    """The guarantee's test: ``distance`` is within ``tolerance`` up to round-off (`SLACK`)."""
    return bool(distance <= tolerance * (1 + SLACK))


@dataclass(frozen=True)
class Chain:
    """One chain of linked ordering nodes: node indices in marching order, closed or open."""

    nodes: IntArray
    closed: bool

    def __len__(self) -> int:
        return int(len(self.nodes))


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
    noise: the typical spread of the points about their curves over a neighbourhood (0 for
        clean samples); it sizes the neighbourhoods.
    scatter: the points' own scatter about their curves, measured over a few scatters (at
        most ``noise``): the scale a tolerance is judged against.
    through_the_middle: whether the tolerance asked for is below the noise, so that the
        contours run through the middle of it (`wavepoly.ordering.noise.runs_through_the_middle`).
    clean: whether the scan was read as a clean sampling (`wavepoly.ordering.contours.clean_scan`):
        members then reach two radii from their contour, and outlines with stems close.
    per_radius: how many points the curves hold per radius of their length
        (`wavepoly.ordering.spacing.points_per_radius`), where noise was measured; else inf.
    """

    contours: list[OrderedContour]
    outliers: IntArray
    radius: float
    merged_walls: FloatArray = field(default_factory=lambda: np.empty((0, 2)))
    notes: tuple[str, ...] = ()
    noise: float = 0.0
    scatter: float = 0.0
    through_the_middle: bool = False
    clean: bool = False
    per_radius: float = float("inf")


@dataclass(frozen=True, repr=False)
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

    @property
    def __geo_interface__(self) -> dict:
        """A GeoJSON Polygon (closed) or LineString (open), for shapely, GeoPandas..."""
        if self.closed:
            return {"type": "Polygon", "coordinates": [_ring(self.vertices)]}
        return {"type": "LineString", "coordinates": self.vertices.tolist()}

    def to_shapely(self):
        """The contour as a shapely Polygon or LineString."""
        return _shape(self)

    def __repr__(self) -> str:
        kind = "closed" if self.closed else "open"
        return f"Contour({kind}, {self.n_vertices} vertices, max error {self.max_error:.4g})"


@dataclass(frozen=True)
class Problem:
    """One way a result's geometry is not valid: what, which contours, and where."""

    kind: str  # "self-intersection", "degenerate polygon", "crossing", "touching"
    contours: tuple[int, ...]
    where: tuple[float, float]

    def __str__(self) -> str:
        which = " and ".join(str(c) for c in self.contours)
        return (f"{self.kind} of contour{'s' if len(self.contours) > 1 else ''} {which} "
                f"at ({self.where[0]:.6g}, {self.where[1]:.6g})")


@dataclass(frozen=True)
class Validity:
    """The geometry check of a result (`wavepoly.validity.check_contours`)."""

    n_closed: int
    n_open: int
    problems: tuple[Problem, ...] = ()

    @property
    def valid(self) -> bool:
        return not self.problems

    def __str__(self) -> str:
        counts = f"{self.n_closed} closed, {self.n_open} open"
        if self.valid:
            return f"{counts}, all valid"
        return f"{counts}, {len(self.problems)} invalid: {self.problems[0]}"


@dataclass(frozen=True)
class ContourReport:
    """Per-contour figures of a fit (the report JSON holds these).

    first_piece: for a contour split at junctions into pieces, the index of the output contour
    whose report first counted the points (the pieces share them); None when not split.
    """

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
    first_piece: int | None = None


@dataclass(frozen=True, repr=False)
class FitResult:
    """Result of `wavepoly.fit` over one slice of 2D points.

    contours: the output contours (closed ones counter-clockwise when outer, clockwise for holes).
    parents: for each contour, the index of the closed contour that contains it, or -1.
    tolerance: the shape tolerance that every non-outlier input point is within.
    max_error / mean_error: achieved distances of the input points to the output.
    outliers: indices of input points outside the guarantee (reported by the ordering).
    reports: per-contour figures; timings: seconds per stage; notes: remarks of the stages.
    validity: the geometry check (`wavepoly.validity.check_contours`).
    suggested_tolerance: set when the tolerance is below the scan's scatter (the curves then
        zigzag through the noise or lose points as outliers) or its point spacing (nearly every
        point a vertex): a tolerance that gives clean curves.
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
    validity: Validity | None = None
    suggested_tolerance: float | None = None

    @property
    def n_vertices(self) -> int:
        return sum(c.n_vertices for c in self.contours)

    @property
    def __geo_interface__(self) -> dict:
        """GeoJSON geometry: a MultiPolygon of the outers with their holes, a MultiLineString
        of the open contours, or a GeometryCollection of both."""
        parents = self.parents or [-1] * len(self.contours)
        depth = nesting_depth(parents)
        polygons = [[_ring(c.vertices), *(_ring(h.vertices) for j, h in enumerate(self.contours)
                                          if parents[j] == i and h.closed)]
                    for i, c in enumerate(self.contours) if c.closed and depth[i] % 2 == 0]
        lines = [c.vertices.tolist() for c in self.contours if not c.closed]
        parts = ([{"type": "MultiPolygon", "coordinates": polygons}] if polygons else []) + (
            [{"type": "MultiLineString", "coordinates": lines}] if lines else [])
        return parts[0] if len(parts) == 1 else {"type": "GeometryCollection",
                                                 "geometries": parts}

    def to_shapely(self):
        """The contours as one shapely geometry (see ``__geo_interface__``)."""
        return _shape(self)

    def __repr__(self) -> str:
        validity = f"; {self.validity}" if self.validity is not None else ""
        return (f"FitResult({len(self.contours)} contours{validity}; {self.n_vertices} "
                f"vertices; max error {self.max_error:.4g} (tolerance {self.tolerance:.4g}); "
                f"{len(self.outliers)} outliers of {self.n_points} points)")


def nesting_depth(parents: list[int]) -> list[int]:
    """Number of enclosing closed contours of each contour (even: outer or island, odd: hole)."""
    depth = []
    for i in range(len(parents)):
        d, p = 0, parents[i]
        while p >= 0:
            d, p = d + 1, parents[p]
        depth.append(d)
    return depth


def _ring(vertices: FloatArray) -> list[list[float]]:
    """A closed ring's coordinates, the first repeated at the end (GeoJSON)."""
    pts = vertices.tolist()
    return pts + pts[:1]


def _shape(obj):
    import shapely.geometry

    return shapely.geometry.shape(obj.__geo_interface__)


# ---------------------------------------------------------------------------------------------
# §3: the wavelet levels of one contour


@dataclass(frozen=True)
class LevelErrors:
    """Eq. 6-7 at one level: per segment of the coarse control polygon."""

    level: int
    shape: FloatArray  # E_i(s): largest distance of the segment's ordered points
    relative: FloatArray  # E_i(r) = E_i(s) / length(S_i)

    def violates(self, tolerance: float, relative_tolerance: float) -> bool:
        """True when some segment breaks both the shape and the relative tolerance (§3)."""
        return bool(np.any((self.shape > tolerance) & (self.relative > relative_tolerance)))


@dataclass(frozen=True)
class Pyramid:
    """The wavelet levels of one contour.

    coefficients[j]: control points at level j, for coarsest <= j <= finest.
    details[j]: wavelet coefficients d[j] that lift level j to j + 1 (eq. 11).
    fine_index: position of each ordered point among the finest level's control points.
    errors: eq. 6-7 figures of each level that was examined.
    """

    closed: bool
    finest: int
    coarsest: int
    coefficients: dict[int, FloatArray]
    details: dict[int, FloatArray]
    fine_index: IntArray
    errors: dict[int, LevelErrors] = field(default_factory=dict)

    @property
    def levels_decomposed(self) -> int:
        return self.finest - self.coarsest


# ---------------------------------------------------------------------------------------------
# §4: the reconstruction of one contour


@dataclass(frozen=True)
class Msc:
    """A multi-storable coefficient run: inner coefficients ``first..last`` of ``level``.

    start / span: parameter interval covered (span may wrap past 1 on a closed contour).
    """

    level: int
    first: int
    last: int
    start: float
    span: float
    points: FloatArray
    params: FloatArray


@dataclass(frozen=True)
class Reconstruction:
    """The polygon of one contour and how it was made."""

    vertices: FloatArray
    params: FloatArray
    closed: bool
    mscs: list[Msc]
    start_level: int
    wavelet_vertices: int  # after MSC assembly and repair, before the selection
    max_error: float
    mean_error: float

    @property
    def mscs_per_level(self) -> dict[int, int]:
        out: dict[int, int] = {}
        for m in self.mscs:
            out[m.level] = out.get(m.level, 0) + 1
        return out


__all__ = ["Chain", "Contour", "ContourReport", "DEFAULT_RELATIVE_TOLERANCE", "FitResult",
           "FloatArray", "IntArray", "LevelErrors", "Msc", "OrderedContour", "Ordering",
           "Problem", "Pyramid", "Reconstruction", "SLACK", "Validity", "nesting_depth",
           "within"]
