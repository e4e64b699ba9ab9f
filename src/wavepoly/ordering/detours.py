"""A ring's short detour onto a neighbouring ring's wall, cut off.

Two rings side by side a tolerance or two apart (rings one inside the other, a hole near its
outline) each follow their own wall. Where one wall's points thin out, a neighbourhood there
takes its centroid from the other wall's band, and the march may carry the ring over onto the
other wall for a few nodes and back: a detour, drawn as teeth reaching across to the other
ring, which runs on along that wall itself. The detour's nodes are the other ring's; cut off,
the ring runs straight past along its own points, and the members the detour stood for go to
whichever ring is nearer.
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.spatial import cKDTree

from ..geometry import segment_distance, true_runs
from ..types import FloatArray, OrderedContour
from .gaps import is_supported
from .untangle import share_members

#: A ring's ordered point lies on another ring's wall within this many radii of its line:
#: the march's nodes lie within half a radius of their wall, and a ring's own wall runs at
#: least a tolerance (1.25 radii in the sweeps of near walls) from its neighbour's.
ON_WALL = 0.75
#: ... and within this many radii of one of its ordered points: the other ring runs there
#: itself, node by node, not across a long straight chord that cuts a stretch it skipped.
NODE_REACH = 1.5
#: The ring runs on past a detour, within this many degrees of the line past it on either
#: side: a line that turns farther from the ring cuts off the tip of a wedge whose point
#: touches the other ring (a line drawing's junction, Porpi's fin against its body).
DETOUR_TURN = 45.0
#: ... measured over this many ordered points (2-4 radii): from one point to the next the
#: ring zigzags where the march stepped across and back.
LEG_POINTS = 4
#: ... and runs beside the other ring there, within this many radii of its line: rings two
#: tolerances apart, side by side, whose march stepped across. A ring whose corner the other
#: touches (a hole's corner at its outline's step) runs away from it on either side.
SIDE_BY_SIDE = 3.0
#: The line past a detour is at most this many radii long: the march's detours span a few
#: nodes where one wall's points thin out; a ring that runs along another for longer shares a
#: wall with it (`shared_walls`).
DETOUR_SPAN = 6.0


def cut_detours(contours: list[OrderedContour], points: FloatArray, radius: float
                ) -> list[OrderedContour]:
    """The contours, each closed ring's short detours onto another closed ring's wall cut
    off, and the members of the rings that lost a detour shared again between them and the
    rings they reached. Only rings within `ON_WALL` radii of each other are compared.

    Parameters
    ----------
    contours : the ordered contours; only the closed ones are read.
    points : the input points (the contours' members index them).
    radius : the neighbourhood radius of the ordering.

    Returns
    -------
    The contours, the rings with detours cut off.

    Examples
    --------
    Two circles 1.5 radii apart; the inner ring steps out onto the outer circle for two nodes.

    >>> t = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    >>> inner = np.column_stack([np.cos(t), np.sin(t)])
    >>> inner[[10, 11]] *= 1.15
    >>> outer = 1.15 * np.column_stack([np.cos(t + 0.05), np.sin(t + 0.05)])
    >>> s = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    >>> pts = np.vstack([r * np.column_stack([np.cos(s), np.sin(s)]) for r in (1.0, 1.15)])
    >>> rings = [OrderedContour(inner, True, np.arange(2000)),
    ...          OrderedContour(outer, True, np.arange(2000, 4000))]
    >>> out = cut_detours(rings, pts, 0.1)
    >>> [len(c.points) for c in out], round(float(np.hypot(*out[0].points.T).max()), 3)
    ([62, 64], 1.0)
    """
    rings = [k for k, c in enumerate(contours) if c.closed and len(c.points) >= 4]
    if len(rings) < 2:
        return contours
    lines = [shapely.LinearRing(contours[k].points) for k in rings]
    near_lines = shapely.STRtree(lines)
    tree = None
    out = list(contours)
    for i, a in enumerate(rings):
        others = [rings[j] for j in near_lines.query(lines[i], predicate="dwithin",
                                                     distance=ON_WALL * radius) if j != i]
        if not others:
            continue
        ring = out[a].points
        reached, detour = _detours(ring, [out[k].points for k in others], radius)
        if not detour.any():
            continue
        tree = cKDTree(points) if tree is None else tree
        keep = ~detour
        for run in true_runs(detour, closed=True):
            before, after = ring[(run[0] - 1) % len(ring)], ring[(run[-1] + 1) % len(ring)]
            if not is_supported(before, after, tree, radius):
                keep[run] = True
        cut = ring[keep]
        if keep.all() or len(cut) < 4 or not shapely.Polygon(cut).is_valid:
            continue
        near = [others[j] for j in sorted(set(reached[detour & ~keep]))]
        group = [a, *near]
        members = np.sort(np.concatenate([out[k].members for k in group]))
        shared = share_members([cut, *[out[k].points for k in near]], members, points,
                               closed=True)
        if len(shared) != len(group):
            continue
        for k, c in zip(group, shared):
            out[k] = c
    return out


def _detours(ring: FloatArray, others: list[FloatArray], radius: float
             ) -> tuple[np.ndarray, np.ndarray]:
    """For each ordered point of ``ring``, the nearest of the ``others`` rings and whether it
    lies on a detour onto that ring's wall: within `ON_WALL` radii of its line and
    `NODE_REACH` of its points, in a run whose line past it (from the point before to the
    point after) is at most `DETOUR_SPAN` radii long and lies off the other ring's wall
    (farther than `ON_WALL` radii from its line), each of whose points lies nearer the
    other ring's line than that line past it: a ring that runs along its own wall close to
    another's, or beside another's detour onto it, has its own line past it. And the ring
    runs on along that line on either side (`_runs_on`), within `SIDE_BY_SIDE` radii of
    the other ring's line over `LEG_POINTS` points."""
    lines = [shapely.LinearRing(o) for o in others]
    at = shapely.points(ring)
    gaps = np.array([shapely.distance(at, line) for line in lines])
    reached, gap = np.argmin(gaps, axis=0), gaps.min(axis=0)
    nodes = cKDTree(np.vstack(others))
    owner = np.repeat(np.arange(len(others)), [len(o) for o in others])
    node_gap, node = nodes.query(ring)
    on = ((gap <= ON_WALL * radius) & (node_gap <= NODE_REACH * radius)
          & (owner[node] == reached))
    detour = np.zeros(len(ring), dtype=bool)
    if on.all():
        return reached, detour
    for run in true_runs(on, closed=True):
        before, after = ring[(run[0] - 1) % len(ring)], ring[(run[-1] + 1) % len(ring)]
        if np.linalg.norm(after - before) > DETOUR_SPAN * radius:
            continue
        past = shapely.distance(shapely.LineString([before, after]), lines[reached[run[0]]])
        own = segment_distance(ring[run], before[None], after[None])
        beside = gaps[reached[run[0]], _legs(run, len(ring))]
        if (past > ON_WALL * radius and (own > gap[run]).all()
                and (beside <= SIDE_BY_SIDE * radius).all()
                and _runs_on(ring, run[0] - 1, run[-1] + 1)):
            detour[run] = True
    return reached, detour


def _runs_on(ring: FloatArray, before: int, after: int) -> bool:
    """Whether the closed ``ring`` runs within `DETOUR_TURN` degrees of the line from its
    point ``before`` to its point ``after``, over `LEG_POINTS` points on either side of it."""
    n = len(ring)
    line = ring[after % n] - ring[before % n]
    legs = (ring[before % n] - ring[(before - LEG_POINTS) % n],
            ring[(after + LEG_POINTS) % n] - ring[after % n])
    cos = [float(leg @ line) / max(np.linalg.norm(leg) * np.linalg.norm(line), 1e-300)
           for leg in legs]
    return min(cos) >= np.cos(np.radians(DETOUR_TURN))


def _legs(run: np.ndarray, n: int) -> np.ndarray:
    """The indices of the `LEG_POINTS` points of a closed ring of ``n`` points on either side
    of the ``run``."""
    steps = np.arange(1, LEG_POINTS + 1)
    return np.concatenate([(run[0] - steps) % n, (run[-1] + steps) % n])
