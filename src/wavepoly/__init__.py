"""wavepoly: concise polygons within a guaranteed tolerance from scanned, unorganized points.

The method of "Constructing 2D curves from scanned data points using B-spline wavelets":
ordering by tangent-vector neighbourhood marching (§2), cubic B-spline wavelet decomposition
(§3) and coarse-to-fine reconstruction from multi-storable coefficients (§4), with every output
verified against the input points.

>>> import wavepoly
>>> from wavepoly.samples import glyph_outlines, sample_rings
>>> pts = sample_rings(glyph_outlines("L").rings, spacing=0.02, noise=0.01, seed=0)
>>> result = wavepoly.fit(pts, tolerance=0.08)
>>> result.max_error <= 0.08
True
"""

from importlib.metadata import PackageNotFoundError, version

from .errors import DataError, ParameterError, WavepolyError
from .fit import fit
from .io import read_points, write_polygons
from .ordering import order_points
from .types import Contour, ContourReport, FitResult, OrderedContour, Ordering

try:
    __version__ = version("wavepoly")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0"

__all__ = ["Contour", "ContourReport", "DataError", "FitResult", "OrderedContour", "Ordering",
           "ParameterError", "WavepolyError", "__version__", "fit", "order_points",
           "read_points", "write_polygons"]
