"""A ring that stands for two walls closer than the radius: the two rings of an annulus.

Two walls less than a radius apart all the way round (a thin-walled tube's section, two
rings one inside the other a tolerance apart) fill every neighbourhood with both. The march
follows them as one chain down the middle and closes it: every point lies within half the
gap of it, so the tolerance holds, but the region it bounds is the tube's bore and wall
together, and a slicer fills the tube. As a stem's two walls are drawn apart
(`wavepoly.ordering.passes`), the ring's members tell its two walls apart: across each
stretch of it their offsets fall into two sharp groups, one per wall, the test that splits a
node between two walls (`wavepoly.ordering.walls`). Where they do all round, the ring is
drawn as two, each at its wall's mean offset: an outline and its hole.

A wall sampled on one side only gives one group (a flat band of offsets where the chain
chords a bend, a bell where it is noisy), and stays one ring; so does a ring whose walls
part somewhere (a thin part's sides, a slit walked out and back), which the stems and folds
read.
"""

from __future__ import annotations

import numpy as np
import shapely

from ..geometry import curve_line, nearest_segment, polyline_segments
from ..kernels import two_means_sides
from ..types import FloatArray, OrderedContour
from .passes import SMOOTH_NODES
from .untangle import share_members
from .walls import EMPTY_MIDDLE, SIDE_SHARE, SIDE_SHARPNESS, SPLIT_ROUNDS

#: The members' offsets are grouped over stretches of the ring this many radii long: a
#: neighbourhood's length, holding some six points of each wall at a third of a radius apart...
STRETCH = 2.0
#: ... or longer, to hold this many members on average (eight of each wall) where the points
#: are sparse (a slice's section points, spaced half a radius apart)...
STRETCH_MEMBERS = 16
#: ... and each needs at least this many to be read.
STRETCH_POINTS = 6
#: A ring is read in at least this many stretches: "all round" is no test of a small ring
#: read in a few, whose stretches each span a bend or a corner (a blob ten pixels across,
#: traced, split into a ring and a phantom second one).
MIN_STRETCHES = 8
#: The bend fitted across a stretch is damped by this (in squared radii): only a stretch
#: with next to no members along it keeps no bend.
BEND_RIDGE = 1e-6
#: Two walls all round: at least this share of the ring's stretches hold members on both
#: sides (a wall that stops leaves one side empty where it does)...
BOTH_SIDES_SHARE = 0.9
#: ... and at least this share find them in two sharp groups (at a corner the ring cuts,
#: both walls' offsets sweep across the stretch together: a square tube's four corners take
#: up to a fifth of its stretches)...
TWO_WALL_SHARE = 0.7
#: ... and their typical (median) stretch is this sharp at least: a bell of scatter about one
#: wall, split in two, gives 0.38, and a stretch of a dozen members passes 0.25 by chance
#: (a noisy triangle five tolerances across, read as a clean sample); two walls with
#: noise a sixteenth of the gap between them give about 0.1.
TYPICAL_SHARPNESS = 0.15
#: An offset ring may fold into small loops where its chain bends sharply; those are cut off
#: where they hold less than this share of its area (a fold of a node or two: about 10^-5).
FOLDS_SHARE = 0.01
#: Walls closer than this many radii are one curve: within a tenth of a tolerance of the
#: ring, and a chain's chords over a curve's bend spread a wall's own offsets as far.
MIN_GAP = 0.2


def split_annuli(contours: list[OrderedContour], points: FloatArray, radius: float
                 ) -> list[OrderedContour]:
    """The contours, each closed one whose members lie on two walls closer than the radius
    all round replaced by the annulus's two rings (`_two_walls`), where both are valid
    polygons, one inside the other, and cross no other contour.

    Parameters
    ----------
    contours : the ordered contours of a clean scan; only the closed ones are read.
    points : the input points (the contours' members index them).
    radius : the neighbourhood radius of the ordering.

    Returns
    -------
    The contours, each such ring replaced by its outer and inner rings.

    Examples
    --------
    Two circles 0.08 apart, each sampled every 0.01, read at a radius of 0.1 as one ring down
    the middle.

    >>> t = np.linspace(0, 2 * np.pi, 600, endpoint=False)
    >>> circle = np.column_stack([np.cos(t), np.sin(t)])
    >>> pts = np.vstack([circle, 1.08 * circle])
    >>> middle = OrderedContour(1.04 * circle[::20], True, np.arange(len(pts)))
    >>> rings = split_annuli([middle], pts, 0.1)
    >>> [round(float(np.hypot(*c.points.T).mean()), 2) for c in rings]
    [1.08, 1.0]
    """
    out: list[OrderedContour] = []
    for k, c in enumerate(contours):
        rings = _two_walls(c, points, radius) if c.closed and len(c.points) >= 4 else None
        if rings is not None and _clear(rings, [o for j, o in enumerate(contours) if j != k]):
            out += share_members(rings, c.members, points, closed=True)
        else:
            out.append(c)
    return out


