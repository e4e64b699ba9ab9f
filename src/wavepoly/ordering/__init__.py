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
   node on each wall; on a clean scan, a node whose wider window finds two parallel walls
   running on side by side, closer than a reach and their scatter (rings 1.5 tolerances
   apart, scattered a quarter of one), moves onto the nearer (`walls`).
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
   as one outline (`mouths`); so do two rings side by side that the walls of a narrow neck
   join, where the march closed a lobe with a spike into the neck and ran the body's
   outline past its mouth (`necks`; a short neck's links routed through its walls,
   `neck_routes`). Two thin rings, each walked out along one of two walls
   side by side and back along the other and turning back where the other does (the march
   swapped walls at two places), are cut where they face each other and joined along the walls
   (`folds`). A ring's detour of a few nodes onto a neighbouring ring's wall, beside which
   it runs on (the march stepped across where its own wall's points thin out), is cut off
   (`detours`). A ring whose members lie on two walls closer than the radius all the way
   round (a thin-walled tube's section, followed down the middle of its wall) becomes the
   annulus's two rings, drawn apart by the walls' offsets (`annuli`).
5. On a noisy scan the outliers are read again: the compact strokes among them (a ghost wall
   beside a wall, the foot of a short wall meeting it) become contours clear of the first
   ones (`strokes`), and a speck that its points surround (a chair's leg seen from round
   about) becomes the ring of its hull (`islands.clutter_specks`).
6. Where the radius spans only a few point spacings (a sparse sample at a coarse tolerance),
   its neighbourhoods may span both walls of a part thinner than the tolerance and measure
   them as noise. The scan is then read again at half the radius, and that reading is kept
   where it is clean and measures much less noise, and leaves no more points out and no more
   contours open (`rereading.FINER_RADIUS`).
7. Where read as noise the curves run through the middle of it and leave a fifth of the points
   out, the scan is read again as a clean sample, and that reading is kept where it holds
   every point but a few within the tolerance (`rereading.MIDDLE_LOSS`), or, where the noisy
   reading's own curves are mostly open, ten times as many as it did
   (`rereading.EXACT_GAIN`): small shapes with sharp corners, and letters packed side by
   side, look like scatter to the windows that measure the noise. Where the finer reading
   of 6. mends it too, that one is kept where it leaves no more open or out: it sees the
   hairlines the tolerance's neighbourhoods span (`rereading`).
8. Where a clean reading still left outlines open, one ending far from every other line,
   the scan is read again with other seeds of the thinning, and the first reading at the
   same radius that closes every outline is kept
   (`rereading.other_thinnings`): where walls run within the radius of each other, which
   centroids the thinning keeps decides whether the march steps across to the other wall.

All neighbour queries use `scipy.spatial.cKDTree`; the cost is O(n log n).
"""

from __future__ import annotations

from dataclasses import replace
from functools import partial

import numpy as np

from ..types import FloatArray, Ordering
from ..validate import check_tolerance, validate_points
from .contours import CORNER_GAP, CORNER_NOISE, clean_scan, contours_of
from .islands import clutter_specks, island_contours, speck_contours
from .joining import CLOSING_SUPPORT, Support
from .marching import (
    chains_of,
    drop_crossing_loops,
    drop_side_chains,
    link_nodes,
    thin,
    wide_nodes,
)
from .neighbourhoods import Atoms, Nodes, nodes_with_points, perpendicular_kurtosis
from .noise import (
    MAX_REACH,
    NOISE_REACH,
    noise_adaptive_nodes,
    runs_through_the_middle,
)
from .rereading import FRAGMENTS, chosen_reading, other_thinnings, tighter_reading
from .spacing import (
    SPACING_SUBSET,
    SPACINGS_PER_RADIUS,
    curve_spacing,
    median_spacing,
    points_per_radius,
    spacing_bound,
)
from .strokes import stroke_contours
from .walls import onto_walls, split_two_walls

#: Kurtosis of the perpendicular scatter below which a wide neighbourhood is two walls, not a
#: band of points (two sharp walls: 1; a flat band: 1.8).
MERGE_KURTOSIS = 1.5

#: A radius widened by more than this factor for the point spacing marks a sparse sample
#: (a crust test set: 129 points at 0.02): its neighbourhoods hold a few points, and the
#: scatter they measure is the curve's turns, not noise.
SPARSE_WIDENING = 2.0
#: Such a sample is read both ways, as a clean sparse curve and as noise; the noise reading
#: wins where the clean one falls apart into `FRAGMENTS` x as many contours and the noise
#: one keeps all but this share of the points (a crust set that only noise can join into one
#: contour loses more: ventilator, 8 contours against 1 with 58 % outliers).
NOISE_READ_LOSS = 0.25

#: Where the points spread about their curves over more than this many radii, the radius is
#: widened to the spread (`WIDE_BAND_RADIUS`): neighbourhoods capped at `MAX_REACH` radii
#: cannot follow a band so wide, and nodes half a radius apart fill it from side to side
#: (Freiburg at 0.0047, a spread of 5-9 radii: 900,000 nodes, 24 GB and no end). Only the
#: windows widened past `wavepoly.ordering.noise.WIDER_WINDOWS` find more than 3.2 radii.
WIDE_BAND = 3.0
#: ... to this many times the spread: the widest neighbourhoods then reach `NOISE_REACH`
#: spreads, as on any noisy scan.
WIDE_BAND_RADIUS = NOISE_REACH / MAX_REACH

#: A reading's neighbourhoods (one per occupied cell of half the radius) are at most this
#: many; where there are more, the radius is widened until they fit: the Freiburg map (1.7
#: million points) at 0.008 made 1.1 million, and the tests for two walls side by side alone
#: asked for 74 million offsets (more than 14 GB); at 0.017, 575,000 took 6 GB and 90 s.
MAX_NODES = 400_000
#: ... in at most this many steps (each measures the noise again).
MAX_NODE_STEPS = 3

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
        halved, with a note, where it spans parts thinner than it, or read with another seed
        or a fifth tighter where a clean reading left outlines open
        (`wavepoly.ordering.rereading`).
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
    if not sparse:
        chosen = partial(chosen_reading, pts, radius=radius, spacing=spacing,
                         tolerance=tolerance)
        ordering = chosen(read, seed)
        other = other_thinnings(ordering, pts, seed, lambda s: chosen(partial(read, seed=s), s))
        ordering = ordering if other is None else other
        tighter = tighter_reading(ordering, pts, spacing, read)
        return ordering if tighter is None else tighter
    ordering = read(sparse=True)
    # a crust test set, or a noisy band sampled more densely than the tolerance?
    clean, noisy = ordering, read(sparse=False)
    if not _better_read_as_noise(clean, noisy, len(pts)):
        return clean
    note = (f"read as a noisy band, not as a sparse sample: as a sparse one the points fall "
            f"apart into {len(clean.contours)} contours")
    return replace(noisy, notes=(*noisy.notes, note))


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
    nodes, atoms, scatter, radius = _nodes_that_fit(pts, radius, sparse, spacing, notes)
    # with no noise measured every scan is clean: the count is not needed
    per_radius = (points_per_radius(pts, radius, seed) if spacing > 0 and nodes.noise > 0
                  else np.inf)
    clean = clean_scan(nodes.noise, radius, per_radius, scatter)
    middle = tolerance is not None and runs_through_the_middle(pts, tolerance, nodes.noise,
                                                               scatter)
    corner_gap = max(CORNER_GAP * radius, CORNER_NOISE * nodes.noise) if middle else None
    if nodes.reach > radius:
        notes.append(_widening_note(nodes, radius))
    noisy = not clean
    if noisy:
        nodes = nodes_with_points(nodes, atoms, NODE_POINTS, DENSE_NODE)
    else:  # a noisy scan's double walls split with a node on each (`split_two_walls`)
        nodes = onto_walls(nodes, atoms, radius)
    nodes = split_two_walls(nodes, atoms, radius, noisy=noisy)
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
        contours, outliers = speck_contours(contours + islands, outliers, pts, radius, given,
                                            scraps=not again)
    elif not (again or middle):  # below the scatter, what lies off the middle is noise
        reread = partial(_read, radius=radius, given=given, seed=seed, min_points=min_points,
                         notes=(), spacing=0.0, tolerance=None, sparse=True, again=True)
        strokes, outliers = stroke_contours(pts, outliers, contours, radius, given, reread)
        specks, outliers = clutter_specks(outliers, pts, radius, given)
        contours += strokes + specks
    return Ordering(contours, outliers, radius, merged, tuple(notes), nodes.noise, scatter,
                    middle, clean, per_radius)


def _nodes_that_fit(pts: FloatArray, radius: float, sparse: bool, spacing: float,
                    notes: list[str]) -> tuple[Nodes, Atoms, float, float]:
    """`noise_adaptive_nodes` at ``radius``, or at a radius widened (with a note added to
    ``notes``) to a band many radii wide (`WIDE_BAND`), then until the nodes are at most
    `MAX_NODES`; and the radius used."""
    min_window = SPACINGS_PER_RADIUS * spacing
    nodes, atoms, scatter = noise_adaptive_nodes(pts, radius, sparse, min_window)
    if nodes.noise > WIDE_BAND * radius:
        wider = WIDE_BAND_RADIUS * nodes.noise
        notes.append(f"radius widened from {radius:.4g} to {wider:.4g}: the points spread "
                     f"{nodes.noise:.3g} about the curves, more than {WIDE_BAND:g} x it")
        radius = wider
        nodes, atoms, scatter = noise_adaptive_nodes(pts, radius, sparse, min_window)
    for _ in range(MAX_NODE_STEPS):
        if len(nodes.xy) <= MAX_NODES:
            break
        # a curve's cells fall as 1 / radius, a band's faster, a scatter of strays' slower
        wider = radius * len(nodes.xy) / MAX_NODES
        notes.append(f"radius widened from {radius:.4g} to {wider:.4g}: at {radius:.4g} the "
                     f"scan has {len(nodes.xy)} neighbourhoods, more than {MAX_NODES} fit "
                     "in memory")
        radius = wider
        nodes, atoms, scatter = noise_adaptive_nodes(pts, radius, sparse, min_window)
    return nodes, atoms, scatter, radius


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
