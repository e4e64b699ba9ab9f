"""wavepoly: concise polygons within a guaranteed tolerance from scanned, unorganized points.

The method of "Constructing 2D curves from scanned data points using B-spline wavelets":
ordering by tangent-vector neighbourhood marching (§2), cubic B-spline wavelet decomposition
(§3) and coarse-to-fine reconstruction from multi-storable coefficients (§4), with every output
verified against the input points; 3D clouds are sliced into a layer model (§5).

>>> import wavepoly
>>> from wavepoly.samples import glyph_outlines, sample_rings
>>> pts = sample_rings(glyph_outlines("L").rings, spacing=0.02, noise=0.01, seed=0)
>>> result = wavepoly.fit(pts, tolerance=0.08)
>>> result.max_error <= 0.08
True
"""

from importlib.metadata import PackageNotFoundError, version

from .errors import DataError, EngineError, ParameterError, ReadNote, WavepolyError
from .fit import fit
from .io import (
    LAYER_FORMATS,
    POLYGON_FORMATS,
    detect_format,
    fit_report,
    fit_summary,
    ordering_summary,
    read_mesh,
    read_points,
    slice_report,
    slice_summary,
    write_layers,
    write_ordering,
    write_points,
    write_polygons,
    write_report,
)
from .io.tiles import expand_sources, read_cloud
from .io.units import UNITS
from .ordering import curve_spacing, median_spacing, order_points
from .slicing import slice_cloud, slice_mesh
from .tiled import dask_available, scheduler_from_environment, slice_tiles
from .types import (
    DEFAULT_RELATIVE_TOLERANCE,
    Contour,
    ContourReport,
    FitResult,
    Layer,
    OrderedContour,
    Ordering,
    SliceResult,
)
from .validate import as_planar, validate_points

try:
    __version__ = version("wavepoly")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0"

__all__ = ["__version__", "as_planar", "Contour", "ContourReport", "curve_spacing",
           "dask_available", "DataError", "DEFAULT_RELATIVE_TOLERANCE", "detect_format",
           "EngineError", "expand_sources", "fit", "fit_report", "fit_summary", "FitResult",
           "Layer", "LAYER_FORMATS", "median_spacing", "order_points", "OrderedContour",
           "Ordering", "ordering_summary", "ParameterError", "POLYGON_FORMATS", "read_cloud",
           "read_mesh", "read_points", "ReadNote", "scheduler_from_environment", "slice_cloud",
           "slice_mesh", "slice_report", "slice_summary", "slice_tiles", "SliceResult", "UNITS",
           "validate_points", "WavepolyError", "write_layers", "write_ordering", "write_points",
           "write_polygons", "write_report"]
