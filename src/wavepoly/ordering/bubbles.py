"""Bubbles, tip loops and specks: stretches of a piece graph that are no rings of their own.

Where the march follows a slit's two walls apart for a few radii, or draws one wall twice by a
junction, two edges run between the same two nodes within a radius or so of each other: a
*bubble*, one stem or wall, walked along the middle between them. Where it zigzags across a
slit narrower than the radius, the chain's first node may come within reach of the chain a few
steps on and meet it: a *tip loop* at the stem's dead end, opened into the stem's tip. A
loop of two or three nodes whose ends both met one junction is a *speck*, which encloses
nothing (`wavepoly.ordering.stems` walks what is left).
"""

from __future__ import annotations

import numpy as np
import shapely

from ..geometry import polyline_length
from ..types import FloatArray
from .piece_graph import Edge, bridges, degrees

#: A loop edge from a junction back to it no longer than this many radii is a speck: the
#: march left two or three nodes by the junction, and both their ends met it.
SPECK_LENGTH = 1.0
#: Two edges between the same two nodes that lie within this many radii of each other are one
#: wall drawn twice, or a slit's two walls followed apart (a bubble), not a ring: a ring that
#: thin is a stem, and walked as one. The silhouettes' slits part 1.1-1.45 radii where the
#: march followed their walls apart (at 1.0 radius wide and 4 long, such bubbles kept 6 of
#: 300 outlines open).
BUBBLE_WIDTH = 1.5
#: ... and no longer than this many radii: the march's two chains by a junction, a few nodes
#: each, or a slit's walls followed apart (8-10 radii on the silhouettes). Longer ones are a
#: chord beside a wall, whose region's boundary `outer_edges` finds.
BUBBLE_LENGTH = 12.0


def is_speck(edge: Edge, radius: float) -> bool:
    """Whether an edge is a loop from a node back to it no longer than `SPECK_LENGTH` radii:
    a piece of two or three points whose ends both met one junction, which encloses nothing
    (its points still belong to the outline)."""
    length = np.linalg.norm(np.diff(edge.xy, axis=0), axis=1).sum()
    return edge.start == edge.end and length <= SPECK_LENGTH * radius


def without_bubbles(comp: list[int], edges: list[Edge], radius: float) -> list[int]:
    """The component with each bubble collapsed: two edges between the same two nodes, no
    longer than `BUBBLE_LENGTH` radii and within `BUBBLE_WIDTH` radii of each other, become
    one edge along the middle between them (in ``edges``, in place of the first). They are one
    wall that the march drew twice by a junction, or a slit's two walls that it followed
    apart for a few radii; their points still belong to the outline, and a stem through the
    bubble is walked out and back along the middle. A longer chord beside a wall is left to
    `outer_edges`."""
    out = list(comp)
    for i, a in enumerate(comp):
        for b in comp[i + 1:]:
            ea, eb = edges[a], edges[b]
            if (a not in out or b not in out or ea.start == ea.end
                    or {ea.start, ea.end} != {eb.start, eb.end}):
                continue
            la, lb = shapely.LineString(ea.xy), shapely.LineString(eb.xy)
            if (max(la.length, lb.length) <= BUBBLE_LENGTH * radius
                    and la.hausdorff_distance(lb) <= BUBBLE_WIDTH * radius):
                other = eb.xy if eb.start == ea.start else eb.xy[::-1]
                edges[a] = Edge(_middle(ea.xy, other), ea.start, ea.end, ea.piece)
                out.remove(b)
    return out


def without_tip_loops(comp: list[int], edges: list[Edge], radius: float,
                      rings: frozenset[int] = frozenset()) -> None:
    """Each tip loop of the component opened into a stem's tip (in ``edges``, in place): a
    loop edge at a node that only one other edge leaves, as thin and short as a bubble
    (`without_bubbles`), becomes an edge from that node along the middle of the loop's two
    halves out to its farthest point, a dead end. The march zigzagged across a slit narrower
    than the radius and its chain's first node met a node a few steps on (a noisy bitmap's
    slit, 1 tolerance wide: a loop of 6 nodes at the tip of the stroke down the slit), which
    closed a loop where the walls run as one stem. Loops are opened only where the rest of
    the component holds a ring the march closed (its piece among ``rings``), and cycles
    longer than its stems and tips together, as an outline is longer than the slits cut
    into it: a lone thin ring's piece whose end met its own far part is a loop with a tail
    (the ring `_thin_ring` walks), a band's zigzag that met itself at both ends two loops
    joined by a bar, and an outline drawn as one piece whose ends each met it a few nodes on
    (scikit-image's horse) a long bar between two small loops, which walked out and back
    drew the outline twice. Among open pieces alone, a loop opened let a reading of a
    serif 'y' close that split its ball terminal off at a hairline, and that reading won."""
    degree = degrees(comp, edges)
    tips = {}
    for k in comp:
        e = edges[k]
        if e.start != e.end or degree[e.start] != 3:
            continue
        far = int(np.argmax(np.linalg.norm(e.xy - e.xy[0], axis=1)))
        if not 0 < far < len(e.xy) - 1:
            continue  # a loop of one point, which encloses nothing
        out, back = e.xy[:far + 1], e.xy[far:][::-1]
        la, lb = shapely.LineString(out), shapely.LineString(back)
        if (la.length + lb.length <= BUBBLE_LENGTH * radius
                and la.hausdorff_distance(lb) <= BUBBLE_WIDTH * radius):
            tips[k] = _middle(out, back)
    rest = [k for k in comp if k not in tips]
    if not tips or not rest:
        return
    stems = bridges(rest, edges)
    if not any(edges[k].piece in rings for k in rest if k not in stems):
        return
    cycles = sum(polyline_length(edges[k].xy, False) for k in rest if k not in stems)
    if cycles <= sum(polyline_length(xy, False)
                     for xy in [edges[k].xy for k in stems] + list(tips.values())):
        return
    fresh = 1 + max(max(e.start, e.end) for e in edges)
    for n, (k, xy) in enumerate(tips.items()):
        edges[k] = Edge(xy, edges[k].start, fresh + n, edges[k].piece)


def _middle(a: FloatArray, b: FloatArray) -> FloatArray:
    """The polyline halfway between two with the same ends, point by point at equal shares of
    their lengths (as many points as the longer has)."""
    share = np.linspace(0.0, 1.0, max(len(a), len(b)))
    along = [shapely.line_interpolate_point(shapely.LineString(xy), share, normalized=True)
             for xy in (a, b)]
    return (shapely.get_coordinates(along[0]) + shapely.get_coordinates(along[1])) / 2
