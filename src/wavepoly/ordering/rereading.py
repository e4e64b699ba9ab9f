"""Second readings of a scan where the first went wrong (`wavepoly.ordering.order_points`).

The ordering reads a scan once at the tolerance's radius. Where that reading's
neighbourhoods spanned parts thinner than the radius, measured the shapes' own corners as
noise, or broke outlines where the points are sparse or where walls run within the radius
of each other, the scan is read again (finer, exactly, coarser, or with another thinning)
and the second reading is kept where it mends what the first broke. Each reading is asked
for through ``read``: `wavepoly.ordering`'s reading with its arguments bound, so this room
needs nothing from the one above it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np
import shapely

from ..geometry import curve_line, mean_width, polyline_distance
from ..types import FloatArray, OrderedContour, Ordering
from .contours import DENSE_CURVE, clean_scan
from .neighbourhoods import cell_atoms, moments, principal_axes
from .noise import HALO_SPREAD, noise_at
from .spacing import SPACINGS_PER_RADIUS, sparse_side_spacing

#: A sparse sample is read both ways, as a clean sparse curve and as noise. A noisy band read
#: as a clean sample falls apart into fragments, each a zigzag across part of the band (fish.txt
#: at 0.02: 11 contours, against 1 read as noise); a crust set read as noise keeps as many
#: contours and loses points to outliers (crocodile: 1 and 1, 22 % of its points). The noise
#: reading wins when the clean one has at least this many times as many contours
#: (`wavepoly.ordering.NOISE_READ_LOSS`); an exact reading of a noisy one is not kept where
#: it falls apart so (`exact_reading`).
FRAGMENTS = 3
#: Where the curves ran through the middle of what was measured as noise and left more than
#: this share of the points out, the scan is read again as a clean sample (`_exact_reading`):
#: below the tolerance a noisy band leaves a few per cent out (the Intel map at 0.05: 7.8 %,
#: the made-up laser maps 3.2-4.8 %; three shapes 3.5 tolerances across: 18 %),
#: a band far wider than the tolerance most (fish.txt at 0.02: 90 %, whose clean reading
#: falls apart into 11 pieces)...
MIDDLE_LOSS = 0.1
#: ... and the clean reading is kept where it leaves at most this share out: a clean sample's
#: ordered contours hold every point within the tolerance (the triangles: all), or within
#: the radius where the spacing widened it beyond the tolerance (a chain of centroids over
#: wider neighbourhoods cuts the turns by more than the tolerance, and the fit covers them:
#: ventilator.p2d at 43, twice its spacing, lost 169 of its 194 points read as noise); a
#: noisy band read as clean zigzags through it and leaves 4-9 % beyond (bands of 0.8-2
#: tolerances).
EXACT_LOSS = 0.01
#: ... or, whether or not it falls apart (`FRAGMENTS`), at most this share of what the noisy
#: reading left out where that reading's own contours are mostly open: clean shapes packed
#: side by side (a page of text traced at 3 pixels: 37 % out and 31 of 33 contours open read
#: as noise, 1.6 % out exactly; letters 20 pixels high at 3: 62 % and 4 of 4, 0.2 %). A
#: noisy band's middle is its closed ring (a uniform band 7 tolerances wide: 1 of 1; its
#: clean reading leaves a tenth out and falls apart into 13 pieces).
EXACT_GAIN = 10.0
#: ... and where the exact reading comes out as outlines: at most this many open pieces per
#: ring it closes (a page of text traced at 1.4 pixels: 0.4-0.9 over seven thinnings;
#: letters packed side by side: 0.5-0.8). A noisy band read exactly breaks into open pieces
#: zigzagging through it, several per ring it closes (the made-up laser maps at 0.02-0.03:
#: 2.9-6.3; the Intel map at 0.0153, half its scatter: 3.3, 2459 contours).
OPEN_PER_RING = 1.5
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

#: A clean reading that left outlines open, and that no other reading closed, is read
#: again at this share of the radius where that still holds `SPACINGS_PER_RADIUS` spacings:
#: two walls about one radius apart (two rings a tolerance apart) put the other wall on each
#: neighbourhood's rim, and the march steps across and back, leaving a ladder of open pieces
#: that meet end to end; a fifth smaller, a neighbourhood holds one wall (concentric rings
#: 0.95-1.02 tolerances apart, 8 seeds at each of five gaps: 9 of 40 left open, 0 so read).
TIGHTER_RADIUS = 0.8
#: ... also where it closed rings narrower on average than this many radii: the pieces of
#: such a ladder joined into lenses, each out along one wall and back along the other (rings
#: 1.02 tolerances apart: 1 of 4 seeds), kept where the tighter reading has fewer of them.
LENS_WIDTH = 1.5
#: Where outlines were left open, the tighter reading is tried only where the open pieces
#: run beside another wall: at least this share of their nodes (`BESIDE_REACH` radii of arc
#: or more from their ends) has points spread across them (`BESIDE_SPREAD`). A ladder's
#: pieces do all along (rings 1-1.05 tolerances apart: 99-100 % of their nodes); a line
#: drawing's strokes only at a junction or a sharp bend, 1-8 % (Deery, Fishi, Snail, f2, f4
#: sampled every third to tenth of a tolerance), and read tighter they closed into rings
#: through their junctions (Fishi every tenth: 4 rings for 2 closed and 4 open strokes).
BESIDE_SHARE = 0.3
#: A node's points are those within this many radii of it (the other wall a radius away
#: falls within, a stretch of it a radius long either side)...
BESIDE_REACH = 1.5
#: ... and they run beside another wall where their deviation across their main axis is at
#: least this many radii: two walls a radius apart put it at half a radius, one wall's
#: scatter at most a quarter (noise a quarter of a tolerance, the clean bound).
BESIDE_SPREAD = 0.35

#: A clean reading that left outlines open is read again with up to this many other seeds of
#: the thinning (`other_thinnings`): of the silhouette sweep's 25 misses (slits and thin limbs
#: whose walls run within the radius of each other), 9 come out right with six (at seeds 1,
#: 1, 1, 3, 3, 3, 4, 5, 6; 6 with three); only scans left open pay the extra readings.
OTHER_THINNINGS = 6
#: ... where an open contour ends at least this many radii from every other line
#: (`_free_end`): the silhouettes the march broke left an end 5.2-6.2 radii from any other;
#: a line drawing's strokes meet at junctions, their ends within 2.1 radii of another
#: stroke, a dangling stroke's tip 3.1 (Deery, Fishi, Snail, whose strokes other seeds
#: closed into rings walking them out and back).
FREE_END = 4.0
#: A piece's own line counts from this many radii along it from its end: nearer, it lies
#: within that reach of the end however straight it runs.
OWN_ARC = 5.0


def chosen_reading(pts: FloatArray, read: Callable[..., Ordering], seed: int, *,
                    radius: float, spacing: float, tolerance: float | None) -> Ordering:
    """The scan read at ``radius`` (not a sparse sample), or read again finer, exactly or
    coarser where that reading went wrong (`_finer_reading`, `_exact_reading`,
    `_coarser_reading`)."""
    ordering = read(sparse=False)
    exact = _exact_reading(ordering, pts, tolerance, read, radius)
    finer = _finer_reading(ordering, pts, radius, spacing, read)
    if finer is not None and (exact is None or _mends_more(finer, exact)):
        return finer
    if exact is not None:
        return exact
    coarser = _coarser_reading(ordering, pts, radius, seed, read)
    return ordering if coarser is None else coarser


def other_thinnings(ordering: Ordering, pts: FloatArray, seed: int,
                     reading: Callable[[int], Ordering]) -> Ordering | None:
    """The scan read again with `OTHER_THINNINGS` other seeds of the thinning where a clean
    reading left outlines open, one of them ending free (`_free_end`): the first read at the
    same radius that closes every one (`_closes_all`); else None. A seed whose own first
    reading was replaced by a coarser or finer one is no other thinning of the same
    neighbourhoods: a layer cut along the turbine blade's flat face, closed so at a coarser
    radius, zigzagged through the face's points where the bridged gaps of the first reading
    drew the section.

    Where two walls run within the radius of each other (a slit, a thin limb's sides, a
    limb beside a slit), which centroids the thinning keeps decides whether the march
    steps across to the other wall and breaks an outline; another thinning of the same
    neighbourhoods often does not."""
    if (not ordering.clean or _open(ordering) == 0 or len(pts) > COARSER_POINTS
            or not _free_end(ordering)):
        return None
    for other in range(seed + 1, seed + 1 + OTHER_THINNINGS):
        again = reading(other)
        if again.radius == ordering.radius and _closes_all(again, ordering, ordering.radius):
            note = (f"read with thinning seed {other}: with seed {seed} the march left "
                    f"{_open(ordering)} of its {len(ordering.contours)} contours open")
            return replace(again, notes=(*again.notes, note))
    return None


def _free_end(ordering: Ordering) -> bool:
    """Whether an open contour of ``ordering`` ends `FREE_END` radii or more from every
    other contour and from its own line `OWN_ARC` radii along and beyond: an outline the
    march broke (it turned back short of a slit's tip, or stopped where two walls' points
    mingle), not a network of strokes that meet at their junctions."""
    reach, own = FREE_END * ordering.radius, OWN_ARC * ordering.radius
    lines = np.array([curve_line(c.points, c.closed) for c in ordering.contours], dtype=object)
    for k, c in enumerate(ordering.contours):
        if c.closed:
            continue
        others = np.delete(lines, k)
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(c.points, axis=0),
                                                              axis=1))])
        for end, far in ((c.points[0], arc >= own), (c.points[-1], arc <= arc[-1] - own)):
            rest = others
            if far.sum() >= 2:
                rest = np.append(others, curve_line(c.points[far], False))
            if shapely.distance(shapely.points(end), rest).min(initial=np.inf) >= reach:
                return True
    return False


def _closes_all(again: Ordering, ordering: Ordering, radius: float) -> bool:
    """Whether reading ``again`` (at ``radius``) is clean, closes every outline, loses none
    of the closed ones of ``ordering``, leaves no more points out and folds no ring onto
    itself (`FOLDED_WIDTH`)."""
    return (again.clean and _open(again) == 0
            and len(again.outliers) <= len(ordering.outliers)
            and len(again.contours) >= len(ordering.contours) - _open(ordering)
            and all(mean_width(c.points) >= FOLDED_WIDTH * radius for c in again.contours))


def _finer_reading(ordering: Ordering, pts: FloatArray, radius: float, spacing: float,
                   read: Callable[..., Ordering]) -> Ordering | None:
    """The scan read at a finer radius (`FINER_RADIUS`), where that reading is clean, measures
    much less noise than ``ordering`` (read at ``radius``) and leaves no more points out and
    no more contours open; else None. Where ``ordering`` is clean and left nothing open or
    out, the finer reading must not draw more outlines side by side (rings inside no other;
    a hole it finds is welcome): its neighbourhoods break a hairline that the tolerance's
    spanned, and one outline comes out as two (serif glyphs at ε 4 % of their height: STIX
    62 -> 64 and cmr10 53 -> 58 of 68; at 6 %, 128 -> 137 of 204 over three serif fonts).
    Only on samples with a few spacings per radius (`FINER_SPACINGS`); the noise is
    measured before any marching."""
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
    if (ordering.clean and _open(ordering) == 0 and len(ordering.outliers) == 0
            and _outer_rings(fine) > _outer_rings(ordering)):
        return None  # a hairline the finer neighbourhoods break: one outline read as two
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
    if not _closes_all(wide, ordering, coarse):
        return None  # a reading that closes only some (a slab cut along a face) is no better
    note = (f"read at a radius of {coarse:.4g}: the point spacing varies across the scan, and "
            f"at {radius:.4g} the march broke outlines where the points are sparsest")
    return replace(wide, notes=(*wide.notes, note))


def tighter_reading(ordering: Ordering, pts: FloatArray, spacing: float,
                    read: Callable[..., Ordering]) -> Ordering | None:
    """The scan read at `TIGHTER_RADIUS` x the radius of ``ordering``, where that clean
    reading, the last one tried, left outlines open beside other walls (`_run_beside`) or
    closed lenses (`_lenses`) and the tighter radius still holds `SPACINGS_PER_RADIUS`
    spacings; kept where it closes every outline (`_closes_all`) and leaves fewer lenses,
    or no more where outlines were open; else None."""
    radius = ordering.radius
    tighter = TIGHTER_RADIUS * radius
    lenses = _lenses(ordering, radius)
    if (not ordering.clean or _open(ordering) + lenses == 0 or len(pts) > COARSER_POINTS
            or not 0 < SPACINGS_PER_RADIUS * spacing <= tighter):
        return None
    if _open(ordering) > 0 and not _run_beside(ordering, pts):
        return None  # strokes meeting at junctions, not a ladder between two walls
    again = read(radius=tighter, sparse=False)
    left = _lenses(again, radius)
    # the lenses stand for walls, not for outlines of their own that it must keep
    walls = replace(ordering, contours=[c for c in ordering.contours if not _lens(c, radius)])
    if not (_closes_all(again, walls, tighter)
            and (left < lenses or (_open(ordering) > 0 and left == lenses))):
        return None
    note = (f"read at a radius of {tighter:.4g}: at {radius:.4g} the march stepped between "
            f"walls about a radius apart, leaving {_open(ordering)} outlines open and "
            f"{lenses} closed across them")
    return replace(again, notes=(*again.notes, note))


def _run_beside(ordering: Ordering, pts: FloatArray) -> bool:
    """Whether at least `BESIDE_SHARE` of the open contours' nodes, `BESIDE_REACH` radii of
    arc or more from their ends, have the points of ``pts`` within `BESIDE_REACH` radii
    spread `BESIDE_SPREAD` radii or more across their main axis: a ladder's pieces, which
    step between two walls about a radius apart, not strokes."""
    reach = BESIDE_REACH * ordering.radius
    inner = np.vstack([np.zeros((0, 2)), *(_away_from_ends(c.points, reach)
                                           for c in ordering.contours if not c.closed)])
    if len(inner) == 0:
        return False
    # each point its own atom: the spread of the points themselves
    _, cov = moments(inner, cell_atoms(pts, reach, min_per_cell=np.inf), reach)
    across = principal_axes(cov)[2]
    return bool((across >= BESIDE_SPREAD * ordering.radius).mean() >= BESIDE_SHARE)


def _away_from_ends(xy: FloatArray, reach: float) -> FloatArray:
    """The nodes of an open chain at least ``reach`` along it from both its ends."""
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(xy, axis=0), axis=1))])
    return xy[(arc >= reach) & (arc <= arc[-1] - reach)]


def _lenses(ordering: Ordering, radius: float) -> int:
    """How many closed contours of ``ordering`` are narrower on average than `LENS_WIDTH`
    radii (`wavepoly.geometry.mean_width`)."""
    return sum(_lens(c, radius) for c in ordering.contours)


def _lens(c: OrderedContour, radius: float) -> bool:
    """Whether ``c`` is closed and narrower on average than `LENS_WIDTH` x ``radius``."""
    return c.closed and mean_width(c.points) < LENS_WIDTH * radius


def _exact_reading(ordering: Ordering, pts: FloatArray, tolerance: float | None,
                   read: Callable[..., Ordering], radius: float) -> Ordering | None:
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
    them) and comes out as their outlines, not as open pieces (`OPEN_PER_RING`: a noisy
    band's pieces zigzagging through it), and in the second case leaves fewer outlines open
    or fewer points out; else None. Never a dense band (`DENSE_CURVE` points per radius
    along it or more): the Freiburg map at 0.06 (220 per radius) left 14 % out through the
    middle, and read exactly it held them all by zigzagging through its bands: 1236 teeth
    in 130 s, against 49 in 19 s through the middle. Nor a reading whose radius was widened
    beyond ``radius``: for a band many radii wide (`wavepoly.ordering.WIDE_BAND`; a clean
    sample's corners and bends, seen as noise, spread about a radius, letters packed side
    by side 1.0-1.6, and a laser map's walls at 0.0047 5-9, which read exactly zigzag), or
    for more neighbourhoods than fit in memory (`wavepoly.ordering.MAX_NODES`)."""
    if (tolerance is None or ordering.noise == 0 or ordering.per_radius >= DENSE_CURVE
            or ordering.radius > radius):
        return None  # a dense or wide band's neighbourhoods follow any turn: its spread is noise
    left_out = _left_out(ordering, pts, tolerance)
    shaped = (not ordering.through_the_middle and ordering.noise > SHAPE_SPREAD * ordering.scatter
              and (_open(ordering) > 0 or len(ordering.outliers) > 0))
    if not shaped and not (ordering.through_the_middle and left_out > MIDDLE_LOSS * len(pts)):
        return None
    exact = read(sparse=True)
    exact_out = _left_out(exact, pts, max(tolerance, exact.radius))
    # the noisy reading's middle fell apart too, and the exact one keeps far more points
    decisive = (exact_out <= left_out / EXACT_GAIN
                and 2 * _open(ordering) > len(ordering.contours)
                and _open(exact) <= OPEN_PER_RING * _closed(exact))
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


