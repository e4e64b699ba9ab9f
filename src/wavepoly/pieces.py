"""The fit's last fallback: contours that still break validity after the fewest-vertex
selection (which keeps its chords clear of other edges: valid by construction) are cut into
open pieces that meet at their end points, a junction. The pieces draw the same lines, so
every point keeps its distance to the output: the tolerance holds, and so does validity.

Two ways remain for a result to break it: contours that cross at a point (two walls meeting
at a T, read as chains that run past each other), cut there (`split_crossings`); and pieces
that meet along a stretch (a piece folding back over itself, an open piece drawn along a
ring), whose linework is noded (`noded_contours`).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import shapely

from .geometry import curve_line
from .types import Contour, ContourReport, FloatArray, Validity
from .validity import noded_pieces, split_at_crossings_of


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
    parent = list(range(n))

    def root(k: int) -> int:
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k

    named = set()
    for problem in validity.problems:
        named.update(problem.contours)
        for k in problem.contours[1:]:
            parent[root(k)] = root(problem.contours[0])
    groups: dict[int, list[int]] = {}
    for k in sorted(named):
        groups.setdefault(root(k), []).append(k)
    return list(groups.values())
