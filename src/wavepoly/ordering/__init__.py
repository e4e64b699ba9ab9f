"""Ordering (paper §2, "Data sorting"): unorganized planar points -> ordered, thinned contours.

The paper marches from a random start point along the least-squares tangent of a fixed-radius
neighbourhood, one neighbourhood at a time, each step summarizing the points ahead by one ordered
point. This module computes the same ingredients for every neighbourhood at once, so that no
Python loop runs over points:

1. *Neighbourhoods*: the plane is cut into cells of radius/2; every occupied cell seeds a
   neighbourhood of the fixed ``radius``, summarized by its centroid and the least-squares
   regression line through it (the tangent: the principal axis of the neighbourhood). Dense
   clouds enter these sums as one weighted atom per cell of radius/8 (`cell_atoms`). On a noisy
   scan (bell-shaped scatter about the curves, `noise_level`) the neighbourhoods reach 5 x the
   noise instead, up to 4 x radius, so that the tangent follows the curve, not the scatter.
   A neighbourhood that spans two walls side by side (a laser map's double wall) becomes a
   node on each wall (`walls`).
2. *Thinning*: a random (seeded) maximal set of centroids at least radius/2 apart is kept
   (Luby's parallel rounds), so consecutive ordered points are radius/2 .. radius apart, as
   one marching step would place them.
3. *Marching*: each ordered point links to the nearest point ahead and the nearest point behind
   along its tangent; mutual links form chains, a chain that comes back to its start is a closed
   contour. Chain ends that are each other's nearest free end are joined (sharp corners, where
   both neighbours lie ahead of the tangent, and gaps in the scan). Where the chain turns
   sharply, the run of turning points is replaced by the intersection of the straight legs on
   either side, so corners stay sharp instead of being rounded by the neighbourhood averaging.
   Short chains alongside longer ones (noise split off a wall, a notch's tip) are absorbed
   (`marching`, `joining`). On a noisy scan a node holds at least two points (strays on a
   floor are no chain), and a join wider than 4 reaches runs along points (no door is closed);
   on a clean scan, a chain closing on itself that wide runs within 2 radii of points.
4. Every input point belongs to the contour of its nearest ordered point (``members``); points of
   contours too short to be curves, or farther than ``radius`` from their contour, are outliers
   (`contours`); on a clean sampling (scatter at most a quarter of the radius) a point within
   two radii of its contour is a member, the tail of that scatter, which the polygon covers.
   A ring the march drew around two shapes that nearly touch, pinched at a waist where each
   of its passes turns from one shape onto the other, is split into the two, as is a hole
   that nearly touches its outline, and two rings side by side that the march stepped
   between on a node or two where one's points thin out (`waists`).
   A group of outliers or a short stroke beyond a closed contour's sharp turn is the tip of a
   notch the march turned back from: the turn's vertex moves out to it (`tips`). Open pieces
   that form one cycle with stems hanging off it (a slit or a thin limb whose walls the march
   followed as one chain) become a closed outline that walks each stem out and back (`stems`).
   Three pieces between two junctions, one of them two walls merged (a hole whose corner
   nears its outline, two shapes a thin gap apart), become the two rings that share that
   wall, drawn apart by its half-width (`shared_walls`).
   A ring capped across a narrow root, facing a bare straight stretch of another ring (a limb
   or a pocket the march closed on itself while the body's outline ran past), joins that ring
   as one outline (`mouths`). Two thin rings, each walked out along one of two walls side by
   side and back along the other and turning back where the other does (the march swapped
   walls at two places), are cut where they face each other and joined along the walls
   (`folds`).
5. On a noisy scan the outliers are read again: the compact strokes among them (a ghost wall
   beside a wall, the foot of a short wall meeting it) become contours clear of the first
   ones (`strokes`).
6. Where the radius spans only a few point spacings (a sparse sample at a coarse tolerance),
   its neighbourhoods may span both walls of a part thinner than the tolerance and measure
   them as noise. The scan is then read again at half the radius, and that reading is kept
   where it is clean and measures much less noise, and leaves no more points out and no more
   contours open (`FINER_RADIUS`).
7. Where read as noise the curves run through the middle of it and leave a fifth of the points
   out, the scan is read again as a clean sample, and that reading is kept where it holds
   every point but a few within the tolerance (`MIDDLE_LOSS`), or, where the noisy reading's
   own curves are mostly open, ten times as many as it did (`EXACT_GAIN`): small shapes with
   sharp corners, and letters packed side by side, look like scatter to the windows that
   measure the noise. Where the finer reading
   of 6. mends it too, that one is kept where it leaves fewer open or out (`_mends_more`).

All neighbour queries use `scipy.spatial.cKDTree`; the cost is O(n log n).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from functools import partial

import numpy as np

from ..geometry import mean_width, polyline_distance
from ..types import FloatArray, Ordering
from ..validate import check_tolerance, validate_points
from .contours import CORNER_GAP, CORNER_NOISE, clean_scan, contours_of
from .islands import island_contours, speck_contours
from .joining import CLOSING_SUPPORT, Support
from .marching import (
    chains_of,
    drop_crossing_loops,
    drop_side_chains,
    link_nodes,
    thin,
    wide_nodes,
)
from .neighbourhoods import Nodes, nodes_with_points, perpendicular_kurtosis
from .noise import (
    HALO_SPREAD,
    MAX_REACH,
    NOISE_REACH,
    noise_adaptive_nodes,
    noise_at,
    runs_through_the_middle,
)
from .spacing import (
    SPACING_SUBSET,
    curve_spacing,
    median_spacing,
    spacing_bound,
    sparse_side_spacing,
)
from .strokes import stroke_contours
from .walls import split_two_walls

#: Kurtosis of the perpendicular scatter below which a wide neighbourhood is two walls, not a
#: band of points (two sharp walls: 1; a flat band: 1.8).
MERGE_KURTOSIS = 1.5
#: The radius must be at least this many point spacings, or one neighbourhood holds too few
#: points along the curve to give a tangent; a smaller radius is widened, with a note.
SPACINGS_PER_RADIUS = 3.0

#: A radius widened by more than this factor for the point spacing marks a sparse sample
#: (a crust test set: 129 points at 0.02): its neighbourhoods hold a few points, and the
#: scatter they measure is the curve's turns, not noise.
SPARSE_WIDENING = 2.0
#: Such a sample is read both ways, as a clean sparse curve and as noise. A noisy band read as
#: a clean sample falls apart into fragments, each a zigzag across part of the band (fish.txt
#: at 0.02: 11 contours, against 1 read as noise); a crust set read as noise keeps as many
#: contours and loses points to outliers (crocodile: 1 and 1, 22 % of its points). The noise
#: reading wins when the clean one has at least this many times as many contours...
FRAGMENTS = 3
#: ... and it keeps all but this share of the points (a crust set that only noise can join
#: into one contour loses more: ventilator, 8 contours against 1 with 58 % outliers).
NOISE_READ_LOSS = 0.25

#: Where the curves ran through the middle of what was measured as noise and left more than
#: this share of the points out, the scan is read again as a clean sample (`_exact_reading`):
#: below the tolerance a noisy band leaves a few per cent out (the Intel map at 0.05: 7.8 %,
#: the made-up laser maps 3.2-4.8 %; three shapes 3.5 tolerances across: 18 %),
#: a band far wider than the tolerance most (fish.txt at 0.02: 90 %, whose clean reading
#: falls apart into 11 pieces)...
MIDDLE_LOSS = 0.1
#: ... and the clean reading is kept where it leaves at most this share out: a clean sample's
#: ordered contours hold every point within the tolerance (the triangles: all), a noisy band
#: read as clean zigzags through it and leaves 4-9 % beyond (bands of 0.8-2 tolerances).
EXACT_LOSS = 0.01
#: ... or, whether or not it falls apart (`FRAGMENTS`), at most this share of what the noisy
#: reading left out where that reading's own contours are mostly open: clean shapes packed
#: side by side (a page of text traced at 3 pixels: 37 % out and 31 of 33 contours open read
#: as noise, 1.6 % out exactly; letters 20 pixels high at 3: 62 % and 4 of 4, 0.2 %). A
#: noisy band's middle is its closed ring (a uniform band 7 tolerances wide: 1 of 1; its
#: clean reading leaves a tenth out and falls apart into 13 pieces).
EXACT_GAIN = 10.0
#: A noisy reading is also read again as a clean one where it left outlines open or points
#: out and its spread over a neighbourhood is more than this many times the points' own
#: scatter: the shapes' own corners and bends within the windows, not a bell of noise about
#: the curves (`wavepoly.ordering.noise.HALO_SPREAD`; shapes 3.5-5 tolerances across with
#: noise a quarter of one: 2.7-6.8; the laser maps 1.2-2.0).
SHAPE_SPREAD = HALO_SPREAD

#: Where the tolerance spans a few point spacings, the scan is read again at this share of the
#: radius (at least `SPACINGS_PER_RADIUS` spacings): at the tolerance's radius a
#: neighbourhood may span both walls of a part thinner than the tolerance (a dolphin's fin, a
#: drill's neck at 5-7 % of their size), and measures them as noise...
FINER_RADIUS = 0.5
#: ... if that is at most this share of the radius (widened to the spacings, a reading
#: barely finer sees the same neighbourhoods)...
FINER_AT_MOST = 0.8
#: ... on samples with at most this many spacings per radius (a laser map's bands hold more,
#: and there a finer neighbourhood measures less of the same scatter, not a thin part)...
FINER_SPACINGS = 12.0
#: ... and the finer reading is kept where it is clean and the tolerance's was not, or where it
#: measures at most this share of the noise the tolerance's did: the walls of a thin part, not
#: scatter, made that noise (a noisy band measures less in smaller neighbourhoods too, but
#: not a clean sampling's spread); and where it leaves no more points out and no more
#: contours open (spikes thinner than the finer radius too read as strokes meeting the body).
FINER_NOISE = 0.6
#: A finer reading is clean only on a scatter of at least this share of its spread over a
#: neighbourhood: a noisy band's scatter, measured over windows a few scatters wide where
#: half its seeds look like a flat band, falls to almost nothing (fish.txt at 0.27: 0.000 of
#: a spread of 0.31 radii; a thin part's walls: 0.18-0.37).
FINER_SCATTER = 0.1

#: Where the scan's sparsest tenth is spaced so widely that its radius of
#: `SPACINGS_PER_RADIUS` spacings is at least this many times the radius (a sampling thinned
#: to a quarter across the part: 1.5-2.2; an even one: 1.1-1.5), a clean reading that left
#: outlines open is read again at that radius: there a neighbourhood of the radius held a
#: point or two, and the march broke the outline (exact silhouettes thinned to 25 % on one
#: side: 22 of 30 right, against 30 of 30 sampled evenly)...
COARSER_AT_LEAST = 1.3
#: ... on clouds of at most this many points (a silhouette, a slice; a laser map is no clean
#: reading, and a second one would cost seconds).
COARSER_POINTS = 200_000
#: That reading is not kept where a ring it closed is narrower on average (twice its area
#: over its perimeter) than this share of its radius: an outline folded onto itself, walked
#: out along one side of a noisy stretch and back along the other (the turbine blade's
#: section in a plane through a shallow face, 0.07 radii: a layer of 3 % of the section's
#: area), not a part's outline, which a neighbourhood of that radius could not have spanned.
FOLDED_WIDTH = 1.0

#: On a dense noisy scan a node summarizes at least this many points: one point has no
#: tangent (its regression line points anywhere), and strays on a laser map's floor, one per
#: neighbourhood, were linked into lines across the rooms...
NODE_POINTS = 2
#: ... where the median neighbourhood holds at least this many (the Intel map 119, Freiburg
#: 1934): there a wall puts dozens of points in any neighbourhood it crosses. On a sparser
#: scan (Intel with every 8th point: 15) a lone point may be a far wall's return, and
#: dropping such nodes listed half as many points again as outliers.
DENSE_NODE = 40

__all__ = ["curve_spacing", "median_spacing", "order_points"]


def order_points(points: FloatArray, radius: float, *, seed: int = 0, min_points: int = 4,
                 tolerance: float | None = None) -> Ordering:
    """Order and thin unorganized planar points into contours (paper §2).

    Parameters
    ----------
    points : (N, 2) unorganized points.
    radius : fixed neighbourhood radius, in the points' units (the paper: about the shape
        tolerance). Widened, with a note, when the median point spacing exceeds radius / 3;
        halved, with a note, where it spans parts thinner than it (`FINER_RADIUS`).
    seed : seed of the random choices (which neighbourhoods are kept when thinning).
    min_points : contours with fewer ordered points than this are treated as outliers.
    tolerance : the shape tolerance the contours will be fitted to, if any. Where it is below
        the noise (`wavepoly.ordering.noise.runs_through_the_middle`: twice the points' own
        scatter, or twice the spread of a halo about a thin core), a group of points off the
        chain marks a corner only beyond `CORNER_NOISE` x the noise, so that the chain stays in
        the middle of the band, and ``Ordering.through_the_middle`` says so.

    Returns
    -------
    `Ordering` with the contours, the outlier indices, the radius used and notes.

    Examples
    --------
    >>> t = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    >>> circle = np.column_stack([np.cos(t), np.sin(t)])
    >>> res = order_points(circle, 0.05)
    >>> len(res.contours), res.contours[0].closed, len(res.outliers)
    (1, True, 0)
    """
    pts = validate_points(points, source="points")[:, :2]
    radius = given = check_tolerance(radius, "radius")
    notes = []
    spacing = spacing_bound(pts, seed)
    if spacing > radius / SPACINGS_PER_RADIUS and len(pts) > 2 * SPACING_SUBSET:
        spacing = curve_spacing(pts, seed=seed)  # the bound was a subset's estimate
    if spacing > radius / SPACINGS_PER_RADIUS:
        new_radius = SPACINGS_PER_RADIUS * spacing
        notes.append(f"radius widened from {radius:.4g} to {new_radius:.4g}: the point spacing "
                     f"along the curves ({spacing:.4g}) is more than a third of it")
        radius = new_radius
    sparse = radius > SPARSE_WIDENING * given
    read = partial(_read, pts, radius=radius, given=given, seed=seed, min_points=min_points,
                   notes=tuple(notes), spacing=spacing, tolerance=tolerance)
    ordering = read(sparse=sparse)
    if not sparse:
        exact = _exact_reading(ordering, pts, tolerance, read)
        finer = _finer_reading(ordering, pts, radius, spacing, read)
        if finer is not None and (exact is None or _mends_more(finer, exact)):
            return finer
        if exact is not None:
            return exact
        coarser = _coarser_reading(ordering, pts, radius, seed, read)
        return ordering if coarser is None else coarser
    # a crust test set, or a noisy band sampled more densely than the tolerance?
    clean, noisy = ordering, read(sparse=False)
    if not _better_read_as_noise(clean, noisy, len(pts)):
        return clean
    note = (f"read as a noisy band, not as a sparse sample: as a sparse one the points fall "
            f"apart into {len(clean.contours)} contours")
    return replace(noisy, notes=(*noisy.notes, note))


def _finer_reading(ordering: Ordering, pts: FloatArray, radius: float, spacing: float,
                   read: Callable[..., Ordering]) -> Ordering | None:
    """The scan read at a finer radius (`FINER_RADIUS`), where that reading is clean, measures
    much less noise than ``ordering`` (read at ``radius``) and leaves no more points out and
    no more contours open; else None. Only on samples with a few spacings per radius
    (`FINER_SPACINGS`); the noise is measured before any marching."""
    finer = max(FINER_RADIUS * radius, SPACINGS_PER_RADIUS * spacing)
    if not (0 < spacing and radius <= FINER_SPACINGS * spacing
            and finer <= FINER_AT_MOST * radius):
        return None
    noise, scatter = noise_at(pts, finer, SPACINGS_PER_RADIUS * spacing)
    if (not clean_scan(noise, finer, finer / spacing, scatter)
            or scatter < FINER_SCATTER * noise
            or (ordering.clean and noise > FINER_NOISE * ordering.noise)):
        return None  # measured before marching: a laser map's band is not clean either way
    fine = read(radius=finer, sparse=False)
    if len(fine.outliers) > len(ordering.outliers) or _open(fine) > _open(ordering):
        return None  # spikes thinner than the finer radius too, read as strokes
    note = (f"read at a radius of {finer:.4g}: at {radius:.4g} the neighbourhoods spanned "
            f"parts thinner than that (noise {ordering.noise:.3g} there, {fine.noise:.3g} here)")
    return replace(fine, notes=(*fine.notes, note))


def _coarser_reading(ordering: Ordering, pts: FloatArray, radius: float, seed: int,
                     read: Callable[..., Ordering]) -> Ordering | None:
    """The scan read at a radius of `SPACINGS_PER_RADIUS` spacings of its sparse side
    (`sparse_side_spacing`), where its density varies so much that this is at least
    `COARSER_AT_LEAST` x ``radius`` and the clean reading at ``radius`` left outlines open;
    kept where it leaves no more points out, every outline closed and none of the closed ones
    lost, and none folded onto itself (`FOLDED_WIDTH`); else None.
    """
    if not ordering.clean or _open(ordering) == 0 or len(pts) > COARSER_POINTS:
        return None
    coarse = SPACINGS_PER_RADIUS * sparse_side_spacing(pts, seed=seed)
    if coarse < COARSER_AT_LEAST * radius:
        return None
    wide = read(radius=coarse, sparse=False)
    if (not wide.clean or len(wide.outliers) > len(ordering.outliers) or _open(wide) > 0
            or len(wide.contours) < len(ordering.contours) - _open(ordering)):
        return None  # a reading that closes only some (a slab cut along a face) is no better
    if any(mean_width(c.points) < FOLDED_WIDTH * coarse for c in wide.contours):
        return None
    note = (f"read at a radius of {coarse:.4g}: the point spacing varies across the scan, and "
            f"at {radius:.4g} the march broke outlines where the points are sparsest")
    return replace(wide, notes=(*wide.notes, note))


def _exact_reading(ordering: Ordering, pts: FloatArray, tolerance: float | None,
                   read: Callable[..., Ordering]) -> Ordering | None:
    """The scan read as a clean sample (no noise measured), where read as noise it went wrong
    in one of two ways. Its curves ran through the middle and left more than `MIDDLE_LOSS`
    of the points out (`_left_out`): small shapes with sharp corners (two triangles 6
    tolerances across) fill the windows that measure the noise with both sides and a
    corner, which look like scatter. Or the spread it measured is the shapes' own, not a
    bell about their curves (`SHAPE_SPREAD` x the points' scatter), and it left outlines
    open or points out. Kept where it leaves at most `EXACT_LOSS` of the points out and
    does not fall apart into open pieces (`FRAGMENTS`), or, where most of the noisy
    reading's own contours are open, leaves out at most a tenth of what it did
    (`EXACT_GAIN`: letters packed side by side, whose noisy reading is open zigzags across
    them), and in the second case leaves fewer outlines open or fewer points out; else
    None."""
    if tolerance is None or ordering.noise == 0:
        return None
    left_out = _left_out(ordering, pts, tolerance)
    shaped = (not ordering.through_the_middle and ordering.noise > SHAPE_SPREAD * ordering.scatter
              and (_open(ordering) > 0 or len(ordering.outliers) > 0))
    if not shaped and not (ordering.through_the_middle and left_out > MIDDLE_LOSS * len(pts)):
        return None
    exact = read(sparse=True)
    exact_out = _left_out(exact, pts, tolerance)
    # the noisy reading's middle fell apart too, and the exact one keeps far more points
    decisive = (exact_out <= left_out / EXACT_GAIN
                and 2 * _open(ordering) > len(ordering.contours))
    if not decisive and (exact_out > EXACT_LOSS * len(pts)
                         or _open(exact) >= FRAGMENTS * max(len(ordering.contours), 1)):
        return None
    if shaped and (_open(exact), len(exact.outliers)) >= (_open(ordering), len(ordering.outliers)):
        return None
    note = (f"read as an exact sample: read as noise (a spread of {ordering.noise:.3g}), the "
            f"curves left {left_out} points out and {_open(ordering)} outlines open")
    return replace(exact, notes=(*exact.notes, note))


def _left_out(ordering: Ordering, pts: FloatArray, tolerance: float) -> int:
    """The outliers of ``ordering`` and its members farther than ``tolerance`` from their
    contour: the points a fit through the middle of the noise leaves out."""
    return len(ordering.outliers) + sum(
        int((polyline_distance(pts[c.members], c.points, c.closed) > tolerance).sum())
        for c in ordering.contours)


def _open(ordering: Ordering) -> int:
    """How many of the contours of ``ordering`` are open."""
    return sum(not c.closed for c in ordering.contours)


def _mends_more(finer: Ordering, exact: Ordering) -> bool:
    """Whether the finer reading leaves fewer outlines open than the exact one, or as many
    and fewer points out. Both mend a noisy reading whose spread was the shapes' own; where
    they leave as many open and out, neither is the better in general (a serif font's
    hairlines at ε 4 % of its height: 5 glyphs right only at half the radius; at 6 %, 5 only
    at the tolerance's), and the exact reading stays. A serif font at ε 4-6 % of its height:
    'x', 'A' and 'w' came out with open pieces read exactly, closed at half the radius."""
    return (_open(finer), len(finer.outliers)) < (_open(exact), len(exact.outliers))


def _better_read_as_noise(clean: Ordering, noisy: Ordering, n_points: int) -> bool:
    """Whether a sparse sample is a noisy band: read as a clean sample, it falls apart into
    `FRAGMENTS` x as many contours as read as noise, which keeps all but
    `NOISE_READ_LOSS` of its points."""
    return (noisy.noise > 0 and len(noisy.outliers) <= NOISE_READ_LOSS * n_points
            and len(clean.contours) >= FRAGMENTS * max(len(noisy.contours), 1))


def _read(pts: FloatArray, radius: float, given: float, seed: int, min_points: int,
          notes: tuple[str, ...], spacing: float, tolerance: float | None, sparse: bool,
          again: bool = False) -> Ordering:
    """`order_points` at a radius already widened for the spacing: noise, nodes, chains and
    contours, read as a sparse sample (no noise measured) or not. ``notes``: those made so
    far; ``spacing``: the points' spacing along the curves (0: unknown), whose few
    spacings are the narrowest window the scatter is measured over; ``again``: this
    is the second reading of a noisy scan's outliers (`strokes`), which is not read again."""
    notes = list(notes)
    rng = np.random.default_rng(seed)
    nodes, atoms, scatter = noise_adaptive_nodes(pts, radius, sparse,
                                                 SPACINGS_PER_RADIUS * spacing)
    clean = clean_scan(nodes.noise, radius, radius / spacing if spacing > 0 else np.inf,
                       scatter)
    middle = tolerance is not None and runs_through_the_middle(pts, tolerance, nodes.noise,
                                                               scatter)
    corner_gap = max(CORNER_GAP * radius, CORNER_NOISE * nodes.noise) if middle else None
    if nodes.reach > radius:
        notes.append(_widening_note(nodes, radius))
    noisy = not clean
    if noisy:
        nodes = nodes_with_points(nodes, atoms, NODE_POINTS, DENSE_NODE)
    nodes = split_two_walls(nodes, atoms, radius)
    keep = thin(nodes.xy, radius / 2, rng)
    nodes = Nodes(nodes.xy[keep], nodes.tangent[keep], nodes.ratio[keep], nodes.spread[keep],
                  nodes.reach, nodes.noise)
    links = link_nodes(nodes, radius, Support(atoms.tree, radius, every_wide_join=True) if noisy
                       else Support(atoms.tree, CLOSING_SUPPORT * radius, every_wide_join=False,
                                    aside=radius))
    chains, absorbed = drop_side_chains(nodes, chains_of(links, len(nodes.xy)))
    chains, absorbed = drop_crossing_loops(nodes, chains, absorbed)
    wide = wide_nodes(nodes, chains, radius)
    two_walls = perpendicular_kurtosis(nodes.xy[wide], nodes.tangent[wide], atoms,
                                       nodes.reach) < MERGE_KURTOSIS
    merged = nodes.xy[wide[two_walls]]
    if len(merged):
        notes.append(f"{len(merged)} place(s) where two walls closer than 2 x radius "
                     "may have merged into one contour")
    if (~two_walls).any():
        notes.append(f"{int((~two_walls).sum())} place(s) where the points spread over a band "
                     "wider than the radius (a thick wall, clutter, or a slice cut along a "
                     "surface)")
    # a noisy scan's outliers read again are strokes beside its walls, not outlines
    contours, outliers = contours_of(pts, atoms.tree, nodes, chains, absorbed, radius,
                                     min_points, clean, corner_gap, stems=not again)
    if clean:  # on a noisy scan such groups are clutter
        islands, outliers = island_contours(outliers, pts, radius, given)
        contours, outliers = speck_contours(contours + islands, outliers, pts, radius, given)
    elif not (again or middle):  # below the scatter, what lies off the middle is noise
        reread = partial(_read, radius=radius, given=given, seed=seed, min_points=min_points,
                         notes=(), spacing=0.0, tolerance=None, sparse=True, again=True)
        strokes, outliers = stroke_contours(pts, outliers, contours, radius, given, reread)
        contours += strokes
    return Ordering(contours, outliers, radius, merged, tuple(notes), nodes.noise, scatter,
                    middle, clean)


def _widening_note(nodes: Nodes, radius: float) -> str:
    """The note that a noisy scan's neighbourhoods were widened, and by what spread: less
    than the spread over a neighbourhood where the curves' bends made up much of it
    (`wavepoly.ordering.noise.BEND_SHARE`)."""
    sizing = nodes.reach / NOISE_REACH
    bends = (f", {sizing:.3g} about the curves' bends" if sizing < nodes.noise
             and nodes.reach < MAX_REACH * radius else "")
    return (f"noisy scan (the points spread {nodes.noise:.3g} about the curves over a "
            f"neighbourhood{bends}): neighbourhoods widened from {radius:.4g} to "
            f"{nodes.reach:.4g} to follow the curves")