def _outer_rings(ordering: Ordering) -> int:
    """How many closed contours of ``ordering`` lie inside no other (outlines, not holes)."""
    rings = [c.points for c in ordering.contours if c.closed and len(c.points) >= 3]
    if not rings:
        return 0
    polygons = np.array([shapely.Polygon(r) for r in rings], dtype=object)
    inside = shapely.contains(polygons[:, None], shapely.points([r[0] for r in rings])[None, :])
    np.fill_diagonal(inside, False)
    return int((~inside.any(axis=0)).sum())


def _closed(ordering: Ordering) -> int:
    """How many of the contours of ``ordering`` are closed."""
    return len(ordering.contours) - _open(ordering)


def _open(ordering: Ordering) -> int:
    """How many of the contours of ``ordering`` are open."""
    return sum(not c.closed for c in ordering.contours)


def _mends_more(finer: Ordering, exact: Ordering) -> bool:
    """Whether the finer reading leaves no more outlines open than the exact one and no more
    points out. Both mend a noisy reading whose spread was the shapes' own; where they leave
    as many open and out, the finer one sees what the tolerance's neighbourhoods span: a
    serif font's hairline joining a bowl to its stem, or an arm to its stem, which read at
    the tolerance's radius as a waist between two rings (ε 4 % of the glyphs' height:
    STIX 57 -> 62 and cmr10 51 -> 53 of 68 right, its 'c' lost, a ball terminal on a
    hairline drawn as a ring of its own; at 6 %, 127 -> 128 of 204 over three serif fonts).
    A serif font at ε 4-6 % of its height: 'x', 'A' and 'w' came out with open pieces read
    exactly, closed at half the radius."""
    return (_open(finer), len(finer.outliers)) <= (_open(exact), len(exact.outliers))
