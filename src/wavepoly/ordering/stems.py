"""Closed outlines with stems: a ring of open pieces, and the slits and thin limbs hanging off it.

Where two walls of an outline run closer than the radius for a while (a slit cut into a
silhouette, a limb thinner than the tolerance), the neighbourhoods span both walls and the march
follows them as one chain, a *stem*. The outline then meets the stem at a T junction, so the
march leaves it open there (a lollipop: a loop and its tail), or the crossing split cuts it into
pieces that meet at the junctions. Read as a graph (pieces are edges, their ends and T
junctions nodes), such an outline is one cycle with stems hanging off it. Walking the cycle and
each stem out along one wall and back along the other gives the closed outline: the two walls
are drawn apart by their measured half-width, so the polygon stays simple.

A stem is told from a stroke of a line drawing (Deery's antlers meet its head at T junctions
too) by its points: two walls merged into one chain hold twice as many points per length as a
wall of the cycle, one stroke as many (`wavepoly.ordering.slits`).
The walk draws one cycle, each stem a path from it to a dead end, the stems at a node on one
side of the cycle. Where it cannot (a stem that forks, a slit's walls followed apart into a face
of their own), the outline is read as the region the pieces bound (`wavepoly.ordering.faces`);
anything else (a line drawing's network, two rings joined by a bar) is left as it is.
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.spatial import cKDTree

from ..geometry import polyline_distance, polyline_length
from ..types import FloatArray, OrderedContour
from .bubbles import is_speck, without_bubbles, without_tip_loops
from .faces import CHORD_TIP, COVER_REACH, outline_of_faces
from .joining import runs_along_points
from .passes import out_and_back, smoothed
from .piece_graph import (
    Edge,
    Junction,
    bridges,
    components,
    degrees,
    junctions,
    outer_edges,
    piece_graph,
    t_ends,
)
from .shared_walls import theta_rings
from .slits import STEM_DENSITY, stems_are_slits
from .untangle import crossing_edges, share_members, untangle

#: Where a stem leaves the cycle at a shallow angle, its first pass may cross the edge the walk
#: arrived by, a few times on each side: up to this many crossings are untangled (2-opt); a walk
#: with more is left to the fit as it is. An outline with three wedge slits crossed 11 times,
#: 8 by one root (at 4 it was left so, and the fit opened it into two pieces).
STEM_CROSSINGS = 12
#: ... each within this many radii of a stem's root.
ROOT_REACH = 2.0
#: Edges inside a cycle longer together than this share of the cycle are no chords across it
#: (a chord spans at most a diameter, a third of a round outline) but a second ring the march
#: stepped onto and off: two circles 1.5 tolerances apart, the inner one cut into pieces where
#: the outer's chain crossed it, each 1.5 radii inside the outer, within `COVER_REACH` of it
#: all the way round.
INNER_RING_SHARE = 0.5


def close_outlines(contours: list[OrderedContour], points: FloatArray, radius: float
                   ) -> list[OrderedContour]:
    """Join the open pieces that form one cycle with stems into a closed outline.

    Parameters
    ----------
    contours : the ordered contours; only the open ones are read.
    points : the input points (the contours' members index them).
    radius : the neighbourhood radius of the ordering.

    Returns
    -------
    The contours, with the open pieces of each such outline replaced by one closed contour
    that walks each stem out along one wall and back along the other.

    Examples
    --------
    A ring with a slit: the march gives a loop whose tail runs down the slit.

    >>> t = np.linspace(0.02, 2 * np.pi - 0.02, 400)
    >>> ring = np.column_stack([np.cos(t), np.sin(t)])
    >>> loop = np.vstack([np.linspace([0.5, 0.0], [1.0, 0.0], 11), ring[::10], ring[-1:]])
    >>> slit = np.column_stack([np.linspace(0.5, 1.0, 80), np.tile([0.01, -0.01], 40)])
    >>> pts = np.vstack([ring, slit])
    >>> oc = OrderedContour(loop, False, np.arange(len(pts)))
    >>> out = close_outlines([oc], pts, 0.05)
    >>> [c.closed for c in out]
    [True]
    """
    if all(c.closed for c in contours):
        return contours
    density = _scan_density(contours)
    closed, used = _closed_components(contours, list(range(len(contours))), points, radius,
                                      density)
    # a piece's end may stop by a ring that is no part of its outline (a slit's tip by a
    # hole): the open pieces left are read again on their own (a lone piece among them, such
    # as a bar between two rings, is no thin ring)
    left = [k for k, c in enumerate(contours) if not c.closed and k not in used]
    if left and any(c.closed for c in contours):
        more, more_used = _closed_components(contours, left, points, radius)
        closed, used = closed + more, used | more_used
    if not closed:
        return contours
    return [c for k, c in enumerate(contours) if k not in used] + closed


def _scan_density(contours: list[OrderedContour]) -> float:
    """Points per length of the contours (0 when they have no length)."""
    length = sum(polyline_length(c.points, c.closed) for c in contours)
    return sum(len(c.members) for c in contours) / length if length > 0 else 0.0


def _closed_components(contours: list[OrderedContour], pick: list[int], points: FloatArray,
                       radius: float, density: float = 0.0
                       ) -> tuple[list[OrderedContour], set[int]]:
    """The closed outlines of the graph of the ``pick`` contours' pieces (`_outline`), and
    the indices of the contours they use. ``density``: the points per length of the scan's
    contours, which a lone piece must hold `STEM_DENSITY` x to be a thin ring (`_thin_ring`;
    0: none is)."""
    lines = [np.vstack([contours[k].points, contours[k].points[:1]]) if contours[k].closed
             else contours[k].points for k in pick]
    closed_lines = [contours[k].closed for k in pick]
    met = _along_points(junctions(lines, closed_lines, radius), lines, closed_lines, points,
                        radius)
    edges, node_xy = piece_graph(lines, closed_lines, radius, met=met)
    closed_pieces = frozenset(np.flatnonzero(closed_lines).tolist())
    closed, used = [], set()
    for comp in components(edges, len(node_xy)):
        taken = sorted({pick[edges[k].piece] for k in comp})
        if all(contours[k].closed for k in taken):
            continue
        members = np.sort(np.concatenate([contours[k].members for k in taken]))
        ring = _outline(comp, edges, points[members], radius, density, closed_pieces)
        if ring is not None:
            used.update(taken)
            closed.append(OrderedContour(ring, True, members))
            continue
        rings = theta_rings([k for k in comp if not is_speck(edges[k], radius)], edges,
                            points[members], radius)
        if rings is None:
            ring = _slit_to_a_dead_end(lines, closed_lines, met, pick, taken,
                                       points[members], radius)
            rings = None if ring is None else [ring]
        if rings is not None:
            used.update(taken)
            closed += share_members(rings, members, points, closed=True)
    return closed, used


def _along_points(met: list[Junction], lines: list[FloatArray], closed: list[bool],
                  points: FloatArray, radius: float) -> list[Junction]:
    """The junctions ``met``, but those where a piece's end meets a closed ring across empty
    space (`joining.runs_along_points`): a small ring's scrap of an arc, open by a tolerance, lies a
    few radii from the next ring with no point between, while the march stops short of a
    slit or an outline it meets with the stroke's points running on. (An open piece met may
    lie across a spike's mouth, where no point is.)"""
    check = [k for k, (_, _, j, _, _) in enumerate(met) if closed[j]]
    if not check:
        return met
    ends = np.array([lines[met[k][0]][met[k][1]] for k in check])
    at = np.array([met[k][4] for k in check])
    bare = {k for k, ok in zip(check, runs_along_points(cKDTree(points), ends, at, radius))
            if not ok}
    return [j for k, j in enumerate(met) if k not in bare]


def _slit_to_a_dead_end(lines: list[FloatArray], closed: list[bool], met: list[Junction],
                        pick: list[int], taken: list[int], members: FloatArray, radius: float
                        ) -> FloatArray | None:
    """The outline of the ``taken`` contours' pieces (``lines``, whether each is ``closed``,
    their `junctions` ``met``) read as a region with a slit whose tip met the outline across
    it at a T junction, or None.

    Two legs of a silhouette: the slit between them runs in from the outline, its walls
    followed apart where it is wide and merged where it narrows, and its tip comes within a
    few radii of the outline across the body (`piece_graph.T_REACH`). Met at a T there, the
    slit closes a cycle; with that end a dead end, the region's largest face holds the slit's
    wide part as a hole touching its outline at the slit's mouth, and its narrow part as a
    stem from that hole (`faces.outline_of_faces`, ``open_holes``). Every piece must stay in
    the component, so a stem's root on its cycle is no dead end."""
    # the graph of the component's own lines: no other line's end meets them
    mine = sorted(pick.index(k) for k in taken)
    at = {old: new for new, old in enumerate(mine)}
    own_met = [(at[i], e, at[j], s, q) for i, e, j, s, q in met if i in at and j in at]
    own_lines, own_closed = [lines[i] for i in mine], [closed[i] for i in mine]
    for end in t_ends(own_met):
        edges, node_xy = piece_graph(own_lines, own_closed, radius, free=frozenset([end]),
                                     met=own_met)
        for comp in components(edges, len(node_xy)):
            if {edges[k].piece for k in comp} != set(range(len(mine))):
                continue
            comp = [k for k in comp if not is_speck(edges[k], radius)]
            ring = outline_of_faces([edges[k].xy for k in comp], members, radius,
                                    open_holes=True)
            if ring is not None:
                return ring
    return None


def _outline(comp: list[int], edges: list[Edge], members: FloatArray, radius: float,
             density: float = 0.0, rings: frozenset[int] = frozenset()) -> FloatArray | None:
    """The closed walk of a component that is one cycle with stems, or of a lone piece that
    is a thin ring (`_thin_ring`), or None. ``rings``: the pieces (`Edge.piece`) that were
    closed contours."""
    comp = without_bubbles([k for k in comp if not is_speck(edges[k], radius)], edges, radius)
    without_tip_loops(comp, edges, radius, rings)
    if not comp:
        return None
    stems = bridges(comp, edges)
    cycle = [k for k in comp if k not in stems]
    if not cycle:
        return _thin_ring(comp, edges, members, radius, density)
    ring = _cycle_with_stems(cycle, stems, edges, members, radius)
    if ring is not None and shapely.Polygon(ring).is_valid:
        return ring
    region = outline_of_faces([edges[k].xy for k in comp], members, radius)
    return ring if region is None else region


def _cycle_with_stems(cycle: list[int], stems: set[int], edges: list[Edge],
                      members: FloatArray, radius: float) -> FloatArray | None:
    """The cycle walked with each stem out and back (`_ring_if_slits`), and with an edge
    across it walked as a slit where the ring leaves that edge's points out
    (`_chord_as_stem`); None where the cycle is more than one ring, or a stem branches."""
    degree = degrees(cycle, edges)
    inner: list[int] = []
    if any(d != 2 for d in degree.values()):
        cycle, inner = outer_edges(cycle, edges)
        degree = degrees(cycle, edges)
        if not cycle or any(d != 2 for d in degree.values()):
            return None  # more than one ring (two rings joined by a bar, a figure eight)
    walk = _cycle_walk(cycle, edges)
    if walk is None:
        return None
    paths = _stem_paths(stems, edges, set(degree))
    if paths is None:
        return None
    ring = _ring_if_slits(walk, paths, members, radius)
    if not inner or (ring is not None and _inner_covered(ring, inner, edges, members, radius)):
        return ring
    return _chord_as_stem(walk, paths, inner, edges, members, radius)


def _ring_if_slits(walk: list[tuple[int, FloatArray]], paths: dict[int, list[FloatArray]],
                   members: FloatArray, radius: float) -> FloatArray | None:
    """The cycle walked with its stems out and back (`_ring_with_stems`, again along their
    averaged paths where the first walk crosses itself), or None where the stems are strokes
    (`stems_are_slits`)."""
    if paths and not stems_are_slits(paths, walk, members, radius):
        return None
    tree = cKDTree(members)
    ring = _ring_with_stems(walk, paths, tree, radius)
    if ring is not None and not shapely.Polygon(ring).is_valid:
        smooth = {v: [smoothed(p) for p in ps] for v, ps in paths.items()}
        again = _ring_with_stems(walk, smooth, tree, radius)
        if again is not None and shapely.Polygon(again).is_valid:
            ring = again
    return ring


def _chord_as_stem(walk: list[tuple[int, FloatArray]], paths: dict[int, list[FloatArray]],
                   inner: list[int], edges: list[Edge], members: FloatArray, radius: float
                   ) -> FloatArray | None:
    """The ring with the one inner edge walked as a stem from either of its ends, or None.

    Where a slit narrows to its tip by a wall of the outline (the gap between a horse's tail
    and its leg), the stem's dead end met that wall (`piece_graph.T_REACH`) and the stem
    became a chord, whose points the outline round it leaves out. Walked as a stem from its
    other end, up to where it comes within `CHORD_TIP` radii of the cycle, it is the slit."""
    if len(inner) != 1:
        return None
    edge = edges[inner[0]]
    on_cycle = {v for v, _ in walk}
    cycle = shapely.MultiLineString([xy for _, xy in walk])
    for root, xy in ((edge.start, edge.xy), (edge.end, edge.xy[::-1])):
        if root not in on_cycle:
            continue
        near = shapely.distance(shapely.points(xy), cycle) <= CHORD_TIP * radius
        far = np.flatnonzero(~near)
        if not len(far):
            continue
        stem = xy[:far[-1] + 1]
        if len(stem) < 3:
            continue
        more = {v: list(ps) for v, ps in paths.items()}
        more.setdefault(root, []).append(stem)
        ring = _ring_if_slits(walk, more, members, radius)
        if ring is not None and shapely.Polygon(ring).is_valid:
            return ring
    return None


def _thin_ring(comp: list[int], edges: list[Edge], members: FloatArray, radius: float,
               density: float) -> FloatArray | None:
    """A lone piece that holds `STEM_DENSITY` x the points per length of the scan's contours
    (``density``) as a ring round it, walked out and back: a hole or a part thinner than the
    radius, whose two walls the march followed as one chain (walked again along its averaged
    path where it zigzags between them and the walk crosses itself). A line drawing's lone
    stroke holds as many points as its rings, and stays open. The length is that of the
    averaged path (`smoothed`): a chain that zigzags between the two walls is longer than the
    ring's middle, and a thin hole traced from a bitmap held only 1.3 x per length of it."""
    if len(comp) != 1 or density <= 0:
        return None
    path = edges[comp[0]].xy
    length = polyline_length(smoothed(path), False)
    if len(path) < 3 or len(members) < STEM_DENSITY * density * max(length, radius):
        return None
    tree = cKDTree(members)
    for walked in (path, smoothed(path)):  # again along its middle, where it zigzags
        ring = out_and_back(walked, -1.0, tree, radius)
        if shapely.Polygon(ring).is_valid:
            return ring
    return None


def _inner_covered(ring: FloatArray, inner: list[int], edges: list[Edge], members: FloatArray,
                   radius: float) -> bool:
    """Whether the ring is a simple polygon within `COVER_REACH` radii of every member nearer
    the inner edges it leaves out than the ring, and those edges are no longer together than
    `INNER_RING_SHARE` of the ring (a ring of their own, not chords across it)."""
    if not shapely.Polygon(ring).is_valid:
        return False
    left_out = sum(polyline_length(edges[k].xy, False) for k in inner)
    if left_out > INNER_RING_SHARE * polyline_length(ring, True):
        return False
    to_ring = polyline_distance(members, ring, True)
    to_inner = np.min([polyline_distance(members, edges[k].xy, False) for k in inner], axis=0)
    return bool(np.all(to_ring[to_inner < to_ring] <= COVER_REACH * radius))


def _cycle_walk(cycle: list[int], edges: list[Edge]) -> list[tuple[int, FloatArray]] | None:
    """The cycle's edges in order, each as (its start node, its polyline along the walk)."""
    left = set(cycle)
    k = cycle[0]
    left.discard(k)
    walk = [(edges[k].start, edges[k].xy)]
    at = edges[k].end
    while left:
        nxt = next((j for j in left if at in (edges[j].start, edges[j].end)), None)
        if nxt is None:
            return None
        left.discard(nxt)
        e = edges[nxt]
        walk.append((at, e.xy if e.start == at else e.xy[::-1]))
        at = e.end if e.start == at else e.start
    return walk if at == walk[0][0] else None


def _stem_paths(stems: set[int], edges: list[Edge], on_cycle: set[int]
                ) -> dict[int, list[FloatArray]] | None:
    """Each stem as a polyline from its cycle node out to its dead end, by cycle node; None
    where a stem branches or does not start on the cycle."""
    adj: dict[int, list[int]] = {}
    for k in stems:
        for v in (edges[k].start, edges[k].end):
            adj.setdefault(v, []).append(k)
    paths: dict[int, list[FloatArray]] = {}
    seen: set[int] = set()
    for v in on_cycle:
        for k in adj.get(v, []):
            parts, at = [], v
            while True:
                e = edges[k]
                parts.append(e.xy if e.start == at else e.xy[::-1])
                seen.add(k)
                at = e.end if e.start == at else e.start
                nxt = [j for j in adj.get(at, []) if j != k]
                if at in on_cycle or len(nxt) > 1:
                    return None  # a bridge between two cycles, or a branching stem
                if not nxt:
                    break
                k = nxt[0]
            paths.setdefault(v, []).append(np.vstack([parts[0]] + [p[1:] for p in parts[1:]]))
    return paths if seen == stems else None


def _ring_with_stems(walk: list[tuple[int, FloatArray]], paths: dict[int, list[FloatArray]],
                     members: cKDTree, radius: float) -> FloatArray | None:
    """The cycle with each stem walked out and back, its two passes apart by the walls'
    half-width (`_untangled_at_roots` where a pass crosses the cycle by a stem's root)."""
    ring = []
    for i, (v, xy) in enumerate(walk):
        arriving = walk[i - 1][1]  # ends at v
        here = paths.get(v, [])
        if not here:
            ring.append(xy[:-1])
            continue
        excursion = _excursions(arriving[-2] - arriving[-1], xy[1] - xy[0], here, members,
                                radius)
        if excursion is None:
            return None
        ring.append(excursion)
        ring.append(xy[1:-1])
    out = np.vstack([r for r in ring if len(r)])
    if len(out) < 3:
        return None
    return _untangled_at_roots(out, [xy[0] for v, xy in walk if v in paths], radius)


def _untangled_at_roots(ring: FloatArray, roots: list[FloatArray], radius: float
                        ) -> FloatArray:
    """The ring, untangled (2-opt) where a stem's first pass crosses the cycle by its root: at
    most `STEM_CROSSINGS` crossings, each edge with an end within `ROOT_REACH` radii of a
    root, and a simple polygon after. Any other crossing is left to the fit, whose selection
    keeps clear of crossing chords (a blanket untangling scrambled the band of a shallow face
    on a slice)."""
    crossings = crossing_edges(ring, True)
    if not len(crossings) or len(crossings) > STEM_CROSSINGS or not roots:
        return ring
    edge, tree = crossings.ravel(), cKDTree(roots)
    gap = np.minimum(tree.query(ring[edge])[0], tree.query(ring[(edge + 1) % len(ring)])[0])
    if gap.max() > ROOT_REACH * radius:
        return ring
    mended = untangle(ring, True)
    return mended if shapely.Polygon(mended).is_valid else ring


def _angle(d: FloatArray) -> float:
    return float(np.arctan2(d[1], d[0]))


def _excursions(back: FloatArray, ahead: FloatArray, stems: list[FloatArray],
                members: cKDTree, radius: float) -> FloatArray | None:
    """The passes out and back along each stem at one cycle node, between the edge the walk
    arrives by (``back``: from the node towards where it came from) and the one it leaves by.

    Measured counter-clockwise from ``back``, stems before ``ahead`` are walked in that order
    out along their right wall; stems past it, clockwise, out along their left wall. Stems on
    both sides of the cycle at one node cannot be drawn in one simple pass: None."""
    a0 = _angle(back)
    turn = np.mod(_angle(ahead) - a0, 2 * np.pi)
    rel = [np.mod(_angle(s[1] - s[0]) - a0, 2 * np.pi) for s in stems]
    ccw = [r < turn for r in rel]
    if any(ccw) and not all(ccw):
        return None
    order = np.argsort(rel) if ccw[0] else np.argsort(rel)[::-1]
    side = -1.0 if ccw[0] else 1.0  # -1: the right wall (as seen walking out)
    passes = []
    for k in order:
        passes.append(out_and_back(stems[k], side, members, radius))
    return np.vstack(passes)
