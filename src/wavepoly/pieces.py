"""The fit's last fallback: contours that still break validity after the fewest-vertex
selection (which keeps its chords clear of other edges: valid by construction) are cut into
open pieces that meet at their end points, a junction. The pieces draw the same lines, so
every point keeps its distance to the output: the tolerance holds, and so does validity.

Two ways remain for a result to break it: contours that cross at a point (two walls meeting
at a T, read as chains that run past each other), cut there (`split_crossings`); and pieces
that meet along a stretch (a piece folding back over itself, an open piece drawn along a
ring), whose linework is noded (`noded_contours`).

Cutting leaves pieces that meet end to end where nothing else passes (the other contour of
a crossing left out as a stub, one wall cut where a second crossed it): they are one line,
and are joined again (`join_at_ends`), into a ring where they close one.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import replace

import numpy as np
import shapely
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from .geometry import curve_line
from .types import Contour, ContourReport, FloatArray, Validity
from .validity import JUNCTION_SLACK, check_contours, noded_pieces, split_at_crossings_of


def split_crossings(contours: list[Contour], reports: list[ContourReport]
                    ) -> tuple[list[Contour], list[ContourReport]]:
    """Contours that still cross, split at the crossing points into open pieces that meet
    there (a junction): the lines drawn are the same, so every point keeps its distance."""
    pieces = split_at_crossings_of([c.vertices for c in contours], [c.closed for c in contours])
    out_c, out_r = [], []
    for k, (c, r) in enumerate(zip(contours, reports)):
        first = len(out_c)
        for xy in pieces.get(k, [c.vertices]):
            out_c.append(Contour(xy, c.closed and k not in pieces, c.max_error, c.mean_error))
            out_r.append(r if k not in pieces else replace(
                r, closed=False, final_vertices=len(xy), first_piece=first))
    return out_c, out_r


def noded_contours(contours: list[Contour], reports: list[ContourReport], validity: Validity
                   ) -> tuple[list[Contour], list[ContourReport]]:
    """The contours that still break validity (an open piece folding back over itself, two
    pieces drawn along one stretch), each group of those that meet replaced by the pieces of
    its noded linework (`wavepoly.validity.noded_pieces`): the same lines, so every point
    keeps its distance. Each piece goes to the contour it lies on, as a split contour's."""
    groups = _problem_groups(validity, len(contours))
    if not groups:
        return contours, reports
    pieces: dict[int, list[FloatArray]] = {}
    for group in groups:
        lines = [curve_line(contours[k].vertices, contours[k].closed) for k in group]
        for xy in noded_pieces([contours[k].vertices for k in group],
                               [contours[k].closed for k in group]):
            middle = shapely.line_interpolate_point(shapely.linestrings(xy), 0.5,
                                                    normalized=True)
            owner = group[int(np.argmin(shapely.distance(lines, middle)))]
            pieces.setdefault(owner, []).append(xy)
    involved = {k for group in groups for k in group}
    out_c, out_r, new_first, split_of = [], [], {}, []
    for k, (c, r) in enumerate(zip(contours, reports)):
        mine = [c] if k not in involved else [Contour(xy, False, c.max_error, c.mean_error)
                                              for xy in pieces.get(k, [])]
        if mine:
            new_first[k] = len(out_c)
        for piece in mine:
            out_c.append(piece)
            out_r.append(r if k not in involved else replace(
                r, closed=False, final_vertices=len(piece.vertices)))
            # the pieces of one contour share its points: they are counted at the first
            split_of.append(r.first_piece if r.first_piece is not None
                            else k if k in involved else None)
    out_r = [r if f is None else replace(r, first_piece=new_first.get(f, i))
             for i, (r, f) in enumerate(zip(out_r, split_of))]
    return out_c, out_r


def _problem_groups(validity: Validity, n: int) -> list[list[int]]:
    """The contours named by the problems of ``validity``, in groups that problems join."""
    named = sorted({k for p in validity.problems for k in p.contours})
    label = _labels(n, [(p.contours[0], k) for p in validity.problems for k in p.contours[1:]])
    groups: dict[int, list[int]] = {}
    for k in named:
        groups.setdefault(int(label[k]), []).append(k)
    return list(groups.values())


def _labels(n: int, pairs: list[tuple[int, int]]) -> np.ndarray:
    """For each of ``n`` items, the label of the group that ``pairs`` join it into."""
    a, b = (np.array(x, dtype=np.intp) for x in zip(*pairs)) if pairs else ([], [])
    graph = coo_matrix((np.ones(len(a)), (a, b)), shape=(n, n))
    return connected_components(graph, directed=False)[1]


def join_at_ends(contours: list[Contour], reports: list[ContourReport]
                 ) -> tuple[list[Contour], list[ContourReport]]:
    """Open pieces whose ends meet two by two where no other contour passes, joined into one
    piece, or into a closed ring where they close one and it is a valid polygon. The lines
    drawn are the same; a join that would break validity is not made. The points of the
    contours joined are counted once, at the joined contour's first piece."""
    joins = _end_joins(contours)
    if not joins:
        return contours, reports
    chains = _chains(joins, [k for k, c in enumerate(contours) if not c.closed])
    joined = {k for chain, _ in chains for k, _ in chain}
    out = [c for k, c in enumerate(contours) if k not in joined]
    made = [_joined_contour(contours, chain, ring) for chain, ring in chains]
    problems = check_contours(out + made).problems
    bad = {k - len(out) for p in problems for k in p.contours if k >= len(out)}
    if bad:  # a join that breaks validity (a ring touching another) is not made
        chains = [ch for i, ch in enumerate(chains) if i not in bad]
        made = [m for i, m in enumerate(made) if i not in bad]
    return _with_reports(contours, reports, chains, made)


