"""Two walls side by side: a neighbourhood that spans both becomes one node on each wall.

A neighbourhood is wider than the gap between two parallel walls when the gap is less than
about twice its reach (a laser map's double walls, rings 1.5-2 tolerances apart, the two sides
of a thin part). Its centroid then lies between the walls, and the march would zigzag between
them or merge them into one contour. Across such a neighbourhood's regression line the offsets
of its points fall into two sharp groups, one per wall: split at their mean, each side's
spread is small against the gap between the sides' means (a wall's noise against the gap),
where a Gaussian scatter gives about 0.38 of the gap, a flat band 0.29 and a corner's second
leg more. Such a node is replaced by two, each at the mean offset of its side and with the same
tangent, so that the thinning keeps a node on each wall and the march follows each wall on
its own. (The kurtosis of the offsets, which tells two equal walls from noise, does not serve
here: a light ghost wall beside a dense one gives a heavy tail, as noise does.) On a noisy
scan, a neighbourhood centred between two walls may be nearly round, its principal axis
across them: it is tested across that axis too (`_across_round`); and each wall's offset is
measured again over a window centred on it (`_recentred`).

Where the walls are about a reach apart (rings 1.5 tolerances apart with noise a quarter of
one), a neighbourhood spans both only where it is centred near the middle, and too few of them
do so side by side to split. Each node is tested against the walls that a wider window finds
about it (`onto_walls`): one whose neighbourhood took in the other wall's near edge, or both
walls, moves onto the nearer wall, so that the march does not step between them.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..kernels import two_means_sides
from ..types import FloatArray, IntArray
from .neighbourhoods import (
    Atoms,
    Nodes,
    Offsets,
    inner_scatter,
    moments,
    perpendicular_offsets,
    principal_axes,
)

#: A neighbourhood is tested when its perpendicular spread exceeds this many radii: two walls
#: a gap d apart spread d / 2, and walls closer than one radius are one curve to the tolerance.
SPLIT_SPREAD = 0.5
#: Each side must hold at least this share of the neighbourhood's weight: two walls, not a wall
#: and a few strays beside it.
SIDE_SHARE = 0.1
#: Each side's own spread must be below this share of the gap between the sides: two sharp
#: walls (walls more than 5 noise levels apart), not a band (0.29) or Gaussian scatter (0.38).
SIDE_SHARPNESS = 0.25
#: Between the sides' means, the middle half of the gap must hold less than this share of the
#: weight: two walls leave it nearly empty (8 % for walls 5.7 noise levels apart), a
#: bell-shaped scatter fills it (31 %), a flat band too (25 %).
EMPTY_MIDDLE = 0.15
#: Walls run side by side for a while: a node splits only when at least this many nodes within
#: `SIDE_BY_SIDE_REACH` neighbourhood reaches would split too (a few that pass by chance on a
#: noisy curve do not).
SIDE_BY_SIDE_NODES = 12
SIDE_BY_SIDE_REACH = 2.0
#: A neighbourhood whose variance ratio (smaller / larger) is above this is nearly round: its
#: principal axis is not to be trusted, and the two-walls test is tried across it too.
ROUND_RATIO = 0.5
#: A round node is tested across only when it holds at least this share of the median weight
#: of the wide neighbourhoods: a node between two walls holds about as much as a wall node.
TURNED_WEIGHT = 0.5
#: On a noisy scan each wall found is measured again over a window this many reaches along
#: the line (either way), short enough to stay on a straight stretch; the points are taken
#: from a disc of `RECENTRE_REACH` reaches about the node, which holds the window: a wall
#: found lies within a reach of the node, and the window reaches half the gap beyond it.
RECENTRE_ALONG = 0.5
RECENTRE_REACH = 2.0
#: `onto_walls` moves nodes where the walls are closer than a reach and this many of a wall's
#: spreads: a neighbourhood centred on one wall then takes in the other's band (its near
#: two standard deviations). Farther apart (rings 2 tolerances apart), each wall's nodes
#: see only their own, and the march keeps to it.
NEAR_EDGE = 2.0
#: It takes the walls' direction from a window of this many reaches about each node:
#: a reach is too short to hold a stretch of each wall where they are a reach apart, and the
#: principal axis of a node between them runs across them (variance ratio 0.6-0.9)...
WALLS_WINDOW = 3.0
#: ... and measures the walls across it within this many reaches, wide enough to hold both
#: walls' whole bands (their means a reach apart, their scatter a quarter reach either way).
WALLS_REACH = 1.5
#: The two walls run side by side: their directions across the window differ by less than
#: this (degrees). The walls of a narrow wedge do not (a glyph's arm meeting its stem at 40
#: degrees, whose node at the fork joins the two).
PARALLEL_WALLS = 15.0
#: ... and run side by side for a long way: at least `WALLS_SHARE` of the nodes within this
#: many reaches find them too. A silhouette's limb a tolerance or so wide and ten long is one
#: outline whose walls meet at its tip and part at its root (its nodes between the walls keep
#: the two together), and most nodes about it lie on the body's outline; so do a slit's, and
#: a glyph's where two strokes meet; rings side by side run on.
WALLS_RUN = 20.0
WALLS_SHARE = 0.5
#: Rounds of two-means after the split at the mean: each moves the split to halfway between
#: the sides' means; two walls settle in two or three.
SPLIT_ROUNDS = 3


def split_two_walls(nodes: Nodes, atoms: Atoms, radius: float, noisy: bool = False) -> Nodes:
    """``nodes`` with each neighbourhood that spans two walls replaced by a node on each.
    ``noisy``: a noisy scan's round neighbourhoods are tested across their principal axis too
    (`_across_round`), and each wall's offset is measured again about it (`_recentred`)."""
    wide = np.flatnonzero(nodes.spread > SPLIT_SPREAD * radius)
    if not len(wide):
        return nodes
    offsets = perpendicular_offsets(nodes.xy[wide], nodes.tangent[wide], atoms, nodes.reach)
    sides = _sides(nodes.xy[wide], nodes.tangent[wide], atoms, nodes.reach, offsets)
    split = _two_walls(sides, radius)
    tangent = nodes.tangent
    if noisy:
        weight = np.bincount(offsets.owner, offsets.weight, len(wide))
        sides, split, tangent = _across_round(nodes, wide, split, sides, weight, atoms, radius)
    low, high, spread_low, spread_high, _, _ = sides
    if split.any():  # walls run side by side for a while; a few such nodes are chance
        found = cKDTree(nodes.xy[wide[split]]).query_ball_point(
            nodes.xy[wide[split]], SIDE_BY_SIDE_REACH * nodes.reach, return_length=True)
        split[np.flatnonzero(split)[found < SIDE_BY_SIDE_NODES]] = False
    if not split.any():
        return nodes
    at = wide[split]
    if noisy:
        low, high = low.copy(), high.copy()
        low[split], high[split] = _recentred(nodes.xy[at], tangent[at], low[split], high[split],
                                             atoms, nodes.reach)
    normal = np.column_stack([-tangent[at, 1], tangent[at, 0]])
    keep = np.ones(len(nodes.xy), dtype=bool)
    keep[at] = False
    xy = np.vstack([nodes.xy[keep], nodes.xy[at] + low[split, None] * normal,
                    nodes.xy[at] + high[split, None] * normal])
    tangent = np.vstack([nodes.tangent[keep], tangent[at], tangent[at]])
    ratio = np.concatenate([nodes.ratio[keep], nodes.ratio[at], nodes.ratio[at]])
    spread = np.concatenate([nodes.spread[keep], spread_low[split], spread_high[split]])
    return Nodes(xy, tangent, ratio, spread, nodes.reach, nodes.noise)


