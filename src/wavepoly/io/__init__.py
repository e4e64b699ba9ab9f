"""Reading scan files and writing polygons."""

from .readers import FORMATS, detect_format, read_points, validate_points
from .writers import POLYGON_FORMATS, write_polygons

__all__ = ["FORMATS", "POLYGON_FORMATS", "detect_format", "read_points", "validate_points",
           "write_polygons"]
