"""Reading scan files, writing polygons and layer models, and the runs' reports."""

from .layers import LAYER_FORMATS, write_layers
from .readers import FORMATS, detect_format, read_mesh, read_points
from .report import (
    fit_report,
    fit_summary,
    ordering_summary,
    slice_report,
    slice_summary,
    write_report,
)
from .writers import POLYGON_FORMATS, write_ordering, write_points, write_polygons

__all__ = ["detect_format", "fit_report", "fit_summary", "FORMATS", "LAYER_FORMATS",
           "ordering_summary", "POLYGON_FORMATS", "read_mesh", "read_points", "slice_report",
           "slice_summary", "write_layers", "write_ordering", "write_points", "write_polygons",
           "write_report"]