def onto_walls(nodes: Nodes, atoms: Atoms, radius: float) -> Nodes:
    """``nodes`` with each one that lies on or between two parallel walls side by side moved
    onto the nearer wall (its mean offset, with the walls' direction).

    The walls are looked for across the principal axis of a window of `WALLS_WINDOW` reaches
    about each node, within `WALLS_REACH` reaches: two sharp sides more than a radius apart
    with an empty middle (`_two_walls`), closer than a reach and `NEAR_EDGE` spreads, whose
    directions differ by less than `PARALLEL_WALLS` degrees, and found by `WALLS_SHARE` of
    the nodes within `WALLS_RUN` reaches.
    """
    reach = nodes.reach
    _, cov = moments(nodes.xy, atoms, WALLS_WINDOW * reach)
    tangent = principal_axes(cov)[0]
    o = perpendicular_offsets(nodes.xy, tangent, atoms, WALLS_REACH * reach)
    sides = _sides(nodes.xy, tangent, atoms, WALLS_REACH * reach, o)
    low, high, spread_low, spread_high = sides[:4]
    # a wall's neighbourhood takes in the other wall's band: farther apart, each has its own
    onto = _two_walls(sides, radius) & (high - low < reach + NEAR_EDGE * np.maximum(
        spread_low, spread_high))
    onto[onto] = _parallel_sides(nodes.xy[onto], tangent[onto], atoms,
                                 _owned(o, onto), 0.5 * (low + high)[onto])
    if onto.any():  # two walls side by side for a long way, not a limb or a fork
        tree = cKDTree(nodes.xy)
        near = tree.query_ball_point(nodes.xy[onto], WALLS_RUN * reach, return_length=True)
        found = cKDTree(nodes.xy[onto]).query_ball_point(nodes.xy[onto], WALLS_RUN * reach,
                                                          return_length=True)
        onto[np.flatnonzero(onto)[found < WALLS_SHARE * near]] = False
    if not onto.any():
        return nodes
    xy, along = nodes.xy.copy(), nodes.tangent.copy()
    wall = np.where(-low < high, low, high)[onto]
    xy[onto] += wall[:, None] * np.column_stack([-tangent[onto, 1], tangent[onto, 0]])
    along[onto] = tangent[onto]
    return Nodes(xy, along, nodes.ratio, nodes.spread, reach, nodes.noise)


