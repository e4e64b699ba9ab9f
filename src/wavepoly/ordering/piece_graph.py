"""Open pieces read as a graph: the pieces are its edges, their ends and T junctions its nodes.

Where a piece's end stops near another piece (or near its own far part), the two meet: at a T
junction the other piece is cut there; where it stops near the other's end, both ends move to
their midpoint. Ends within `END_REACH` radii are then one node. `ordering.stems` reads the
graph's components as rings with stems.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..types import FloatArray, IntArray
from .neighbourhoods import point_clusters

#: A piece's end within this many radii of another contour (or of its own far part) meets it
#: there, a T junction: the march stops up to 2.3 radii short of a slit it meets.
T_REACH = 3.0
#: Piece ends within this many radii of each other are one junction (the crossing split puts
#: them on one point; a T junction found twice lies within it).
END_REACH = 0.5

#: Where an open line's end meets a line: (line, end 0 or -1, the line met, its arc length
#: there or None where it meets that line's end, the point).
Junction = tuple[int, int, int, "float | None", FloatArray]

#: An edge lies on the outline of its rings' region where its segments' midpoints lie within
#: this fraction of a segment of the region's outline (the region is built from its points).
ON_OUTLINE = 1e-6


@dataclass
class Edge:
    """A piece of an open contour between two graph nodes."""

    xy: FloatArray
    start: int
    end: int
    piece: int


def piece_graph(lines: list[FloatArray], closed: list[bool], radius: float,
                free: frozenset[tuple[int, int]] = frozenset(),
                met: list[Junction] | None = None) -> tuple[list[Edge], FloatArray]:
    """Pieces cut at the T junctions that the open ones' ends make, as edges between the
    clustered end nodes (a closed line starts and ends on one node). ``free``: ends (line,
    0 or -1) that meet nothing, dead ends whatever lies near them; ``met``: the lines'
    `junctions`, where already found.

    Each edge remembers its line (``Edge.xy`` is a stretch of it, the junction points added)."""
    cuts: list[list[tuple[float, FloatArray]]] = [[] for _ in lines]
    ends = []
    for i, e, j, s, q in junctions(lines, closed, radius) if met is None else met:
        if (i, e) in free:
            continue
        if s is not None:
            cuts[j].append((s, q))
        ends.append((i, e, q))
    lines = [xy.copy() for xy in lines]
    for i, e, q in ends:
        lines[i][e] = q  # the end meets the line it heads into
    pieces, owner = [], []
    for i, xy in enumerate(lines):
        for piece in _cut(xy, cuts[i]):
            pieces.append(piece)
            owner.append(i)
    tips = np.array([p[e] for p in pieces for e in (0, -1)])
    label = point_clusters(tips, END_REACH * radius)
    node_xy = np.array([tips[label == c].mean(axis=0) for c in range(label.max() + 1)])
    edges = []
    for k, (piece, i) in enumerate(zip(pieces, owner)):
        a, b = label[2 * k], label[2 * k + 1]
        edges.append(Edge(np.vstack([node_xy[a], piece[1:-1], node_xy[b]]), int(a), int(b), i))
    return edges, node_xy


def t_ends(met: list[Junction]) -> list[tuple[int, int]]:
    """The open lines' ends (line, 0 or -1) that meet the inside of a line (T junctions),
    among their `junctions`."""
    return [(i, e) for i, e, _, s, _ in met if s is not None]


def junctions(lines: list[FloatArray], closed: list[bool], radius: float) -> list[Junction]:
    """Where each open line's ends meet a line (`_t_junction`): (line, end, the line met,
    its arc length or None where it meets that line's end, the point)."""
    geoms = [shapely.LineString(xy) for xy in lines]
    tree = shapely.STRtree(geoms)
    out = []
    for i, xy in enumerate(lines):
        if closed[i]:
            continue
        for e in (0, -1):
            near = tree.query(shapely.Point(xy[e]), predicate="dwithin",
                              distance=T_REACH * radius)
            at = _t_junction(i, xy[e], e, lines, geoms, near, radius)
            if at is not None:
                out.append((i, e, *at))
    return out


def _t_junction(i: int, end: FloatArray, e: int, lines: list[FloatArray],
                geoms: list[shapely.Geometry], near: IntArray, radius: float
                ) -> tuple[int, float | None, FloatArray] | None:
    """The nearest place within `T_REACH` radii where the end of line ``i`` meets the inside
    of a line (its own beyond 2 `T_REACH` radii of the end) among the ``near`` ones, as
    (line, arc length, point); where it meets another line's end, the arc length is None and
    the point halfway between the ends."""
    best = None
    p = shapely.Point(end)
    for j in near:
        xy, g = lines[j], geoms[j]
        if j == i:
            own = _own_far_part(xy, e, 2 * T_REACH * radius)
            if own is None:
                continue
            s0, g = own
        else:
            s0 = 0.0
        d = g.distance(p)
        if d > T_REACH * radius or (best is not None and d >= best[0]):
            continue
        s = g.project(p)
        length = geoms[j].length
        s_full = s + s0 if e == 0 or j != i else s
        if s_full <= END_REACH * radius or s_full >= length - END_REACH * radius:
            if j == i:
                continue
            # two ends meet (where a slit's walls converge the march stops on both, a few
            # radii apart): both move to their midpoint, and the clustering joins them there
            other = lines[j][0] if s_full <= END_REACH * radius else lines[j][-1]
            best = (d, j, None, (end + other) / 2)
            continue
        q = np.asarray(g.interpolate(s).coords[0])
        best = (d, j, s_full, q)
    return None if best is None else best[1:]


