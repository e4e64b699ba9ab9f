"""Rings folded onto two walls side by side, end to end: re-paired into the walls' own rings.

Two walls a tolerance or two apart (a thin part's sides, two rings one inside the other) that
the march swapped between at two places come out as two thin rings, each walked out along
one wall and back along the other, turning back at a hairpin where the other ring turns back
too, a few radii on. Each ring is as valid as a thin slab's outline, but neither is a ring
of the points: the walls run on through the gap between the hairpins. Cut at the places where
they face each other, the rings fall into stretches of wall, and each stretch's end continues
across the gap into the stretch in line with it; the walls come out as rings of their own.

Two slabs end to end have no points in the gap between their ends, and stay as they are.
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.spatial import cKDTree

from ..geometry import mean_width, true_runs
from ..types import FloatArray, OrderedContour
from .gaps import is_supported
from .untangle import share_members

#: A closed contour narrower on average (twice its area over its perimeter) than this many
#: radii is a thin ring that may be folded: two walls up to 2 radii apart walked out and back.
FOLD_WIDTH = 2.5
#: Two thin rings face each other where their outlines come within this many radii: the march
#: turns back a radius or two before where the other ring turns back.
FACING_REACH = 4.0
#: Each ring faces the others at a few places at most (two per ring swapped with).
MAX_PLACES = 4
#: Cut where each comes within `FACING_REACH` of the other, the rings' stretches end up to
#: twice that apart across the place, and more where a hairpin is blunt or closes across the
#: band in one long chord (15 radii on circles 1.5 radii apart with noise a quarter of one).
JOIN_REACH = 4 * FACING_REACH


def unfold_rings(contours: list[OrderedContour], points: FloatArray, radius: float
                 ) -> list[OrderedContour]:
    """The contours, with thin rings that face each other end to end re-paired along their
    walls where that gives rings that are not thin, valid, cross nothing, and whose joins the
    points fill.

    Parameters
    ----------
    contours : the ordered contours; only the closed ones narrower than `FOLD_WIDTH` radii
        are read.
    points : the input points (the contours' members index them).
    radius : the neighbourhood radius of the ordering.

    Returns
    -------
    The contours, the folded rings replaced by the walls' rings.

    Examples
    --------
    Two circles 1.5 radii apart, drawn as two rings each half on one circle and half on the
    other, turning back where the other does.

    >>> def arc(r, a, b):
    ...     t = np.linspace(a, b, 300)
    ...     return r * np.column_stack([np.cos(t), np.sin(t)])
    >>> fold = lambda a, b: np.vstack([arc(1.0, a, b), arc(1.015, b, a)])
    >>> gap = 0.012
    >>> rings = [fold(gap, np.pi - gap), fold(np.pi + gap, 2 * np.pi - gap)]
    >>> t = np.linspace(0, 2 * np.pi, 800, endpoint=False)
    >>> pts = np.vstack([r * np.column_stack([np.cos(t), np.sin(t)]) for r in (1.0, 1.015)])
    >>> halves = [np.flatnonzero(pts[:, 1] >= 0), np.flatnonzero(pts[:, 1] < 0)]
    >>> out = unfold_rings([OrderedContour(r, True, m) for r, m in zip(rings, halves)],
    ...                    pts, 0.01)
    >>> sorted(round(float(np.hypot(*c.points.T).mean()), 3) for c in out)
    [1.0, 1.015]
    """
    thin = [k for k, c in enumerate(contours)
            if c.closed and len(c.points) >= 4 and mean_width(c.points) < FOLD_WIDTH * radius]
    if len(thin) < 2:
        return contours
    rings = [contours[k].points for k in thin]
    places = _facing_places(rings, radius)
    replaced: dict[int, list[OrderedContour]] = {}
    for group in _groups(places):
        walls, used = _rejoined(rings, [p for p in places if p[0] in group], points, radius)
        if walls is None:
            continue
        taken = [thin[k] for k in sorted(used)]
        members = np.sort(np.concatenate([contours[k].members for k in taken]))
        new = share_members(walls, members, points, closed=True)
        if _clear(new, [c for k, c in enumerate(contours) if k not in taken], radius):
            replaced.update({k: [] for k in taken})
            replaced[taken[0]] = new
    return [n for k, c in enumerate(contours) for n in replaced.get(k, [c])]


def _groups(places: list[tuple[int, np.ndarray, int, np.ndarray]]) -> list[set[int]]:
    """The sets of rings joined by the facing ``places`` (each place joins its two rings)."""
    groups: list[set[int]] = []
    for a, _, b, _ in places:
        met = [g for g in groups if a in g or b in g]
        merged = {a, b}.union(*met)
        groups = [g for g in groups if g not in met] + [merged]
    return groups


def _facing_places(rings: list[FloatArray], radius: float
                   ) -> list[tuple[int, np.ndarray, int, np.ndarray]]:
    """Where two of the thin ``rings`` come within `FACING_REACH` radii of each other: for
    each such place, the two rings and the indices of their vertices there (one run each)."""
    lines = [shapely.LinearRing(r) for r in rings]
    places = []
    for a in range(len(rings)):
        for b in range(a + 1, len(rings)):
            if shapely.distance(lines[a], lines[b]) > FACING_REACH * radius:
                continue
            near_a = shapely.distance(shapely.points(rings[a]), lines[b]) <= FACING_REACH * radius
            near_b = shapely.distance(shapely.points(rings[b]), lines[a]) <= FACING_REACH * radius
            runs_a, runs_b = _runs(near_a), _runs(near_b)
            if len(runs_a) != len(runs_b) or not runs_a or len(runs_a) > MAX_PLACES:
                continue  # no rings facing end to end: one wraps the other's end
            # pair the runs by nearness: each run of one faces the nearest run of the other
            centre_b = np.array([rings[b][m].mean(axis=0) for m in runs_b])
            for m in runs_a:
                k = int(np.argmin(np.linalg.norm(centre_b - rings[a][m].mean(axis=0), axis=1)))
                places.append((a, m, b, runs_b[k]))
    return places


def _runs(mask: np.ndarray) -> list[np.ndarray]:
    """The cyclic runs of True in ``mask``, each as indices in order; none where all are True
    (a ring that is all one place faces nothing end to end)."""
    return [] if mask.all() else true_runs(mask, closed=True)


def _rejoined(rings: list[FloatArray], places, points: FloatArray, radius: float
              ) -> tuple[list[FloatArray] | None, set[int]]:
    """The rings cut at the facing ``places`` into stretches, each stretch's end joined to
    the end in line with it across the place (`_in_line`), walked into rings; None where a
    ring is cut at fewer than two places, the ends do not pair up, a join crosses empty
    space (`wavepoly.ordering.gaps.is_supported`: the march swaps walls where one's points
    thin out, so a join may cross a gap in its own wall's sampling), or a stretch is left
    over."""
    cut: dict[int, np.ndarray] = {}
    for a, ra, b, rb in places:
        for k, run in ((a, ra), (b, rb)):
            cut.setdefault(k, np.zeros(len(rings[k]), dtype=bool))[run] = True
    stretches: list[FloatArray] = []
    ring_of: list[int] = []
    for k, mask in cut.items():
        if len(_runs(mask)) < 2:
            return None, set()
        for run in true_runs(~mask, closed=True, min_run=2):
            stretches.append(rings[k][run])
            ring_of.append(k)
    ends = np.array([s[i] for s in stretches for i in (0, -1)])
    partner = _in_line(ends, np.repeat(ring_of, 2), rings, places, radius)
    if partner is None:
        return None, set()
    tree = cKDTree(points)
    if not all(is_supported(ends[i], ends[j], tree, radius)
               for i, j in enumerate(partner) if i < j):
        return None, set()
    walked = _walk(stretches, partner)
    return (None, set()) if walked is None else (walked, set(cut))


def _in_line(ends: FloatArray, ring: np.ndarray, rings: list[FloatArray], places,
             radius: float) -> np.ndarray | None:
    """Each stretch end's partner across its place (ends 2i and 2i + 1 belong to stretch i):
    at each place two ends of each ring, paired so that the two joins do not cross (an X
    would swap the walls again), the shorter pairing where neither does; None where a place
    has not two ends of each ring within `JOIN_REACH` radii."""
    centres = np.array([np.vstack([rings[a][ma], rings[b][mb]]).mean(axis=0)
                        for a, ma, b, mb in places])
    place_of = np.argmin(np.linalg.norm(ends[:, None] - centres[None], axis=2), axis=1)
    partner = np.full(len(ends), -1)
    for p, (a, _, b, _) in enumerate(places):
        mine, theirs = (np.flatnonzero((place_of == p) & (ring == k)) for k in (a, b))
        if len(mine) != 2 or len(theirs) != 2:
            return None
        best = None
        for other in (theirs, theirs[::-1]):
            segments = [shapely.LineString([ends[i], ends[j]]) for i, j in zip(mine, other)]
            length = sum(s.length for s in segments)
            if (not segments[0].intersects(segments[1])
                    and max(s.length for s in segments) <= JOIN_REACH * radius
                    and (best is None or length < best[0])):
                best = (length, other)
        if best is None:
            return None
        partner[mine], partner[best[1]] = best[1], mine
    return partner if (partner >= 0).all() else None


def _walk(stretches: list[FloatArray], partner: np.ndarray) -> list[FloatArray] | None:
    """The rings walked along the stretches, each end to its partner's stretch."""
    left = set(range(len(stretches)))
    rings = []
    while left:
        first = min(left)
        at, parts = first, []
        end = 2 * first + 1  # walking the stretch forwards, out at its last end
        while True:
            left.discard(at)
            parts.append(stretches[at] if end % 2 else stretches[at][::-1])
            nxt = int(partner[end])
            at = nxt // 2
            if at == first:
                break
            if at not in left:
                return None
            end = nxt ^ 1  # in at one end, out at the other
        rings.append(np.vstack(parts))
    return rings


def _clear(new: list[OrderedContour], rest: list[OrderedContour], radius: float) -> bool:
    """Whether the re-paired rings are valid polygons, not thin, and cross neither each
    other nor the other contours."""
    lines = [shapely.LinearRing(c.points) for c in new if len(c.points) >= 3]
    if len(lines) != len(new) or not all(shapely.Polygon(c.points).is_valid for c in new):
        return False
    if any(mean_width(c.points) < FOLD_WIDTH * radius for c in new):
        return False
    others = [shapely.LineString(c.points) if not c.closed else shapely.LinearRing(c.points)
              for c in rest if len(c.points) >= 2 + c.closed]
    everything = np.array(lines + others, dtype=object)
    for i, line in enumerate(lines):
        hit = shapely.intersects(line, everything)
        hit[i] = False
        if hit.any():
            return False
    return True