def _owned(o: Offsets, chosen: np.ndarray) -> Offsets:
    """``o`` restricted to the lines ``chosen``, numbered among them."""
    number = np.cumsum(chosen) - 1
    keep = chosen[o.owner]
    return Offsets(number[o.owner[keep]], o.atom[keep], o.weight[keep], o.offset[keep],
                   int(chosen.sum()))


def _parallel_sides(centre: FloatArray, tangent: FloatArray, atoms: Atoms, o: Offsets,
                    split: FloatArray) -> np.ndarray:
    """Whether the points on either side of ``split`` across each line (``centre``,
    ``tangent``; ``o``: their offsets) run within `PARALLEL_WALLS` degrees of each other:
    each side's least-squares slope of offset against the distance along the line."""
    along = np.einsum("nd,nd->n", atoms.xy[o.atom] - centre[o.owner], tangent[o.owner])
    high = o.offset > split[o.owner]
    angles = []
    for side in (~high, high):
        w = np.where(side, o.weight, 0.0)
        total = np.maximum(np.bincount(o.owner, w, o.lines), 1e-300)
        a = np.bincount(o.owner, w * along, o.lines) / total
        y = np.bincount(o.owner, w * o.offset, o.lines) / total
        aa = np.bincount(o.owner, w * along * along, o.lines) / total - a * a
        ay = np.bincount(o.owner, w * along * o.offset, o.lines) / total - a * y
        angles.append(np.degrees(np.arctan2(ay, np.maximum(aa, 1e-300))))
    return np.abs(angles[0] - angles[1]) < PARALLEL_WALLS


def _recentred(centre: FloatArray, tangent: FloatArray, low: FloatArray, high: FloatArray,
               atoms: Atoms, reach: float) -> tuple[FloatArray, FloatArray]:
    """The offsets of the two walls found across each line (``centre``, ``tangent``), each
    measured again as the mean offset of the points in a window centred on it: within
    `RECENTRE_ALONG` reaches along the line and half the gap across.

    The neighbourhood that found the walls is a disc about the node: where the node sits on
    one wall, the disc reaches only the near edge of the other wall's band, and that side's
    mean falls short of the wall (on a made-up map's double wall at ε 0.05, about 0.13 m
    where the faces are 0.15 m apart): a node between the faces, which the march then
    zigzags through.
    """
    o = perpendicular_offsets(centre, tangent, atoms, RECENTRE_REACH * reach)
    along = np.einsum("nd,nd->n", atoms.xy[o.atom] - centre[o.owner], tangent[o.owner])
    half = 0.5 * (high - low)[o.owner]
    near = np.abs(along) <= RECENTRE_ALONG * reach
    measured = []
    for side in (low, high):
        weight = np.where(near & (np.abs(o.offset - side[o.owner]) < half), o.weight, 0.0)
        total = np.bincount(o.owner, weight, len(centre))
        moment = np.bincount(o.owner, weight * o.offset, len(centre))
        measured.append(np.where(total > 0, moment / np.maximum(total, 1e-300), side))
    return measured[0], measured[1]