def _own_far_part(xy: FloatArray, e: int, skip: float) -> tuple[float, shapely.Geometry] | None:
    """The part of a piece farther than ``skip`` along it from its end ``e``, and where that
    part starts (its arc length from the piece's start)."""
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(xy, axis=0), axis=1))])
    keep = arc >= skip if e == 0 else arc <= arc[-1] - skip
    if keep.sum() < 2:
        return None
    return float(arc[keep][0]), shapely.LineString(xy[keep])


def _cut(xy: FloatArray, cuts: list[tuple[float, FloatArray]]) -> list[FloatArray]:
    """A polyline cut at arc lengths, each cut point ending one piece and starting the next."""
    if not cuts:
        return [xy]
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(xy, axis=0), axis=1))])
    cuts = sorted(cuts, key=lambda c: c[0])
    bounds = [(-np.inf, xy[0])] + cuts + [(np.inf, xy[-1])]
    pieces = []
    for (lo, start), (hi, end) in zip(bounds[:-1], bounds[1:]):
        inner = xy[(arc > lo) & (arc < hi)]
        if np.isinf(lo):
            inner = inner[1:]
        if np.isinf(hi):
            inner = inner[:-1]
        pieces.append(_no_repeats(np.vstack([start[None], inner, end[None]])))
    return [p for p in pieces if len(p) >= 2]


def _no_repeats(xy: FloatArray) -> FloatArray:
    step = np.linalg.norm(np.diff(xy, axis=0), axis=1)
    return xy[np.concatenate([[True], step > 0])]


def components(edges: list[Edge], n_nodes: int) -> list[list[int]]:
    """Edge indices of each connected component of the graph."""
    if not edges:
        return []
    ends = np.array([[e.start, e.end] for e in edges])
    graph = coo_matrix((np.ones(len(ends)), (ends[:, 0], ends[:, 1])), shape=(n_nodes, n_nodes))
    label = connected_components(graph, directed=False)[1]
    comp: dict[int, list[int]] = {}
    for k, (a, _) in enumerate(ends):
        comp.setdefault(int(label[a]), []).append(k)
    return list(comp.values())


def bridges(comp: list[int], edges: list[Edge]) -> set[int]:
    """Edges of the component whose removal disconnects it (Tarjan, on a multigraph)."""
    adj: dict[int, list[tuple[int, int]]] = {}
    for k in comp:
        adj.setdefault(edges[k].start, []).append((edges[k].end, k))
        adj.setdefault(edges[k].end, []).append((edges[k].start, k))
    disc: dict[int, int] = {}
    low: dict[int, int] = {}
    bridges: set[int] = set()
    root = edges[comp[0]].start
    stack = [(root, -1, iter(adj[root]))]
    disc[root] = low[root] = 0
    while stack:
        v, via, it = stack[-1]
        for w, k in it:
            if k == via:
                continue
            if w in disc:
                low[v] = min(low[v], disc[w])
            else:
                disc[w] = low[w] = len(disc)
                stack.append((w, k, iter(adj[w])))
                break
        else:
            stack.pop()
            if stack:
                u = stack[-1][0]
                low[u] = min(low[u], low[v])
                if low[v] > disc[u]:
                    bridges.add(via)
    return bridges


def degrees(cycle: list[int], edges: list[Edge]) -> dict[int, int]:
    degree: dict[int, int] = {}
    for k in cycle:
        for v in (edges[k].start, edges[k].end):
            degree[v] = degree.get(v, 0) + 1
    return degree


def outer_edges(cycle: list[int], edges: list[Edge]) -> tuple[list[int], list[int]]:
    """The cycle edges on the outline of the region that the component's rings enclose, and
    the edges inside it (a chord where the chains of a slit's tip crossed): none when the
    rings enclose more than one simple region."""
    lines = [shapely.LineString(edges[k].xy) for k in cycle]
    region = shapely.union_all(shapely.get_parts(shapely.polygonize([shapely.union_all(lines)])))
    if not isinstance(region, shapely.Polygon) or region.is_empty or region.interiors:
        return [], []
    outline = region.exterior
    outer, inner = [], []
    for k, line in zip(cycle, lines):
        mid = shapely.points((edges[k].xy[:-1] + edges[k].xy[1:]) / 2)
        on = shapely.distance(mid, outline) <= ON_OUTLINE * line.length / len(mid)
        (outer if on.mean() > 0.5 else inner).append(k)
    return outer, inner
