"""Records of slicing: a cloud's surface, a layer's job, layers and the layer model."""

from __future__ import annotations

from dataclasses import dataclass, field

from .curves import Contour, FitResult, FloatArray, _shape


@dataclass(frozen=True)
class SurfaceSamples:
    """A cloud in plane coordinates with what is known of its surface at each point.

    uvh: (N, 3) plane coordinates and height, sorted by height; normals: (N, 3) unit normals
    of the local tangent planes; low, high: height range of each point's neighbourhood;
    radius: the neighbourhood's radius; flatness: its smallest principal variance over the
    middle one (0 on a plane, larger across an edge; inf where a shallow point's wider fit
    spans an edge); offset: each point's signed distance
    from its tangent plane (through its neighbourhood's centroid), along its normal;
    slope_score: where the surface is shallow, its slope over the slope's standard error
    (from a wider neighbourhood, which then also gives the other fields); inf where steep;
    bend: where shallow, the height field's second-order term along its steepest direction
    (height ≈ slope · s + bend · s² at a distance s up the slope), 0 where steep; support:
    the half-height about each point of all the points its fields depend on (its neighbours'
    neighbourhoods, or its wider one where shallow).
    """

    uvh: FloatArray
    normals: FloatArray
    low: FloatArray
    high: FloatArray
    radius: FloatArray
    flatness: FloatArray
    offset: FloatArray
    slope_score: FloatArray
    bend: FloatArray
    support: FloatArray


@dataclass(frozen=True)
class LayerSpec:
    """A layer's parameters: all that its fit needs besides its band of the cloud (small, it
    travels to a worker ahead of the points).

    bottom, thickness: the slab [bottom, bottom + thickness) that the layer stands for;
    low, high: the heights that the band of points covers (-inf / inf where it reaches the
    cloud's ends): a point's neighbourhood is complete when it lies within them;
    section_band: only slab points within ``section_band / 2`` of the mid-plane give section
    points (None: the whole slab); max_gap: the widest gap between open pieces to bridge.
    """

    bottom: float
    thickness: float
    low: float
    high: float
    tolerance: float
    relative_tolerance: float | None
    section_band: float | None = None
    max_gap: float = 0.0

    @property
    def z(self) -> float:
        """Height of the layer's mid-plane."""
        return self.bottom + 0.5 * self.thickness


@dataclass(frozen=True)
class LayerJob:
    """One layer's fit: its parameters and its band of the cloud, (u, v, height) sorted by
    height, that holds the slab and the points around it (it travels to a worker process)."""

    spec: LayerSpec
    points: FloatArray


@dataclass(frozen=True)
class ErrorJob:
    """One layer's staircase error: its slab's points (u, v, height) and the contours of the
    layer and of its neighbours (None: no layer there); farther_below / farther_above: the
    layers beyond them as (bottom, top, contours), outward, ending with (height, height,
    None) at the end of the stack, where the error reaches past the neighbours
    (`wavepoly.staircase.farther_layers`). ``outside``: measure instead how far the slab's
    points lie outside the region of ``own`` (0 within it), all but a few."""

    slab: FloatArray
    bottom: float
    top: float
    own: list[Contour]
    below: list[Contour] | None
    above: list[Contour] | None
    outside: bool = False
    farther_below: tuple = ()
    farther_above: tuple = ()


@dataclass(frozen=True)
class TileSummary:
    """One tile of a cloud: its file, point count and height range along the slicing axis."""

    path: str
    count: int
    low: float
    high: float


@dataclass(frozen=True, repr=False)
class Layer:
    """One layer of the model.

    bottom, thickness: the slab [bottom, bottom + thickness) along the axis that it stands for.
    band: (low, high) heights of the points whose section points were fitted.
    fit: the layer's fit of its mid-plane section, in plane coordinates (see
        `SliceResult.basis`), with ``fit.z`` the mid-plane height.
    slab_points: cloud points in the slab; model_error: the largest distance of a slab point
        to the surface of the stacked layers, the staircase error (inf when the layer has
        points and no contour).
    """

    bottom: float
    thickness: float
    band: tuple[float, float]
    fit: FitResult
    slab_points: int
    model_error: float

    @property
    def z(self) -> float:
        """Height of the layer's mid-plane."""
        return self.bottom + 0.5 * self.thickness

    @property
    def top(self) -> float:
        return self.bottom + self.thickness

    @property
    def __geo_interface__(self) -> dict:
        """A GeoJSON Feature: the layer's contours in plane coordinates, its heights and
        errors as properties."""
        return {"type": "Feature", "geometry": self.fit.__geo_interface__,
                "properties": {"z": self.z, "bottom": self.bottom, "thickness": self.thickness,
                               "vertices": self.fit.n_vertices, "slab_points": self.slab_points,
                               "model_error": self.model_error}}

    def to_shapely(self):
        """The layer's contours as one shapely geometry."""
        return _shape(self.fit)

    def __repr__(self) -> str:
        return (f"Layer(z={self.z:.4g}, thickness {self.thickness:.4g}, "
                f"{len(self.fit.contours)} contours, {self.fit.n_vertices} vertices, "
                f"model error {self.model_error:.4g})")


@dataclass(frozen=True, repr=False)
class SliceResult:
    """Layers bottom to top. ``basis`` rows are (e1, e2, axis): a point p has plane coordinates
    (p . e1, p . e2) and height p . axis."""

    layers: list[Layer]
    basis: FloatArray
    tolerance: float
    adaptive: bool
    n_points: int
    timings: dict[str, float] = field(default_factory=dict)
    notes: tuple[str, ...] = ()
    engine: dict = field(default_factory=dict)  # where the layers were fitted (the report)

    @property
    def model_error(self) -> float:
        """Largest distance of a cloud point to the surface of the stacked layers, the 3D
        staircase error (`wavepoly.staircase`)."""
        errs = [la.model_error for la in self.layers if la.slab_points]
        return max(errs) if errs else 0.0

    @property
    def n_vertices(self) -> int:
        return sum(la.fit.n_vertices for la in self.layers)

    def to_world(self, xy: FloatArray, height: float) -> FloatArray:
        """3D points of plane coordinates ``xy`` at ``height`` along the axis."""
        return xy @ self.basis[:2] + height * self.basis[2]

    @property
    def __geo_interface__(self) -> dict:
        """A GeoJSON FeatureCollection of the layers (``geopandas.GeoDataFrame.from_features``
        takes it)."""
        return {"type": "FeatureCollection",
                "features": [la.__geo_interface__ for la in self.layers]}

    def to_shapely(self) -> list:
        """Each layer's contours as one shapely geometry, bottom to top."""
        return [la.to_shapely() for la in self.layers]

    def __repr__(self) -> str:
        kind = "adaptive" if self.adaptive else "uniform"
        return (f"SliceResult({len(self.layers)} {kind} layers of {self.n_points} points, "
                f"{self.n_vertices} vertices, model error {self.model_error:.4g} "
                f"(tolerance {self.tolerance:.4g}))")


__all__ = ["ErrorJob", "Layer", "LayerJob", "LayerSpec", "SliceResult", "SurfaceSamples",
           "TileSummary"]