def _across_round(nodes: Nodes, wide: IntArray, split: np.ndarray, sides: tuple[FloatArray, ...],
                  weight: FloatArray, atoms: Atoms, radius: float
                  ) -> tuple[tuple[FloatArray, ...], np.ndarray, FloatArray]:
    """The sides and the split of the ``wide`` nodes, and the nodes' tangents, with the wide
    nodes that are nearly round, do not split along their principal axis and hold at least
    `TURNED_WEIGHT` x the wide nodes' median ``weight`` tested across it too: where that test
    finds two walls, the node splits across and its tangent is turned.

    A neighbourhood centred between two walls about a reach apart takes in a short stretch of
    each: the two stretches side by side are about as long as they are apart, and the principal
    axis may run across the walls (a variance ratio 0.6-0.9 where a wall's own is 0.2-0.5).
    Across that axis the offsets are the walls' runs along themselves, no two sides; along it
    they are the two walls. Such a node holds a stretch of each wall, as much as a node on
    one; a round cluster of clutter holds less (the Intel map's rooms: about 0.4 of the median),
    and across it two sides are chance.
    """
    round_ = np.flatnonzero(~split & (nodes.ratio[wide] > ROUND_RATIO)
                            & (weight >= TURNED_WEIGHT * np.median(weight)))
    if not len(round_):
        return sides, split, nodes.tangent
    at = wide[round_]
    turned = np.column_stack([-nodes.tangent[at, 1], nodes.tangent[at, 0]])
    across = _sides(nodes.xy[at], turned, atoms, nodes.reach)
    two = _two_walls(across, radius)
    if not two.any():
        return sides, split, nodes.tangent
    tangent = nodes.tangent.copy()
    tangent[at[two]] = turned[two]
    sides = tuple(np.array(s, copy=True) for s in sides)
    for s, a in zip(sides, across):
        s[round_[two]] = a[two]
    split = split.copy()
    split[round_[two]] = True
    return sides, split, tangent


def two_walls_spread(centre: FloatArray, tangent: FloatArray, atoms: Atoms, reach: float,
                     radius: float, offsets: Offsets | None = None
                     ) -> tuple[np.ndarray, FloatArray]:
    """Which lines (``centre``, ``tangent``) have two walls side by side within ``reach``, and
    the RMS spread of the points about their own wall (`split_two_walls`'s tests, without
    the run along the walls). ``offsets``: the points' offsets, when already measured."""
    sides = _sides(centre, tangent, atoms, reach, offsets)
    share = sides[4]
    own = np.sqrt((1 - share) * sides[2] ** 2 + share * sides[3] ** 2)
    return _two_walls(sides, radius), own


def _two_walls(sides: tuple[FloatArray, ...], radius: float) -> np.ndarray:
    """Which of the neighbourhoods measured by `_sides` hold two walls side by side."""
    low, high, spread_low, spread_high, share, middle = sides
    gap = high - low
    return ((gap > radius) & (share >= SIDE_SHARE) & (share <= 1 - SIDE_SHARE)
            & (np.maximum(spread_low, spread_high) < SIDE_SHARPNESS * gap)
            & (middle < EMPTY_MIDDLE))


def _sides(centre: FloatArray, tangent: FloatArray, atoms: Atoms, reach: float,
           offsets: Offsets | None = None) -> tuple[FloatArray, ...]:
    """Across each line (``centre``, ``tangent``), of the points within ``reach``: the mean
    offset and RMS spread of each side, and the share of the weight on the high side. The
    sides are split where two-means puts them (a light ghost wall beside a dense one would
    lose some of the dense wall's points to a split at the mean). Last, the share of the
    weight in the middle half of the gap between the sides' means. (The rounds run compiled:
    `wavepoly.kernels.two_means_sides`.)"""
    o = perpendicular_offsets(centre, tangent, atoms, reach) if offsets is None else offsets
    inner = inner_scatter(o, tangent, atoms)
    return two_means_sides(o.owner, o.offset, o.weight, inner, o.lines, SPLIT_ROUNDS)


def _sides_reference(centre: FloatArray, tangent: FloatArray, atoms: Atoms, reach: float,
                     offsets: Offsets | None = None) -> tuple[FloatArray, ...]:
    """`_sides` in NumPy, the reference of the compiled `wavepoly.kernels.two_means_sides`
    for the tests."""
    o = perpendicular_offsets(centre, tangent, atoms, reach) if offsets is None else offsets
    owner, offset, w, k = o.owner, o.offset, o.weight, o.lines
    inner = inner_scatter(o, tangent, atoms)
    total = np.maximum(np.bincount(owner, w, k), 1e-300)
    mean = np.bincount(owner, w * offset, k) / total
    threshold = mean
    for _ in range(SPLIT_ROUNDS + 1):  # two-means in one dimension (Lloyd's rounds)
        up = offset > threshold[owner]
        out = []
        for side in (~up, up):
            ws = np.where(side, w, 0.0)
            weight = np.maximum(np.bincount(owner, ws, k), 1e-300)
            m = np.bincount(owner, ws * offset, k) / weight
            var = np.bincount(owner, ws * (offset - m[owner]) ** 2 + np.where(side, inner, 0.0),
                              k) / weight
            out.append((m, np.sqrt(np.maximum(var, 0.0)), weight))
        (low, s_low, _), (high, s_high, w_high) = out
        threshold = 0.5 * (low + high)
    middle = np.abs(offset - threshold[owner]) < 0.25 * (high - low)[owner]
    return low, high, s_low, s_high, w_high / total, np.bincount(owner, w * middle, k) / total
