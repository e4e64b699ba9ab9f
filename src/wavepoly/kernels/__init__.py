"""Compiled inner loops (numba), where a loop over points is the algorithm itself.

Each kernel has a NumPy reference beside the code that calls it, and the tests compare them
on random cases. Kernels take and return plain arrays, so they know nothing of the records.
`planar` holds the loops over planar points and polylines, `surfaces` those over 3D
neighbourhoods.
"""

from .planar import (
    edge_distances,
    fewest_edges,
    group_order,
    nearest_in_grid,
    nearly_uniform_search,
    neighbour_distances,
    neighbourhood_sums,
    order_within_groups,
    segment_grid,
    sweep_cones,
    thin_blocks,
    two_means_sides,
)
from .surfaces import sheet_sides

__all__ = [
    "edge_distances",
    "fewest_edges",
    "group_order",
    "nearest_in_grid",
    "nearly_uniform_search",
    "neighbour_distances",
    "neighbourhood_sums",
    "order_within_groups",
    "segment_grid",
    "sheet_sides",
    "sweep_cones",
    "thin_blocks",
    "two_means_sides",
]
