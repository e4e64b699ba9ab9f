"""Validity is part of the guarantee: simple polygons, no crossings, junctions only at ends."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

import wavepoly
from wavepoly import DataError
from wavepoly.ordering.untangle import crossing_edges, untangle
from wavepoly.samples import glyph_outlines, sample_rings
from wavepoly.types import Contour, FitResult
from wavepoly.validity import check_contours, noded_pieces, split_at_crossings_of

from .conftest import distance_to_output, teeth
from .truth import blob_sweep_case, independent_problems


def _within(points, result):
    inliers = np.setdiff1d(np.arange(len(points)), result.outliers)
    assert distance_to_output(points[inliers], result).max() <= result.tolerance * (1 + 1e-9)


def _valid(points, result):
    _within(points, result)
    assert result.validity is not None and result.validity.valid, result.validity
    assert independent_problems(result) == []


# -- the check itself ---------------------------------------------------------------------------


def test_check_finds_each_kind_of_problem():
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    bowtie = np.array([[0, 0], [1, 1], [1, 0], [0, 1]], float)
    v = check_contours([Contour(bowtie, True)])
    assert [p.kind for p in v.problems] == ["self-intersection"]
    assert np.allclose(v.problems[0].where, (0.5, 0.5))
    v = check_contours([Contour(square, True), Contour(square + 0.5, True)])
    assert [p.kind for p in v.problems] == ["crossing"]
    v = check_contours([Contour(square, True), Contour(square + [1, 0], True)])
    assert [p.kind for p in v.problems] == ["touching"]
    zigzag = np.array([[0, 0], [2, 0], [1, -1], [1, 1]], float)
    assert [p.kind for p in check_contours([Contour(zigzag, False)]).problems] == [
        "self-intersection"]
    # strokes meeting at an end point (a T and an L junction) are valid
    bar = np.array([[0, 0], [2, 0]], float)
    stem = np.array([[1, 0], [1, 1]], float)
    ell = np.array([[2, 0], [2, 1]], float)
    v = check_contours([Contour(bar, False), Contour(stem, False), Contour(ell, False)])
    assert v.valid and (v.n_closed, v.n_open) == (0, 3)
    # but a stroke crossing another is not
    cross = np.array([[1, -1], [1, 1]], float)
    assert not check_contours([Contour(bar, False), Contour(cross, False)]).valid


def test_split_at_crossings_makes_a_junction():
    a = np.array([[0.0, 0.0], [2.0, 0.0]])
    b = np.array([[1.0, -1.0], [1.0, 1.0]])
    pieces = split_at_crossings_of([a, b], [False, False])
    assert sorted(pieces) == [0, 1] and all(len(p) == 2 for p in pieces.values())
    for parts in pieces.values():
        assert all(np.allclose(p[-1], [1, 0]) or np.allclose(p[0], [1, 0]) for p in parts)
    contours = [Contour(p, False) for parts in pieces.values() for p in parts]
    assert check_contours(contours).valid


def _drawn(lines, closed):
    return shapely.union_all([shapely.linestrings(np.vstack([xy, xy[:1]]) if c else xy)
                              for xy, c in zip(lines, closed)])


def test_noded_pieces_draw_a_fold_once_and_stay_simple():
    """The end of a wall piece on a laser map (0.05 m, a made-up map scanned to 30 m): the
    selection ran along a line, back over it past its start and on: a fold that meets
    itself along a stretch, which no crossing point can cut."""
    line = np.array([[10.466, 5.323], [10.499, 5.273], [10.467, 5.276], [10.436, 5.278],
                     [10.476, 5.275], [10.515, 5.272], [10.556, 5.300]])
    assert not check_contours([Contour(line, False)]).valid
    pieces = noded_pieces([line], [False])
    assert check_contours([Contour(p, False) for p in pieces]).valid
    assert _drawn(pieces, [False] * len(pieces)).hausdorff_distance(
        _drawn([line], [False])) < 1e-12


@settings(max_examples=60, deadline=None)
@given(st.lists(st.lists(st.tuples(st.integers(0, 6), st.integers(0, 6)), min_size=2,
                         max_size=9), min_size=1, max_size=4), st.lists(st.booleans(),
                                                                        min_size=4, max_size=4))
def test_property_noded_pieces_are_valid_and_draw_the_same_lines(walks, closed):
    """Polylines on a coarse grid fold back, overlap and cross one another at will: their
    noded pieces are valid together and draw the same point set."""
    lines = [np.array(w, float) for w in walks]
    closed = [c and len(np.unique(xy, axis=0)) >= 3 for xy, c in zip(lines, closed)]
    pieces = noded_pieces(lines, closed)
    assert check_contours([Contour(p, False) for p in pieces]).valid
    drawn = _drawn([xy for xy in lines if np.ptp(xy, axis=0).any()],
                   [c for xy, c in zip(lines, closed) if np.ptp(xy, axis=0).any()])
    if not shapely.is_empty(drawn):
        assert _drawn(pieces, [False] * len(pieces)).hausdorff_distance(drawn) < 1e-9


def test_untangle_removes_a_crossing_and_keeps_the_points():
    ring = np.array([[0, 0], [2, 0], [0, 1], [2, 1]], float)  # 0-1-2-3 crosses itself
    assert len(crossing_edges(ring, True))
    fixed = untangle(ring, True)
    assert not len(crossing_edges(fixed, True))
    assert sorted(map(tuple, fixed)) == sorted(map(tuple, ring))



def test_untangle_moves_a_point_off_an_edge_it_touches():
    # a spike's loop whose corner (as the corner sharpening puts it) lies on a later leg
    a, b = np.array([8.2546, 11.5808]), np.array([8.2917, 11.5374])
    ring = np.array([[8.0, 10.0], [8.1449, 11.5009], [8.1915, 11.5255], a + 0.35 * (b - a),
                     [8.2449, 11.897], [8.151, 11.6988], a, b, [8.5, 10.0]])
    assert not shapely.Polygon(ring).is_valid and not len(crossing_edges(ring, True))
    fixed = untangle(ring, True)
    assert shapely.Polygon(fixed).is_valid
    assert sorted(map(tuple, fixed)) == sorted(map(tuple, ring))


def test_a_spike_whose_corner_touches_its_leg_stays_one_closed_outline():
    """DejaVu Sans Mono's 'W' at ε 0.1: the ordered ring's inner apex looped round a corner
    that lay on the leg beyond it; the fit cut the outline there into two open pieces."""
    shape = glyph_outlines("W", height=20.0, family="DejaVu Sans Mono")
    pts = sample_rings(shape.rings, spacing=0.03, noise=0.025, seed=11)
    result = wavepoly.fit(pts, 0.1)
    _valid(pts, result)
    assert [c.closed for c in result.contours] == [True]

def test_invalid_results_are_not_written(tmp_path):
    bowtie = np.array([[0, 0], [1, 1], [1, 0], [0, 1]], float)
    contours = [Contour(bowtie, True)]
    result = FitResult(contours, 0.1, 0.0, 0.0, np.empty(0, np.intp), 4,
                       validity=check_contours(contours))
    with pytest.raises(DataError, match="not valid.*self-intersection.*0.5, 0.5"):
        wavepoly.write_polygons(tmp_path / "out.geojson", result)
    assert list(tmp_path.iterdir()) == []


# -- fits: properties ---------------------------------------------------------------------------


@st.composite
def glyph_union(draw, tolerances=(0.02, 0.04, 0.08), noise=(0.0, 0.25)):
    """A few glyphs side by side, some close enough for their outlines to nearly touch."""
    text = draw(st.text(alphabet="BOSW8&kx%e", min_size=1, max_size=3))
    eps = draw(st.sampled_from(tolerances))
    noise = draw(st.floats(*noise)) * eps
    seed = draw(st.integers(0, 10**6))
    pts = sample_rings(glyph_outlines(text, height=1.0).rings, spacing=eps / 3, noise=noise,
                       seed=seed)
    return pts, eps


@settings(max_examples=10, deadline=None)
@given(glyph_union())
def test_property_valid_and_within_tolerance_on_glyphs(case):
    pts, eps = case
    _valid(pts, wavepoly.fit(pts, eps))


@st.composite
def random_walls(draw):
    """A few straight walls of a floor plan, 1-4 m long, crossing and meeting at will, some
    doubled 0.5-3 ε apart (a thin wall's two faces), sampled densely with Gaussian noise as
    a laser map's bands: the crossings and folds the selection must keep valid."""
    eps = draw(st.sampled_from((0.05, 0.1)))
    rng = np.random.default_rng(draw(st.integers(0, 10**6)))
    noise = draw(st.floats(0.0, 0.3)) * eps
    walls = []
    for _ in range(draw(st.integers(2, 6))):
        a = rng.uniform(0, 4, 2)
        d = rng.normal(size=2)
        d /= np.linalg.norm(d)
        b = a + d * rng.uniform(1, 4)
        walls.append((a, b))
        if rng.uniform() < 0.3:  # the wall's other face
            n = np.array([-d[1], d[0]]) * rng.uniform(0.5, 3) * eps
            walls.append((a + n, b + n))
    pts = []
    for a, b in walls:
        t = rng.uniform(0, 1, max(8, int(np.linalg.norm(b - a) / (eps / 6))))
        pts.append(a + t[:, None] * (b - a))
    pts = np.concatenate(pts)
    return pts + rng.normal(0, noise, pts.shape) if noise > 0 else pts, eps


@settings(max_examples=12, deadline=None)
@given(random_walls())
def test_property_valid_and_within_tolerance_on_crossing_walls(case):
    """Walls that cross, meet at T's and run side by side closer than the tolerance: the
    result is valid and every point not listed as an outlier is within ε."""
    pts, eps = case
    _valid(pts, wavepoly.fit(pts, eps))


@settings(max_examples=10, deadline=None)
@given(glyph_union(tolerances=(0.01, 0.02), noise=(0.15, 0.25)))
def test_property_clean_samplings_have_no_outliers(case):
    """Noise at most ε / 4 on glyphs 50-100 tolerances high: valid, within the tolerance,
    and no point left out as an outlier. (On glyphs 12 tolerances high the windows that
    measure the noise hold corners and both walls of a stroke, and the scatter measured is
    not the noise.)"""
    pts, eps = case
    result = wavepoly.fit(pts, eps)
    _valid(pts, result)
    assert len(result.outliers) == 0


@settings(max_examples=10, deadline=None)
@given(st.floats(1.5, 4.0), st.floats(0.0, 0.25), st.booleans(), st.integers(0, 10**6))
def test_property_near_touching_and_nested_rings(gap, noise, nested, seed):
    """Two rings a few tolerances apart, side by side or one inside the other."""
    eps = 0.05
    rng = np.random.default_rng(seed)
    t = rng.uniform(0, 2 * np.pi, (2, 3000))
    inner = 1.0 - gap * eps if nested else 1.0
    centre = 0.0 if nested else 2.0 + gap * eps
    pts = np.vstack([np.column_stack([np.cos(t[0]), np.sin(t[0])]),
                     np.column_stack([centre + inner * np.cos(t[1]), inner * np.sin(t[1])])])
    pts += rng.normal(scale=noise * eps, size=pts.shape)
    result = wavepoly.fit(pts, eps)
    _valid(pts, result)
    assert sorted(c.closed for c in result.contours) == [True, True]
    assert len(result.outliers) == 0



@settings(max_examples=10, deadline=None)
@given(st.floats(1.5, 2.5), st.floats(4.0, 6.0), st.floats(0.0, 0.125), st.floats(0, 360),
       st.integers(0, 10**6))
def test_property_small_hole_near_its_outline(gap, size, noise, angle, seed):
    """A round hole a few tolerances across, ``gap`` ε inside a disk's wall (the validity
    benchmark's small holes): valid, within the tolerance, and the hole drawn as a hole."""
    from benchmarks.holes import small_hole

    pts = sample_rings(small_hole(size, gap, angle), spacing=1 / 3, noise=noise, seed=seed)
    result = wavepoly.fit(pts, 1.0)
    _valid(pts, result)
    assert [c.closed for c in result.contours] == [True, True]
    assert sorted(result.parents) == [-1, 0]
    assert len(result.outliers) == 0

# -- regression: the shared cases ---------------------------------------------------------------


@pytest.mark.parametrize("name, eps", [
    ("noisy_sets/crab_2percent_noise.txt", 0.0422), ("noisy_sets/Keyboard0.txt", 0.00609),
    ("noisy_sets/fish.txt", 0.02), ("noisy_sets/bot.txt", 0.02),
    ("hnn_crust/crocodile-conf.p2d", 0.02)])
def test_shared_silhouettes_come_out_valid(shared_data, name, eps):
    pts = wavepoly.as_planar(wavepoly.read_points(shared_data / "curves2d" / name))
    _valid(pts, wavepoly.fit(pts, eps))


@pytest.mark.parametrize("name, eps", [("ventilator.p2d", 43.0), ("crocodile-conf.p2d", 7.1)])
def test_sparse_crust_sets_at_twice_their_spacing_are_whole_outlines(shared_data, name, eps):
    """Clean sparse samples at twice their spacing (what ``wavepoly info`` suggests): the
    radius widened to 3 spacings measured the outline's turns as noise, the curve ran
    through the middle and left 169 of 194 and 85 of 129 points out. Read again exactly,
    the chain of centroids over those wider neighbourhoods cut the turns by more than the
    tolerance, which the fit covers, and that reading was refused for it."""
    pts = wavepoly.as_planar(wavepoly.read_points(shared_data / "curves2d" / "hnn_crust" / name))
    result = wavepoly.fit(pts, eps)
    _valid(pts, result)
    assert [c.closed for c in result.contours] == [True]
    assert len(result.outliers) == 0


@pytest.mark.parametrize("eps", [0.05, 0.1])
def test_intel_map_comes_out_valid(shared_data, eps):
    pts = wavepoly.read_points(shared_data / "lidar2d" / "intel-corrected.log.gz")
    _valid(pts, wavepoly.fit(pts, eps))



@pytest.mark.parametrize("offset", [(0.0, 0.0), (0.033, 0.071)])
def test_intel_map_at_four_times_its_scatter_leaves_under_one_percent_out(shared_data, offset):
    """The issue's bar: outliers at most 1 % at 0.1 m. Shifted by (0.033, 0.071) m the map
    left 1.08 % out; its strokes of 3-4 tolerances are contours now (0.93 %)."""
    pts = wavepoly.read_points(shared_data / "lidar2d" / "intel-corrected.log.gz") + offset
    result = wavepoly.fit(pts, 0.1)
    assert len(result.outliers) <= 0.01 * len(pts)

def test_keyboard_silhouette_is_two_closed_outlines(shared_data):
    """The ordering used to march back across a thin part of the outline (a self-crossing
    that every polygon in that order inherits); untangled, it is two simple polygons."""
    pts = wavepoly.read_points(shared_data / "curves2d" / "noisy_sets" / "Keyboard0.txt")
    result = wavepoly.fit(pts, 0.00609)
    _valid(pts, result)
    assert [c.closed for c in result.contours] == [True, True]


def test_small_loops_and_strokes_are_contours_not_outliers():
    """A loop or a stroke of 4 tolerances, beside a big outline, is a contour (a hoof in a leg
    slice), not a group of outliers."""
    eps = 0.05
    rng = np.random.default_rng(5)
    t = rng.uniform(0, 2 * np.pi, 6000)
    big = np.column_stack([2 * np.cos(t), 2 * np.sin(t)])
    t = rng.uniform(0, 2 * np.pi, 40)
    loop = np.column_stack([3 + 2 * eps * np.cos(t), 2 * eps * np.sin(t)])
    s = rng.uniform(0, 4 * eps, 30)
    stroke = np.column_stack([-3 + s, 0.5 + 0 * s])
    pts = np.vstack([big, loop, stroke]) + rng.normal(scale=eps / 8, size=(6070, 2))
    result = wavepoly.fit(pts, eps)
    _valid(pts, result)
    assert len(result.outliers) == 0
    assert sorted(c.closed for c in result.contours) == [False, True, True]


@pytest.mark.parametrize("char, spacing, noise, eps, seed", [
    ("0", 0.02, 0.025, 0.1, 6),  # a noise point 1.07 ε from the true glyph
    ("m", 0.05, 0.0, 0.12, 5),  # a notch tip the chain rounded off by 1.25 ε
    ("a", 0.02, 0.02, 0.1, 4)])  # the acute tip of the tail
def test_clean_samplings_have_no_outliers(char, spacing, noise, eps, seed):
    """Members a little beyond the radius from the ordered chain, on a scan whose scatter is at
    most ε / 4, are covered by the polygon, not listed as outliers."""
    pts = sample_rings(glyph_outlines(char, height=20.0).rings, spacing=spacing, noise=noise,
                       seed=seed)
    result = wavepoly.fit(pts, eps)
    _valid(pts, result)
    assert len(result.outliers) == 0


@pytest.mark.parametrize("char, family, spacing, noise, eps, seed", [
    ("B", "DejaVu Sans", 0.02, 0.02, 0.1, 4),  # the waist's tip came out as an open stroke
    ("8", "DejaVu Serif", 0.03, 0.01, 0.08, 3),  # ... or as 8 outliers 2.7 radii beyond
    ("b", "DejaVu Serif", 0.03, 0.025, 0.1, 11),  # ... or as a little loop off the bisector
    ("M", "STIXGeneral", 0.05, 0.02, 0.3, 12)])  # ... or as a chain of 2 nodes (11 outliers)
def test_a_notch_is_followed_to_its_tip(char, family, spacing, noise, eps, seed):
    """Where two walls of an outline converge to a notch, the march turns back a few radii
    before the tip; the closed outline still reaches it (the right number of closed
    outlines, no open piece, no outliers)."""
    shape = glyph_outlines(char, height=20.0, family=family)
    pts = sample_rings(shape.rings, spacing=spacing, noise=noise, seed=seed)
    result = wavepoly.fit(pts, eps)
    _valid(pts, result)
    assert [c.closed for c in result.contours] == [True] * len(shape.rings)
    assert len(result.outliers) == 0


def test_a_loop_through_strays_does_not_cut_an_outline_open():
    """Sparse noisy samples (spacing ε / 3, noise ε / 4): the march closed a loop of 4 nodes
    through strays beside the 'g', which crossed its outline; both were split at the
    crossings and the outline came out as 3 open pieces."""
    shape = glyph_outlines("g", height=20.0)
    pts = sample_rings(shape.rings, spacing=0.03, noise=0.025, seed=11)
    result = wavepoly.fit(pts, 0.1)
    _valid(pts, result)
    assert [c.closed for c in result.contours] == [True, True]


def test_parts_of_an_outline_that_nearly_touch_make_one_outline():
    """The arms of a STIX 'k' meet its stem through a slit narrower than the tolerance: the
    march ran along the stem across the slit and the arms closed a ring of their own, sharing
    the stem's edge; split at the crossings, the 'k' came out as 3 open pieces."""
    shape = glyph_outlines("k", height=20.0, family="STIXGeneral")
    pts = sample_rings(shape.rings, spacing=0.05, noise=0.02, seed=12)
    result = wavepoly.fit(pts, 0.3)
    _valid(pts, result)
    assert [c.closed for c in result.contours] == [True]
    assert shapely.Polygon(result.contours[0].vertices).area == pytest.approx(
        shapely.Polygon(shape.rings[0]).area, rel=0.05)


def test_a_small_loop_of_a_few_points_is_a_contour():
    """Seven points round a hole 6 tolerances wide, in a silhouette sampled more sparsely than
    the tolerance (the radius widened to 3 spacings, wider than the loop): the march makes no
    chain of them, and they were outliers."""
    eps = 0.002
    t = np.linspace(0, 2 * np.pi, 600, endpoint=False)
    ring = np.column_stack([np.cos(t), np.sin(t)])
    s = np.linspace(0, 2 * np.pi, 7, endpoint=False) + 0.3
    loop = 0.006 * np.column_stack([np.cos(s), np.sin(s)])
    pts = np.vstack([ring, loop])
    result = wavepoly.fit(pts, eps)
    _valid(pts, result)
    assert sorted(c.closed for c in result.contours) == [True, True]
    assert len(result.outliers) == 0


def test_a_sliver_of_a_hole_two_tolerances_long_is_a_contour():
    """Thirteen points round a sliver 1.9 tolerances long and a third as wide (what a slit
    leaves of a silhouette's hole, row 0 seed 53 of the benchmark): the directions from its
    centre leave a gap of about 125 degrees, and its points were outliers."""
    eps = 0.0033
    t = np.linspace(0, 2 * np.pi, 1900, endpoint=False)
    ring = 0.3 * np.column_stack([np.cos(t), np.sin(t)])
    s = np.linspace(0, 2 * np.pi, 13, endpoint=False) + 0.2
    sliver = np.column_stack([0.001 * np.cos(s), 0.003 * np.sin(s)]) + [0.1, 0.0]
    pts = np.vstack([ring, sliver])
    result = wavepoly.fit(pts, eps)
    _valid(pts, result)
    assert sorted(c.closed for c in result.contours) == [True, True]
    assert len(result.outliers) == 0


def test_a_sliver_sampled_unevenly_is_a_contour():
    """The hole left between three touching disks is a thin curved triangle; sampled at
    random, its long side held no point between its ends (these 15 points, in tolerances, are
    the stress sweep's union of disks, seed 3). The points' mean leaned to the denser sides,
    the long side spanned 136 degrees from it, and the 15 points were outliers on a clean
    scan."""
    eps = 1.0
    t = np.linspace(0, 2 * np.pi, 1500, endpoint=False)
    ring = 80 * np.column_stack([np.cos(t), np.sin(t)])
    sliver = np.array([[1.195, 0.354], [0.087, 0.951], [0.055, 0.975], [1.156, 0.419],
                       [0.416, 1.512], [0.119, 1.336], [0.907, 0.878], [1.283, 0.204],
                       [0.317, 0.779], [0.0, 1.017], [1.375, 0.049], [1.322, 0.138],
                       [0.596, 1.48], [0.791, 1.099], [1.404, 0.0]])
    pts = np.vstack([ring, sliver])
    result = wavepoly.fit(pts, eps)
    _valid(pts, result)
    assert sorted(c.closed for c in result.contours) == [True, True]
    assert len(result.outliers) == 0


def test_vase_silhouette_keeps_its_hole(shared_data):
    pts = wavepoly.read_points(shared_data / "curves2d" / "noisy_sets" / "vase.txt")
    result = wavepoly.fit(pts, 0.00102)
    _valid(pts, result)
    assert [c.closed for c in result.contours] == [True, True]
    assert len(result.outliers) == 0


def test_a_tolerance_below_the_scatter_is_said_and_a_better_one_suggested():
    rng = np.random.default_rng(2)
    t = rng.uniform(0, 2 * np.pi, 20000)
    pts = np.column_stack([np.cos(t), np.sin(t)]) * 3 + rng.normal(scale=0.03, size=(20000, 2))
    low = wavepoly.fit(pts, 0.04)
    assert low.suggested_tolerance is not None and 0.07 <= low.suggested_tolerance <= 0.12
    assert "try" in wavepoly.fit_summary(low)[-len(low.notes) - 1]
    _valid(pts, low)
    assert wavepoly.fit(pts, low.suggested_tolerance).suggested_tolerance is None


def test_a_tolerance_just_above_twice_a_bell_of_noise_runs_through_the_middle(seed=0):
    """A room's four walls scanned with Gaussian scatter 0.022 (a bell: the spread over a
    neighbourhood is the points' own scatter), at a tolerance of 0.05, 2.3 sigma: some 2 %
    of the points lie farther than the tolerance from the wall's middle. Reaching them broke
    the room into 17-21 pieces with teeth; the walls now run through the middle, the points
    beyond are listed and a tolerance is suggested."""
    rng = np.random.default_rng(seed)
    corners = np.array([[0, 0], [4, 0], [4, 3], [0, 3]], float)
    walls = []
    for a, b in zip(corners, np.roll(corners, -1, axis=0)):
        n = int(4000 * np.linalg.norm(b - a))
        normal = np.array([a[1] - b[1], b[0] - a[0]]) / np.linalg.norm(b - a)
        walls.append(a + rng.uniform(0, 1, (n, 1)) * (b - a)
                     + rng.normal(0, 0.022, (n, 1)) * normal)
    pts = np.vstack(walls)
    result = wavepoly.fit(pts, 0.05)
    _valid(pts, result)
    assert [c.closed for c in result.contours] == [True] and teeth(result) == 0
    assert 0.06 <= result.suggested_tolerance <= 0.08
    assert len(result.outliers) <= 0.04 * len(pts)


def _ring_band(n, scatter, seed=4, radius=3.0):
    rng = np.random.default_rng(seed)
    t = rng.uniform(0, 2 * np.pi, n)
    r = radius + rng.normal(scale=scatter, size=n)
    return np.column_stack([r * np.cos(t), r * np.sin(t)])


def test_below_the_scatter_the_curve_runs_through_the_middle_of_the_band():
    """A ring scanned with scatter 0.06 at tolerance 0.05: a polygon that kept every point
    within the tolerance zigzagged from side to side of the band. The curve now follows the
    middle of the band, and the points beyond the tolerance are listed as outliers."""
    pts = _ring_band(20000, 0.06)
    res = wavepoly.fit(pts, 0.05)
    _valid(pts, res)
    assert [c.closed for c in res.contours] == [True]
    radial = np.linalg.norm(res.contours[0].vertices, axis=1) - 3.0
    assert np.abs(radial).max() < 0.03  # the middle of the band, not its sides
    # a zigzag across the band is far longer than the ring
    assert shapely.Polygon(res.contours[0].vertices).length < 1.01 * 2 * np.pi * 3.0
    # the outliers are the noise beyond the tolerance: about the Gaussian share beyond 0.83 σ
    assert 0.3 < len(res.outliers) / len(pts) < 0.5
    assert any("middle of the noise" in n for n in res.notes)


def test_a_noisy_band_sampled_coarser_than_the_tolerance_is_one_contour():
    """1000 points round a ring with scatter 0.15, at tolerance 0.02 (as fish.txt): the point
    spacing widens the radius 9-fold, so the ordering read them as a sparse clean sample, and
    the ring fell apart into a dozen zigzag pieces. Read as a noisy band, it is one ring."""
    pts = _ring_band(1000, 0.15)
    res = wavepoly.fit(pts, 0.02)
    _valid(pts, res)
    assert [c.closed for c in res.contours] == [True]
    radial = np.linalg.norm(res.contours[0].vertices, axis=1) - 3.0
    assert np.abs(radial).max() < 0.15
    assert any("noisy band" in n for n in res.notes)
    assert res.suggested_tolerance is not None and res.suggested_tolerance >= 0.3


def test_the_scatter_is_the_same_at_every_tolerance():
    """The points' own scatter is measured over a few scatters, not over the radius: a wavy
    ring (bumps 0.15 high, 1.26 apart) with scatter 0.02 measures 0.014-0.016 whether fitted at
    0.05 or 0.15 (a little low: over so small a window the regression line leans towards the
    points); over three radii, the spread that sizes the neighbourhoods, the bumps count too,
    and it grows with the tolerance."""
    rng = np.random.default_rng(5)
    t = rng.uniform(0, 2 * np.pi, 30000)
    r = 6 + 0.15 * np.sin(30 * t) + rng.normal(scale=0.02, size=len(t))
    pts = np.column_stack([r * np.cos(t), r * np.sin(t)])
    for tolerance in (0.05, 0.15):
        ordering = wavepoly.order_points(pts, tolerance, tolerance=tolerance)
        assert 0.012 <= ordering.scatter <= 0.022
    assert ordering.noise > 2 * ordering.scatter


def test_crab_keeps_its_legs(shared_data):
    """crab_2percent_noise at 0.0422: its legs, over three radii, looked like a scatter of
    0.042, but the points' own scatter is 0.013; the tolerance is above twice it, so the
    polygon covers the legs and no point is dropped as noise. The spread over a neighbourhood
    is 3.2 x that scatter, the legs' turns and not a halo: it drew a suggestion of 0.13, which
    would round the legs off; no longer. Neighbourhoods 5 x that spread wide drew the claws as
    triangles across them and left 4 points out; sized by the spread about the legs' bends
    (0.032), they follow the claws and keep every point."""
    pts = wavepoly.read_points(shared_data / "curves2d" / "noisy_sets" / "crab_2percent_noise.txt")
    res = wavepoly.fit(pts, 0.0422)
    _valid(pts, res)
    assert [c.closed for c in res.contours] == [True]
    assert len(res.outliers) == 0 and res.suggested_tolerance is None


@pytest.mark.parametrize("name, closed", [("fish.txt", [True]), ("bot.txt", [False])])
def test_fish_and_bottle_at_a_tolerance_below_their_scatter(shared_data, name, closed):
    """fish.txt and bot.txt at 0.02, a tenth of their scatter: one outline each (the bottle's
    neck is open), through the middle of the band, and a suggested tolerance that, once
    used, draws no further suggestion (at 0.57 the bottle's mouth, 6 tolerances wide, is
    joined as a gap in the scan)."""
    pts = wavepoly.read_points(shared_data / "curves2d" / "noisy_sets" / name)
    res = wavepoly.fit(pts, 0.02)
    _valid(pts, res)
    assert [c.closed for c in res.contours] == closed
    assert res.n_vertices < 60
    again = wavepoly.fit(pts, res.suggested_tolerance)
    _valid(pts, again)
    assert again.suggested_tolerance is None and len(again.contours) == 1
    assert len(again.outliers) <= 0.03 * len(pts)


def test_a_fish_whose_fins_spread_like_a_halo_keeps_them(shared_data):
    """fish.txt at 0.71, some 3 times its scatter: over a neighbourhood its fins spread
    twice as wide as its scatter, as a halo about a thin core does, and the curve ran through
    the middle, listing the head and tail fins as outliers (253 of 1000 points). No core
    holds the points, so the outline follows the fins."""
    pts = wavepoly.read_points(shared_data / "curves2d" / "noisy_sets" / "fish.txt")
    res = wavepoly.fit(pts, 0.71)
    _valid(pts, res)
    assert [c.closed for c in res.contours] == [True]
    assert len(res.outliers) <= 0.01 * len(pts)
    assert res.suggested_tolerance is None


def _drawn_length(result):
    return sum((shapely.Polygon(c.vertices).length if c.closed
                else shapely.LineString(c.vertices).length) for c in result.contours)


def test_intel_walls_below_their_halo_are_not_zigzags(shared_data):
    """The Intel map at 0.05: its walls have a core of scatter 0.018 and a halo (poses seen
    from afar) that spreads 0.027 over a neighbourhood. Halo points put into the chain as
    corners zigzagged every wall from edge to edge: 1155 m of lines against 843 m at 0.1.
    The walls now run through the core, no longer than at 0.1; the halo beyond the tolerance
    is listed, and the suggested tolerance holds."""
    pts = wavepoly.read_points(shared_data / "lidar2d" / "intel-corrected.log.gz")
    low, high = wavepoly.fit(pts, 0.05), wavepoly.fit(pts, 0.1)
    _valid(pts, low)
    assert _drawn_length(low) < 1.02 * _drawn_length(high)
    assert any("halo" in n for n in low.notes) and low.suggested_tolerance is not None
    assert len(low.outliers) < 0.12 * len(pts)
    assert not any("halo" in n for n in high.notes) and high.suggested_tolerance is None


@pytest.mark.parametrize("eps", [0.08, 0.09])
def test_intel_walls_a_little_below_four_scatters_are_not_zigzags(shared_data, eps):
    """At 0.08-0.09 the Intel map measured 11 points per radius by the spacing of neighbours
    (points per area across its bands), under a dense curve's 12, and was read as a clean
    sparse sample: every stray within reach of a wall became a corner, 281-310 teeth and
    2.3-2.5 x the vertices at 0.1, in 40 s. Its walls hold 30-40 points per radius; read as
    the noisy scan it is, they have about as few teeth as at 0.1 (21)."""
    pts = wavepoly.read_points(shared_data / "lidar2d" / "intel-corrected.log.gz")
    result = wavepoly.fit(pts, eps)
    _valid(pts, result)
    assert teeth(result) <= 60
    assert result.n_vertices < 1.5 * 1719  # at 0.1


@pytest.mark.parametrize("text", ["8", "e", "%"])
def test_glyphs_scanned_noisier_than_the_tolerance_are_clean_outlines(text):
    """Glyphs sampled with scatter 0.7 x the tolerance: a polygon keeping every point within
    it zigzagged through the noise, 1.45-1.5 x as long as the outline. Through the middle of
    the noise, each ring is one clean outline as long as the true one, and the points beyond
    the tolerance (the Gaussian share beyond 1.43 sigma: 15 %) are listed."""
    eps = 0.1
    shape = glyph_outlines(text)
    pts = sample_rings(shape.rings, spacing=eps / 3, noise=0.7 * eps, seed=1)
    res = wavepoly.fit(pts, eps)
    _valid(pts, res)
    assert [c.closed for c in res.contours] == [True] * len(shape.rings)
    drawn = sum(shapely.LinearRing(c.vertices).length for c in res.contours)
    true = sum(shapely.LinearRing(r).length for r in shape.rings)
    assert drawn < 1.03 * true
    assert 0.1 < len(res.outliers) / len(pts) < 0.2


@pytest.mark.parametrize("seed", [4, 20, 28, 48])
def test_a_bitmap_traced_outline_with_noise_has_no_outliers(seed):
    """A silhouette traced from a 200-pixel bitmap (staircase walls a pixel, ε / 2, high)
    sampled with noise ε / 4: the staircase adds to the scatter the ordering measures
    (0.28-0.31 radii), but the sampling is clean, and no point is an outlier (1 or 2 were,
    at a limb's tip or where a limb meets the body). Seed 48: the march stopped 12.4 radii
    short of closing the outline, at a limb whose walls merged (one open piece)."""
    from benchmarks.silhouettes import bitmap, sample, silhouette

    rings = bitmap(silhouette(seed), 200)
    eps = 0.01  # the silhouette is 1 unit across its diagonal
    pts = sample(rings, 2000, eps / 4, 1000 + seed)
    result = wavepoly.fit(pts, eps)
    _valid(pts, result)
    assert len(result.outliers) == 0
    assert [c.closed for c in result.contours] == [True] * len(rings)


def test_a_slit_whose_wavelet_polygon_crosses_itself_comes_out_one_valid_outline():
    """Silhouette 13: a slit whose walls run closer than ε for most of its length. The
    wavelet polygon of its walls crossed itself, and the selection, which never forbids that
    polygon's edges, kept a crossing: the outline came out in 4 open pieces. On a clean scan
    the repaired ordered points are the simple backbone, and the selection gets the rounds it
    needs to settle (38 vertices, not the backbone's 970)."""
    from benchmarks.silhouettes import sample, silhouette

    eps = 1 / 300  # the silhouette is 1 unit across its diagonal
    pts = sample(silhouette(13), 3000, eps / 8, 1013)
    result = wavepoly.fit(pts, eps)
    _valid(pts, result)
    assert [c.closed for c in result.contours] == [True]
    assert len(result.outliers) == 0
    assert len(result.contours[0].vertices) < 100


def test_a_selection_crossing_the_backbone_for_many_rounds_settles_with_few_vertices():
    """Silhouette 20 with noise ε/3: a spike of the backbone (reaching a far noise point)
    crossed a wall's long chord, and each round forbade that chord only for the path to take
    the next one along it. After 200 rounds the fit fell back on the backbone, 589 vertices
    in a zigzag through the noise, where the selection had 73."""
    from benchmarks.silhouettes import sample, silhouette

    rings = silhouette(20)
    eps = float(np.hypot(*np.ptp(np.vstack(rings), axis=0))) / 150
    pts = sample(rings, 3000, eps / 3, 1020)
    result = wavepoly.fit(pts, eps)
    _valid(pts, result)
    assert [c.closed for c in result.contours] == [True]
    assert result.n_vertices < 100
    assert teeth(result) <= 1


def _figure_eight(turn_deg: float, gap: float = 0.1, spacing: float = 0.1) -> np.ndarray:
    """A closed chain round two unit circles whose outlines come ``gap`` apart, crossing from
    one to the other by the kiss: leaving each ``turn_deg`` degrees short of it."""
    def arc(centre, start, stop):
        n = int(np.radians(abs(stop - start)) / spacing)
        t = np.radians(np.linspace(start, stop, n))
        return np.column_stack([centre[0] + np.cos(t), centre[1] + np.sin(t)])

    left, right = (-1 - gap / 2, 0.0), (1 + gap / 2, 0.0)
    return np.vstack([arc(left, turn_deg, 360 - turn_deg),  # round the left circle
                      arc(right, 180 - turn_deg, -180 + turn_deg)])  # then round the right


def test_a_figure_eight_at_a_kiss_splits_into_two_rings():
    from wavepoly.ordering.untangle import split_kissing_rings

    chain = _figure_eight(60.0)
    assert len(crossing_edges(chain, True)) == 1  # the march crossed over at the kiss
    rings = split_kissing_rings(chain, radius=0.2)
    assert len(rings) == 2
    polys = sorted((shapely.Polygon(r) for r in rings), key=lambda p: p.centroid.x)
    assert all(p.is_valid for p in polys) and not polys[0].intersects(polys[1])
    for poly, x in zip(polys, (-1.05, 1.05)):  # each ring holds one circle's points
        xy = np.asarray(poly.exterior.coords)
        assert np.allclose(np.hypot(xy[:, 0] - x, xy[:, 1]), 1.0)
    assert sorted(map(tuple, np.vstack(rings))) == sorted(map(tuple, chain))


def test_a_shallow_crossing_in_a_neck_stays_one_ring():
    # passes that cross at a shallow angle ran along a neck narrower than the tolerance: one
    # outline, untangled (here the passes cross at about 41 degrees)
    from wavepoly.ordering.untangle import split_kissing_rings

    rings = split_kissing_rings(_figure_eight(10.0), radius=0.2)
    assert len(rings) == 1 and shapely.LinearRing(rings[0]).is_simple


def _strip_with_a_swap(width: float = 1.0, swap: float = 0.6, spacing: float = 0.2
                       ) -> np.ndarray:
    """A closed chain round a strip 10 long and ``width`` wide that swaps walls half way
    along, both ways: its two passes cross there like an X (at about 62 degrees)."""
    def wall(x0, x1, y):
        n = int(abs(x1 - x0) / spacing)
        return np.column_stack([np.linspace(x0, x1, n, endpoint=False), np.full(n, y)])

    mid = 5.0
    return np.vstack([wall(0.0, mid, 0.0), wall(mid + swap, 10.0, width),
                      wall(10.0, mid + swap, 0.0), wall(mid, 0.0, width)])


def test_a_stroke_the_march_crossed_stays_one_ring():
    """A chain that swapped walls inside a stroke narrower than the neighbourhoods (a serif
    font's hairline at 4 % of its height) crosses itself as at a kiss, but each loop the
    split would leave closes on a U-turn across the stroke: one outline, untangled. STIX's
    's', 'j' and '@' at ε 0.8 (20 high, noise 0.1) were cut in two at a hairline."""
    from wavepoly.ordering.untangle import (
        KISS_CLOSING_TURN,
        _kissing_split,
        pass_turns,
        split_kissing_rings,
    )

    chain = _strip_with_a_swap()
    (i, j), = crossing_edges(chain, True)
    _, from_i, from_j = pass_turns(chain, np.array([i]), np.array([j]))
    assert min(from_i[0], from_j[0]) > KISS_CLOSING_TURN  # both loops turn back
    assert _kissing_split(chain, radius=0.4) is None
    rings = split_kissing_rings(chain, radius=0.4)
    assert len(rings) == 1 and shapely.Polygon(rings[0]).is_valid


@pytest.mark.parametrize("char", ["s", "j", "@"])
def test_serif_hairlines_at_a_coarse_tolerance_keep_their_rings(char):
    """STIX at ε 0.8 (4 % of its height), whose hairlines are thinner than the neighbourhoods:
    the march crossed a hairline, and the glyph was cut in two there (`untangle`)."""
    shape = glyph_outlines(char, height=20.0, family="STIXGeneral")
    pts = sample_rings(shape.rings, spacing=0.1, noise=0.1, seed=11)
    result = wavepoly.fit(pts, 0.8)
    _valid(pts, result)
    assert [c.closed for c in result.contours] == [True] * len(shape.rings)


@pytest.mark.parametrize(("char", "spacing", "noise", "eps"),
                         [("x", 0.1, 0.1, 0.8), ("A", 0.15, 0.05, 1.2), ("w", 0.15, 0.05, 1.2)])
def test_a_finer_reading_that_closes_more_wins_over_an_exact_one(char, spacing, noise, eps):
    """STIX at ε 4-6 % of its height: read as noise, the walls of its strokes looked like
    scatter; read exactly at the tolerance's radius, pieces stayed open ('A' three of four),
    where at half the radius every ring closes (`ordering.rereading._mends_more`)."""
    shape = glyph_outlines(char, height=20.0, family="STIXGeneral")
    pts = sample_rings(shape.rings, spacing=spacing, noise=noise, seed=11)
    result = wavepoly.fit(pts, eps)
    _valid(pts, result)
    assert [c.closed for c in result.contours] == [True] * len(shape.rings)


@pytest.mark.parametrize("char", ["K", "u", "a"])
def test_a_hairline_the_tolerance_spans_is_read_finer_where_that_ties(char):
    """STIX at ε 0.8 (4 % of its height) as the glyph sweep samples it: read as noise, then
    exactly and at half the radius, each leaving nothing open or out. Read exactly, the
    hairline joining a bowl or an arm to its stem was a waist between two rings ('K', 'u'),
    or the march ran across one and lost a counter ('a'); at half the radius it is drawn
    (`ordering.rereading._mends_more`)."""
    shape = glyph_outlines(char, height=20.0, family="STIXGeneral")
    pts = sample_rings(shape.rings, spacing=0.1, noise=0.1, seed=13)
    result = wavepoly.fit(pts, 0.8)
    _valid(pts, result)
    assert [c.closed for c in result.contours] == [True] * len(shape.rings)


@pytest.mark.parametrize(("family", "char"), [("cmr10", "M"), ("cmr10", "s"),
                                               ("STIXGeneral", "3")])
def test_a_finer_reading_that_breaks_a_hairline_does_not_win(family, char):
    """Serif glyphs at ε 0.8 (4 % of their height) as the glyph sweep samples them: read at
    the tolerance's radius, one closed outline with nothing open or out; at half the radius
    (less spread measured, so that reading was kept) the neighbourhoods break a hairline
    and the outline came out as two rings side by side (`ordering.rereading`)."""
    shape = glyph_outlines(char, height=20.0, family=family)
    pts = sample_rings(shape.rings, spacing=0.1, noise=0.1, seed=13)
    result = wavepoly.fit(pts, 0.8)
    _valid(pts, result)
    assert [c.closed for c in result.contours] == [True] * len(shape.rings)


@pytest.mark.parametrize(("seed", "noise"), [(9, 0.0), (14, 0.0)])
def test_blobs_touching_at_a_pixel_corner_stay_two_rings(seed, noise):
    """Random blobs (the benchmark's blob sweep, size 0.1) of which two touch at a pixel's
    corner, their outlines 0.4-0.9 ε apart there: the march ran from one onto the other, and
    untangling its chain drew both as one outline with a neck (one ring short before).
    (Seed 10 with noise ε / 4 came out with as many contours as rings only because one ring
    drawn in two pieces made up for two blobs drawn as one; the count was no test of it.)"""
    pts, result, rings = blob_sweep_case(seed, noise)
    assert all(c.closed for c in result.contours)
    assert len(result.contours) == len(rings)
    assert len(result.outliers) == 0
    _valid(pts, result)


def test_a_head_on_a_neck_narrower_than_the_tolerance_stays_one_ring():
    # silhouette 33 from a 300-pixel bitmap: an arm's tip touches the head, and the march
    # crossed there at a shallow angle; the truth is one ring
    from benchmarks.bench_validity import SILHOUETTE_SAMPLINGS
    from benchmarks.silhouettes import bitmap, sample, silhouette

    pixels, n, eps, noise = SILHOUETTE_SAMPLINGS[3]
    pts = sample(bitmap(silhouette(33), pixels), n, noise * eps, 1033)
    result = wavepoly.fit(pts, eps)
    assert [c.closed for c in result.contours] == [True]
    _valid(pts, result)


def test_rings_split_at_a_neck_stay_closed_when_fitted(monkeypatch):
    """Two closed rings the ordering left nearly touching (here forced: blob sweep seed 14,
    noise ε/4, every crossing read as a kiss): the second ring's repaired wavelet polygon cut
    across the first's edges, the selection may always fall back on it, and both rings were
    split into open pieces at the crossing. Its backbone is now its repaired ordered points."""
    import wavepoly.ordering.untangle as untangle_module
    monkeypatch.setattr(untangle_module, "KISS_ANGLE", 0.0)
    pts, result, _ = blob_sweep_case(14, 0.25)
    assert all(c.closed for c in result.contours)
    _valid(pts, result)


def test_a_ring_fitted_first_keeps_clear_of_a_closed_neighbour_still_to_come():
    """Blob sweep seed 36 (size 0.1, noise ε/4, not among the benchmark's seeds): two rings
    split at a kiss, the larger fitted first cut its corner across the smaller one's ordered
    points, so no polygon of the smaller one could keep clear of it, and both were split
    open at the crossing (2 open pieces). The first now keeps clear of the second's ordered
    ring."""
    pts, result, _ = blob_sweep_case(36, 0.25)
    assert all(c.closed for c in result.contours)
    _valid(pts, result)


def test_a_dot_beyond_a_strokes_end_stays_a_ring():
    """STIX's '?' at ε 0.8: its dot lies 2.5 radii below the stem's end with nothing between,
    and was joined to the stem as a thin limb's tip the march had closed apart."""
    shape = glyph_outlines("?", height=20.0, family="STIXGeneral")
    pts = sample_rings(shape.rings, spacing=0.1, noise=0.1, seed=11)
    result = wavepoly.fit(pts, 0.8)
    _valid(pts, result)
    assert [c.closed for c in result.contours] == [True, True]