def _end_joins(contours: list[Contour]) -> dict[tuple[int, int], tuple[int, int]]:
    """For each open end (contour, 0 start or 1 end) that shares its point with exactly one
    other open end and with no other contour, that other end."""
    opens = [k for k, c in enumerate(contours) if not c.closed and len(c.vertices) >= 2]
    if not opens:
        return {}
    ends = np.concatenate([contours[k].vertices[[0, -1]] for k in opens])
    _, inverse, counts = np.unique(ends, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.ravel()
    pairs = np.flatnonzero(counts == 2)
    if not len(pairs):
        return {}
    lines = [curve_line(c.vertices, c.closed) for c in contours]
    scale = max(float(np.ptp(ends, axis=0).max()), float(np.abs(ends).max()), 1e-300)
    tree = shapely.STRtree(lines)
    order = np.argsort(inverse, kind="stable")  # the two ends at each shared point, in turn
    first = np.searchsorted(inverse[order], pairs)
    joins = {}
    for a, b in zip(order[first].tolist(), order[first + 1].tolist()):
        ka, kb = opens[a // 2], opens[b // 2]
        near = tree.query(shapely.points(ends[a]), predicate="dwithin",
                          distance=JUNCTION_SLACK * scale)
        if set(near.tolist()) != {ka, kb}:
            continue  # a third contour passes: a junction, not one line
        joins[(ka, a % 2)] = (kb, b % 2)
        joins[(kb, b % 2)] = (ka, a % 2)
    return joins


def _chains(joins: dict[tuple[int, int], tuple[int, int]], opens: list[int]
            ) -> list[tuple[list[tuple[int, bool]], bool]]:
    """The runs of pieces that ``joins`` link end to end: each a list of (contour, reversed)
    in drawing order, and whether it closes on itself."""
    seen, chains = set(), []
    starts = [k for k in opens if (k, 0) not in joins or (k, 1) not in joins]
    loops = [k for k in opens if (k, 0) in joins and (k, 1) in joins]
    for k in starts + loops:
        if k in seen or ((k, 0) not in joins and (k, 1) not in joins):
            continue
        flip = (k, 1) not in joins and (k, 0) in joins  # leave by the joined end
        chain, ring = [], False
        while True:
            chain.append((k, flip))
            seen.add(k)
            nxt = joins.get((k, 0 if flip else 1))
            if nxt is None:
                break
            if nxt[0] in seen:
                ring = nxt[0] == chain[0][0]
                break
            k, flip = nxt[0], nxt[1] == 1
        if len(chain) > 1 or ring:
            chains.append((chain, ring))
    return chains


def _joined_contour(contours: list[Contour], chain: list[tuple[int, bool]], ring: bool
                    ) -> Contour:
    parts = [contours[k].vertices[::-1] if flip else contours[k].vertices for k, flip in chain]
    xy = np.vstack([parts[0]] + [p[1:] for p in parts[1:]])
    members = [contours[k] for k, _ in chain]
    closed = ring and len(xy) >= 4
    return Contour(xy[:-1] if closed else xy, closed, max(c.max_error for c in members),
                   members[0].mean_error)


def _with_reports(contours: list[Contour], reports: list[ContourReport],
                  chains: list[tuple[list[tuple[int, bool]], bool]], made: list[Contour]
                  ) -> tuple[list[Contour], list[ContourReport]]:
    """The contours with each chain replaced by its joined contour (at its first piece's
    place), and their reports: a joined contour counts the points of every contour it joins,
    each split contour's once, and the pieces of one split contour still count them once."""
    owner = [r.first_piece if r.first_piece is not None else k for k, r in enumerate(reports)]
    head = {min(k for k, _ in chain): joined for (chain, _), joined in zip(chains, made)}
    label = _labels(len(contours), [(owner[chain[0][0]], owner[k]) for chain, _ in chains
                                    for k, _ in chain[1:]])

    def root(o: int) -> int:
        return int(label[o])

    gone = {k for chain, _ in chains for k, _ in chain} - set(head)
    points = Counter()
    for o in set(owner):
        points[root(o)] += reports[o].input_points
    kept = [k for k in range(len(contours)) if k not in gone]
    size = Counter(root(owner[k]) for k in kept)
    out_c, out_r, first_of = [], [], {}
    for k in kept:
        c, g = head.get(k, contours[k]), root(owner[k])
        first_of.setdefault(g, len(out_c))
        out_c.append(c)
        out_r.append(replace(reports[k], closed=c.closed, final_vertices=len(c.vertices),
                             input_points=points[g],
                             first_piece=first_of[g] if size[g] > 1 else None))
    return out_c, out_r
