"""The ground floor: every record that crosses a module, the guarantee's slack and the defaults.

Data flows one way: points -> `Ordering` (of `Chain` and `OrderedContour`) -> `Pyramid` (the
wavelet levels) -> `Reconstruction` -> `Contour` -> `FitResult` -> writers; for 3D clouds,
`LayerJob` (a `LayerSpec` and its band of points) -> `Layer` records in a `SliceResult`.
Nothing here imports another wavepoly module: `curves` holds the planar records, `layers`
those of slicing.
"""

from .curves import *  # noqa: F403
from .curves import __all__ as _curves
from .layers import *  # noqa: F403
from .layers import __all__ as _layers

__all__ = [*_curves, *_layers]