def _two_walls(c: OrderedContour, points: FloatArray, radius: float
               ) -> list[FloatArray] | None:
    """The ring's two walls, outer first, where its members lie on both sides of it in
    `BOTH_SIDES_SHARE` of its stretches, and fall into two sharp groups across it in
    `TWO_WALL_SHARE` (`TYPICAL_SHARPNESS` in the median); None elsewhere."""
    xy = _smoothed_ring(c.points)
    a, b = polyline_segments(xy, True)
    length = np.linalg.norm(b - a, axis=1)
    arc = np.concatenate([[0.0], np.cumsum(length)])
    stretches = min(int(arc[-1] // (STRETCH * radius)), len(c.members) // STRETCH_MEMBERS)
    if stretches < MIN_STRETCHES:
        return None
    members = points[c.members]
    seg, _ = nearest_segment(members, xy, True)
    along, offset = _along_and_offset(members, a[seg], b[seg], length[seg])
    stretch = np.minimum(((arc[seg] + along) / arc[-1] * stretches).astype(np.intp),
                         stretches - 1)
    counts = np.bincount(stretch, minlength=stretches)
    offset = offset - _common_bend(stretch, (arc[seg] + along) / radius, offset, stretches)
    low, high, spread_low, spread_high, share, middle = _sides(stretch, offset, stretches)
    gap = high - low
    both = ((counts >= STRETCH_POINTS) & (gap >= MIN_GAP * radius)
            & (share >= SIDE_SHARE) & (share <= 1 - SIDE_SHARE))
    sharpness = np.maximum(spread_low, spread_high) / np.maximum(gap, 1e-300)
    two = both & (sharpness < SIDE_SHARPNESS) & (middle < EMPTY_MIDDLE)
    if (both.mean() < BOTH_SIDES_SHARE or two.mean() < TWO_WALL_SHARE
            or np.median(sharpness[both]) > TYPICAL_SHARPNESS):
        return None
    node = _nearest_passed(np.minimum((arc[:-1] / arc[-1] * stretches).astype(np.intp),
                                      stretches - 1), np.flatnonzero(two))
    normal = _node_normals(xy)
    low_ring, high_ring = xy + low[node, None] * normal, xy + high[node, None] * normal
    rings = [_unfolded(low_ring), _unfolded(high_ring)]
    if any(r is None for r in rings):
        return None
    return sorted(rings, key=lambda r: -shapely.Polygon(r).area)


def _unfolded(ring: FloatArray) -> FloatArray | None:
    """The ring less the small loops it folds into where it is offset from a chain that
    bends more sharply than the offset (a zigzag's remnant that the smoothing left): the
    outline of its largest part, where that holds all but `FOLDS_SHARE` of the area; None
    where the ring does not fold so slightly."""
    polygon = shapely.Polygon(ring)
    if polygon.is_valid:
        return ring
    parts = [p for p in shapely.get_parts(shapely.make_valid(polygon))
             if isinstance(p, shapely.Polygon)]
    if not parts:
        return None
    largest = max(parts, key=lambda p: p.area)
    if largest.area < (1 - FOLDS_SHARE) * sum(p.area for p in parts):
        return None
    out = shapely.get_coordinates(largest.exterior)[:-1]
    # in the chain's own sense of travel, as the ring that did not fold keeps it
    same = largest.exterior.is_ccw == shapely.LinearRing(ring).is_ccw
    return out if same else out[::-1]


def _nearest_passed(stretch: np.ndarray, passed: np.ndarray) -> np.ndarray:
    """For each node's ``stretch``, the nearest of the sorted stretches that ``passed`` the
    two-walls test (its own where it did; the lower on a tie): a node where one wall's points
    thin out takes the walls' offsets of the stretch beside it."""
    right = np.minimum(np.searchsorted(passed, stretch), len(passed) - 1)
    left = np.maximum(right - 1, 0)
    nearer_left = np.abs(stretch - passed[left]) <= np.abs(passed[right] - stretch)
    return passed[np.where(nearer_left, left, right)]


def _sides(stretch: np.ndarray, offset: FloatArray, k: int) -> tuple[FloatArray, ...]:
    """Two-means of each stretch's offsets (`wavepoly.kernels.two_means_sides`): the low and
    high sides' means and spreads, the share on the high side, the share in the middle."""
    ones = np.ones(len(offset))
    return two_means_sides(stretch, offset, ones, np.zeros(len(offset)), k, SPLIT_ROUNDS)


def _common_bend(stretch: np.ndarray, s: FloatArray, offset: FloatArray, k: int) -> FloatArray:
    """Each member's share of the bend its stretch's two walls take together away from the
    ring: a parabola in the arc length ``s`` (in radii), fitted by least squares to the
    offsets less their side's mean. Where the ring cuts a corner or a bend, both walls'
    offsets sweep across the stretch alike, and that sweep, not the walls, would blur each
    side."""
    low, high, *_ = _sides(stretch, offset, k)
    side = np.where(offset > 0.5 * (low + high)[stretch], high[stretch], low[stretch])
    u = s - (np.bincount(stretch, s, k) / np.maximum(np.bincount(stretch, None, k), 1))[stretch]
    powers = np.stack([np.ones_like(u), u, u * u], axis=1)
    gram = np.zeros((k, 3, 3))
    rhs = np.zeros((k, 3))
    for i in range(3):
        rhs[:, i] = np.bincount(stretch, powers[:, i] * (offset - side), k)
        for j in range(3):
            gram[:, i, j] = np.bincount(stretch, powers[:, i] * powers[:, j], k)
    gram += BEND_RIDGE * np.eye(3)  # a stretch of few members keeps a flat fit
    coef = np.linalg.solve(gram, rhs[..., None])[..., 0]
    return np.einsum("ij,ij->i", powers, coef[stretch])


def _smoothed_ring(xy: FloatArray) -> FloatArray:
    """The closed chain averaged over `SMOOTH_NODES` nodes each side: each node of a chain
    down the middle of two walls is a centroid pulled towards one of them, and offsets taken
    across its zigzag would blur each wall's."""
    k = min(SMOOTH_NODES, (len(xy) - 1) // 2)
    return np.mean([np.roll(xy, i, axis=0) for i in range(-k, k + 1)], axis=0)


def _along_and_offset(p: FloatArray, a: FloatArray, b: FloatArray, length: FloatArray
                      ) -> tuple[FloatArray, FloatArray]:
    """Each point's distance along its segment a-b (clipped to it) and its signed offset
    across it (positive to the left of a -> b)."""
    d = (b - a) / np.maximum(length, 1e-300)[:, None]
    rel = p - a
    along = np.clip(np.einsum("ij,ij->i", rel, d), 0.0, length)
    return along, d[:, 0] * rel[:, 1] - d[:, 1] * rel[:, 0]


def _node_normals(xy: FloatArray) -> FloatArray:
    """The unit left normal at each node of a closed chain (of the chord between its
    neighbours)."""
    d = np.roll(xy, -1, axis=0) - np.roll(xy, 1, axis=0)
    d /= np.maximum(np.linalg.norm(d, axis=1), 1e-300)[:, None]
    return np.column_stack([-d[:, 1], d[:, 0]])


def _clear(rings: list[FloatArray], others: list[OrderedContour]) -> bool:
    """Whether the outer ring holds the inner one, both are valid polygons, and neither meets
    another contour."""
    outer, inner = (shapely.Polygon(r) for r in rings)
    if not (outer.is_valid and inner.is_valid and outer.contains(inner)):
        return False
    lines = np.array([curve_line(c.points, c.closed) for c in others], dtype=object)
    return not any(shapely.intersects(shapely.LinearRing(r), lines).any() for r in rings)
