"""Slits or strokes: whether the stems hanging off a cycle of open pieces are two walls.

Where a slit or a limb narrower than the radius is cut into an outline, the march follows its
two walls as one chain, a stem (`wavepoly.ordering.stems`). A line drawing's stroke meets a
ring at a T junction too, and must stay a stroke. The points tell them apart: a uniform
sampling puts twice as many points per length on two merged walls as on the cycle's one wall,
and as many on one stroke; and a slit's walls part where it opens into the outline, so that
the cycle turns back there (a hairpin) and the stem runs on between its arms.
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.spatial import cKDTree

from ..geometry import nearest_of_segments, polyline_length
from ..types import FloatArray, IntArray
from .passes import smoothed

#: Stems hold at least this many times the points per length of their cycle: a uniform
#: sampling puts twice as many on two merged walls, and as many on one stroke.
STEM_DENSITY = 1.5
#: A stem whose root sits where the cycle turns back, and that runs on the other way
#: (`_at_hairpins`: a slit whose walls part into the cycle), need hold only this many times
#: the cycle's points per length: where a slit narrows below a pixel, a bitmap's trace holds
#: one wall in places, and such stems held 1.3 x (a line drawing's strokes 1.0).
SLIT_DENSITY = 1.2
#: Stems whose points lie this many times as far from them as the ring's from the ring (the
#: median), two walls to either side of their chain, need hold only `SLIT_DENSITY` x the
#: ring's points too: such slits held 1.23-1.36 x the points and spread 1.30-1.73 x (bitmap
#: silhouettes with noise), a line drawing's strokes 1.18-1.33 x and 0.78-1.10 x (Goldi,
#: Fishi, fish.txt; one of 1.39 x held 1.07 x the points).
SLIT_SPREAD = 1.25
#: A ring whose points lie on it (an exact sampling's ordered points) spreads at least this
#: many radii, so that the ratio is finite.
SPREAD_FLOOR = 1e-3
#: The cycle's arms and the stem are followed this many radii from the root...
HAIRPIN_REACH = 3.0
#: ... the arms run within this many degrees of each other (a wedge slit's walls part at up
#: to 70 degrees, zigzags and all, over those radii)...
HAIRPIN_ARMS = 90.0
#: ... and the stem within this many degrees of the way back between them.
HAIRPIN_STEM = 50.0
#: Stems are measured over the denser half of their stretches this many radii long
#: (`_denser_half`): a dozen points or more on one wall sampled at 3 per radius.
STEM_WINDOW = 4.0
#: A stem whose path is this many times as long as its averaged path zigzags between its
#: walls, and is measured along the averaged one (a limb 1.5 tolerances wide on a noisy bitmap:
#: 2.5 x).
ZIGZAG = 1.5
#: A ring's points are counted in windows of this many radii (some 20 points each on a
#: uniform sampling of 3 spacings per radius, so that chance varies a count by a fifth)...
DENSITY_WINDOW = 8.0
#: ... and the sampling is even when the densest decile of windows holds at most this many
#: times as many points per length as the sparsest: a scan's uniform sampling, not a laser
#: map's, whose density falls with the range (there a stem is no sign of two walls).
EVEN_SAMPLING = 3.0
#: On an uneven sampling (a turntable scan's far side holds a quarter of the near side's
#: points per length) the stems are measured against the cycle's walls within this many radii
#: of them, which a smooth change of density leaves alike, and must spread `SLIT_SPREAD` x as
#: far as the cycle's points too: the slits of silhouettes thinned so held 1.5-4.0 x the points
#: of the walls beside them and spread 1.8 x or more.
LOCAL_REACH = 2 * DENSITY_WINDOW


def stems_are_slits(paths: dict[int, list[FloatArray]], walk: list[tuple[int, FloatArray]],
                    members: FloatArray, radius: float) -> bool:
    """Whether a cycle's stems are two walls merged into one chain, not strokes.

    The cycle must be sampled evenly (`EVEN_SAMPLING`), and its stems together hold
    `STEM_DENSITY` x its points per length, measured over their denser half (`_denser_half`;
    a line drawing's strokes hold 1.0 together, 1.2 over their denser half when sampled at 3
    points per radius), or `SLIT_DENSITY` x where each runs on from a hairpin of the cycle
    (`_at_hairpins`) or where their points spread `SLIT_SPREAD` x as far about them as the
    ring's about it (`_spread_ratio`). A stem that zigzags between its walls, twice as long
    as they are, is measured along its averaged path (`_middle`).

    Parameters
    ----------
    paths : each stem as a polyline from its root on the cycle, by the root's node.
    walk : the cycle's edges in order, each as (its start node, its polyline along the walk).
    members : the points of the cycle and its stems.
    radius : the neighbourhood radius of the ordering.
    """
    lines = [xy for _, xy in walk] + [_middle(p) for ps in paths.values() for p in ps]
    label = np.concatenate([np.full(len(xy) - 1, k) for k, xy in enumerate(lines)])
    a = np.vstack([xy[:-1] for xy in lines])
    b = np.vstack([xy[1:] for xy in lines])
    seg_length = np.linalg.norm(b - a, axis=1)
    seg, dist = nearest_of_segments(members, a, b)
    near = dist <= radius
    seg, dist = seg[near], dist[near]
    count = np.bincount(seg, minlength=len(a))
    ring = label < len(walk)
    wide = _spread_ratio(dist, ring[seg], radius) >= SLIT_SPREAD
    window = STEM_WINDOW * radius
    stem_density = _denser_half(count[~ring], seg_length[~ring], label[~ring], window)
    if not _even(seg[seg < ring.sum()], seg_length[ring], radius):
        beside = ring & _near(a, b, np.vstack(lines[len(walk):]), LOCAL_REACH * radius)
        return wide and bool(stem_density >= STEM_DENSITY * _density(count, seg_length, beside))
    least = SLIT_DENSITY if wide or _at_hairpins(paths, walk, radius) else STEM_DENSITY
    return bool(stem_density >= least * _density(count, seg_length, ring))


def _density(count: FloatArray, seg_length: FloatArray, pick: np.ndarray) -> float:
    """Points per length of the ``pick`` segments (``count`` points on each)."""
    return float(count[pick].sum() / max(seg_length[pick].sum(), 1e-300))


def _near(a: FloatArray, b: FloatArray, xy: FloatArray, reach: float) -> np.ndarray:
    """Whether each segment a-b has its middle within ``reach`` of a vertex of ``xy``."""
    return cKDTree(xy).query((a + b) / 2, distance_upper_bound=reach)[0] <= reach


def _middle(stem: FloatArray) -> FloatArray:
    """A stem's averaged path (`passes.smoothed`) where it zigzags, `ZIGZAG` x as long as
    that path, else the stem itself."""
    middle = smoothed(stem)
    zigzag = polyline_length(stem, False) >= ZIGZAG * polyline_length(middle, False)
    return middle if zigzag else stem


def _spread_ratio(dist: FloatArray, on_ring: np.ndarray, radius: float) -> float:
    """The stems' points' median distance from them over the ring's points' from it (0 when
    either holds none): two merged walls lie half their gap to either side of their stem."""
    if on_ring.all() or not on_ring.any():
        return 0.0
    ring_spread = max(float(np.median(dist[on_ring])), SPREAD_FLOOR * radius)
    return float(np.median(dist[~on_ring])) / ring_spread


def _at_hairpins(paths: dict[int, list[FloatArray]], walk: list[tuple[int, FloatArray]],
                 radius: float) -> bool:
    """Whether each stem runs on from a hairpin of the cycle (`runs_on_from_hairpin`)."""
    for i, (v, leaving) in enumerate(walk):
        for stem in paths.get(v, []):
            if not runs_on_from_hairpin(walk[i - 1][1][::-1], leaving, stem, radius):
                return False
    return True


def runs_on_from_hairpin(back: FloatArray, ahead: FloatArray, out: FloatArray, radius: float
                         ) -> bool:
    """Whether an outline turns back at a point and a line runs on the other way from it:
    ``back`` and ``ahead``, the outline from the point either way, run side by side
    (`HAIRPIN_ARMS`) over `HAIRPIN_REACH` radii, and ``out``, the line from the point, runs
    back between them (`HAIRPIN_STEM`). So a slit's walls part where it opens into the
    outline (wider than the radius, the march followed each) and the slit's stem continues
    between them, where a line drawing's stroke leaves a smooth ring. Each polyline starts at
    the point."""
    reach = HAIRPIN_REACH * radius
    root = ahead[0]
    arms = np.zeros(2)
    for arm in (back, ahead):
        d = _point_along(arm, reach) - root
        arms += d / max(np.linalg.norm(d), 1e-300)
    if np.linalg.norm(arms) < 2 * np.cos(np.radians(HAIRPIN_ARMS / 2)):
        return False
    arms /= np.linalg.norm(arms)
    d = _point_along(out, reach) - root
    return bool(d @ arms <= -np.cos(np.radians(HAIRPIN_STEM)) * np.linalg.norm(d))


def _point_along(xy: FloatArray, distance: float) -> FloatArray:
    """The point ``distance`` along a polyline from its start (its end, if shorter)."""
    return np.asarray(shapely.LineString(xy).interpolate(distance).coords[0])


def _denser_half(count: FloatArray, seg_length: FloatArray, line: IntArray, window: float
                 ) -> float:
    """Points per length over the denser half (by length) of the stretches ``window`` long
    along each line (``count`` points on each segment, ``line`` the line of each; the last,
    short stretch of a line joins the one before).

    A wedge slit's stem runs on where its walls part, and there holds one wall (a stretch as
    long as the merged one where the march went round both walls, which kept whole outlines
    open: their stems held 1.4 x the ring's points per length); its merged stretch holds two."""
    start = np.flatnonzero(np.r_[True, line[1:] != line[:-1]])
    stop = np.r_[start[1:], len(line)]
    which = np.repeat(np.arange(len(start)), stop - start)  # each segment's line, from 0
    arc = np.r_[0.0, np.cumsum(seg_length)]
    base = arc[start][which]
    along = arc[1:] - base - seg_length / 2
    total = arc[stop][which] - base  # the length of each segment's line
    last = np.maximum(total // window - 1, 0)
    stretch = np.minimum(along // window, last)
    _, key = np.unique(np.column_stack([which, stretch]), axis=0, return_inverse=True)
    key = key.ravel()
    points = np.bincount(key, count)
    width = np.bincount(key, seg_length)
    order = np.argsort(-points / np.maximum(width, 1e-300))
    half = np.searchsorted(np.cumsum(width[order]), width.sum() / 2) + 1
    taken = order[:half]
    return float(points[taken].sum() / max(width[taken].sum(), 1e-300))


def _even(seg: IntArray, seg_length: FloatArray, radius: float) -> bool:
    """Whether points spread evenly along a ring: counted in windows of `DENSITY_WINDOW`
    radii, the densest decile holds at most `EVEN_SAMPLING` x the sparsest."""
    arc = np.cumsum(seg_length)
    window = ((arc - seg_length / 2) // (DENSITY_WINDOW * radius)).astype(int)
    n_windows = int(arc[-1] // (DENSITY_WINDOW * radius))
    if n_windows < 2:
        return True
    window = np.minimum(window, n_windows - 1)  # the last, short window joins the one before
    count = np.bincount(window[seg], minlength=n_windows)
    width = np.bincount(window, weights=seg_length, minlength=n_windows)
    filled = width > 0  # a window that a segment longer than it spans holds none
    low, high = np.percentile(count[filled] / width[filled], [10, 90])
    return bool(high <= EVEN_SAMPLING * low)
