"""Ordering (paper §2): contour counts, closure, order against ground truth, properties."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import cKDTree

from wavepoly.errors import DataError, ParameterError
from wavepoly.ordering import curve_spacing, order_points
from wavepoly.ordering.contours import MEMBER_REACH, sharpen_corners
from wavepoly.ordering.joining import Support, join_ends
from wavepoly.ordering.neighbourhoods import Nodes
from wavepoly.samples import glyph_outlines, sample_rings

from .truth import densify, diagonal, order_agreement, svg_shape

SINGLE_CURVES = ["simple", "blob2", "complex", "spiral"]
JUNCTIONS = ["Deery", "Fishi", "Goldi", "Porpi", "Snail", "f1", "f2", "f3", "f4"]


def distance_to_contour(points, contour):
    geom = (shapely.linearrings(contour.points) if contour.closed
            else shapely.linestrings(contour.points))
    return shapely.distance(shapely.points(points), geom)


def check_coverage(pts, ordering):
    """Every input point is a member of exactly one contour or an outlier, within the radius
    (within `MEMBER_REACH` radii on a clean sampling, where the polygon covers the scatter's
    tail instead of listing it)."""
    seen = np.concatenate([c.members for c in ordering.contours] + [ordering.outliers])
    assert np.array_equal(np.sort(seen), np.arange(len(pts)))
    reach = (MEMBER_REACH if ordering.clean else 1.0) * ordering.radius
    for c in ordering.contours:
        assert distance_to_contour(pts[c.members], c).max() <= reach + 1e-9


@pytest.mark.parametrize("name", SINGLE_CURVES)
@pytest.mark.parametrize("noise", [0.0, 1 / 8])
def test_svg_single_curves(shared_data, name, noise):
    shape = svg_shape(shared_data / "curves2d" / "ground_truth_svg" / f"{name}.svg")
    eps = diagonal(shape) / 300
    pts = sample_rings(shape.rings, spacing=eps / 5, noise=noise * eps, closed=shape.closed,
                       seed=1)
    ordering = order_points(pts, eps)
    assert [c.closed for c in ordering.contours] == [True]
    _, tau = order_agreement(ordering.contours[0].points, shape, closed=True)
    assert tau >= 0.99
    assert len(ordering.outliers) <= 0.01 * len(pts)
    check_coverage(pts, ordering)


@pytest.mark.parametrize("name", JUNCTIONS)
def test_svg_drawings_with_junctions_stay_sane(shared_data, name):
    """Strokes that touch have no simple contour count: no crash, full coverage, few outliers."""
    shape = svg_shape(shared_data / "curves2d" / "ground_truth_svg" / f"{name}.svg")
    eps = diagonal(shape) / 300
    pts = sample_rings(shape.rings, spacing=eps / 5, noise=eps / 8, closed=shape.closed, seed=2)
    ordering = order_points(pts, eps)
    assert ordering.contours
    assert len(ordering.outliers) <= 0.01 * len(pts)
    check_coverage(pts, ordering)


@pytest.mark.parametrize("text, rings", [("B", 3), ("8", 3), ("&", 2), ("kx", 2), ("O", 2),
                                         ("i", 2), ("%", 5)])
@pytest.mark.parametrize("noise", [0.0, 0.02, 0.04])  # up to half the radius
def test_glyph_contours_closure_and_order(text, rings, noise):
    shape = glyph_outlines(text)
    assert len(shape.rings) == rings
    pts = sample_rings(shape.rings, spacing=0.012, noise=noise, seed=4)
    ordering = order_points(pts, 0.08)
    # noise widens the neighbourhoods, and says so
    assert any("noisy scan" in n for n in ordering.notes) == (noise > 0)
    assert len(ordering.merged_walls) <= 3  # glyph walls are far apart; no false alarms
    assert len(ordering.contours) == rings
    assert all(c.closed for c in ordering.contours)
    found = set()
    truth = densify(shape, 0.005)
    for c in ordering.contours:
        ring, tau = order_agreement(c.points, truth, closed=True)
        assert tau >= 0.99, (text, ring, tau)
        found.add(ring)
    assert found == set(range(rings))  # one contour per true ring
    # at noise sigma = radius / 2, 4.6 % of the points lie beyond the radius from the true curve
    assert len(ordering.outliers) <= (0.01 if noise < 0.04 else 0.05) * len(pts)
    check_coverage(pts, ordering)


def test_open_curves_and_islands():
    t = np.linspace(0, 1, 3000)
    arc = np.column_stack([10 * np.cos(2 * t), 10 * np.sin(2 * t)])  # an open arc
    line = np.column_stack([np.linspace(-5, 5, 1000), np.full(1000, -3.0)])  # an open segment
    ring = np.column_stack([2 * np.cos(6 * t) + 20, 2 * np.sin(6.2832 * t)])  # a closed island
    pts = np.vstack([arc, line, ring])
    pts = pts[np.random.default_rng(0).permutation(len(pts))]
    ordering = order_points(pts, 0.1)
    flags = sorted(c.closed for c in ordering.contours)
    assert flags == [False, False, True]
    data_ends = np.array([arc[0], arc[-1], line[0], line[-1]])
    for c in ordering.contours:
        if not c.closed:  # the ends reach the ends of the data, within the radius
            gap = np.linalg.norm(c.points[[0, -1]][:, None] - data_ends[None], axis=2).min(axis=1)
            assert gap.max() <= 0.1


def test_corner_is_kept_not_cut():
    square = np.array([[0, 0], [10, 0], [10, 10], [0, 10]], dtype=float)
    pts = sample_rings([square], spacing=0.01, noise=0.01, seed=5)
    ordering = order_points(pts, 0.1)
    (contour,) = ordering.contours
    for corner in square:  # an ordered point sits on every corner (within the noise)
        assert np.linalg.norm(contour.points - corner, axis=1).min() < 0.05


def test_density_varies_by_five():
    shape = glyph_outlines("D")
    pts = sample_rings(shape.rings, spacing=0.012, noise=0.01, density_ratio=5.0, seed=6)
    ordering = order_points(pts, 0.08)
    assert len(ordering.contours) == 2 and all(c.closed for c in ordering.contours)


def test_sparse_points_widen_the_radius():
    t = np.linspace(0, 2 * np.pi, 300, endpoint=False)
    pts = np.column_stack([np.cos(t), np.sin(t)]) * 10  # spacing ~0.21
    ordering = order_points(pts, 0.1)
    assert ordering.radius > 0.5 and "widened" in ordering.notes[0]
    assert len(ordering.contours) == 1 and ordering.contours[0].closed


def test_close_walls_are_reported():
    x = np.linspace(0, 10, 4000)
    pts = np.vstack([np.column_stack([x, np.zeros_like(x)]),
                     np.column_stack([x, np.full_like(x, 0.09)])])  # 0.9 radii apart
    pts = pts[np.random.default_rng(1).permutation(len(pts))]
    ordering = order_points(pts, 0.1)
    assert len(ordering.contours) == 1 and len(ordering.merged_walls) > 0
    assert any("merged" in n for n in ordering.notes)


def test_a_wide_band_is_not_two_walls():
    """A slice cut along a surface: a flat band 1.5 radii wide is one curve, reported as a band
    (two sharp walls as far apart have a bimodal scatter and are reported as merged)."""
    rng = np.random.default_rng(2)
    pts = np.column_stack([rng.uniform(0, 10, 8000), rng.uniform(-0.075, 0.075, 8000)])
    ordering = order_points(pts, 0.1)
    assert len(ordering.contours) == 1 and not ordering.contours[0].closed
    assert len(ordering.merged_walls) == 0
    assert any("band wider than the radius" in n for n in ordering.notes)


def test_isolated_outliers_are_counted():
    shape = glyph_outlines("O")
    pts = sample_rings(shape.rings, spacing=0.012, noise=0.01, seed=7)
    stray = np.array([[50.0, 50.0], [-30.0, 5.0], [10.0, 40.0]])
    ordering = order_points(np.vstack([pts, stray]), 0.08)
    assert set(range(len(pts), len(pts) + 3)) <= set(ordering.outliers.tolist())
    assert len(ordering.contours) == 2


def test_bad_input():
    with pytest.raises(DataError):
        order_points(np.empty((0, 2)), 0.1)
    with pytest.raises(DataError, match="NaN"):
        order_points(np.array([[0.0, 0.0], [np.nan, 1.0]]), 0.1)
    with pytest.raises(ParameterError):
        order_points(np.random.default_rng(0).normal(size=(10, 2)), 0.0)


def test_shared_real_scans(shared_data):
    from wavepoly.io import read_points

    pts = read_points(shared_data / "curves2d" / "noisy_sets" / "Keyboard0.txt")
    radius = 3 * curve_spacing(pts)
    ordering = order_points(pts, radius)
    assert sum(c.closed for c in ordering.contours) >= 1
    assert len(ordering.outliers) <= 0.02 * len(pts)
    check_coverage(pts, ordering)


@st.composite
def smooth_closed_curve(draw):
    """A random star-shaped closed curve r(t) = 1 + sum a_k cos(k t + p_k), sampled and noisy."""
    k = draw(st.integers(1, 4))
    amps = draw(st.lists(st.floats(0.0, 0.25 / k), min_size=k, max_size=k))
    phases = draw(st.lists(st.floats(0, 6.28), min_size=k, max_size=k))
    n = draw(st.integers(1500, 4000))
    seed = draw(st.integers(0, 10**6))
    rng = np.random.default_rng(seed)
    t = rng.uniform(0, 2 * np.pi, n)
    r = 10 * (1 + sum(a * np.cos((j + 2) * t + p) for j, (a, p) in enumerate(zip(amps, phases))))
    pts = np.column_stack([r * np.cos(t), r * np.sin(t)])
    return pts + rng.normal(0, 0.01, pts.shape), seed


@settings(max_examples=15, deadline=None)
@given(smooth_closed_curve())
def test_property_closed_curves(data):
    pts, seed = data
    ordering = order_points(pts, 0.15, seed=seed % 7)
    check_coverage(pts, ordering)
    assert len(ordering.contours) == 1 and ordering.contours[0].closed
    # the result does not depend on the input order of the points (only on the seed)
    perm = np.random.default_rng(seed).permutation(len(pts))
    again = order_points(pts[perm], 0.15, seed=seed % 7)
    assert len(again.contours) == 1
    assert abs(len(again.contours[0].points) - len(ordering.contours[0].points)) <= 0.05 * len(
        ordering.contours[0].points)


@st.composite
def polyline_with_corners(draw):
    """A random open polyline with 3-6 corners (turns of 40-140 degrees), sampled and noisy."""
    n_seg = draw(st.integers(3, 6))
    turns = draw(st.lists(st.floats(40, 140), min_size=n_seg, max_size=n_seg))
    signs = draw(st.lists(st.sampled_from([-1, 1]), min_size=n_seg, max_size=n_seg))
    heading, p, verts = 0.0, np.zeros(2), [np.zeros(2)]
    for turn, sign in zip(turns, signs):
        p = p + 4.0 * np.array([np.cos(heading), np.sin(heading)])
        verts.append(p)
        heading += np.radians(turn) * sign
    verts = np.array(verts)
    seed = draw(st.integers(0, 10**6))
    return verts, seed


@settings(max_examples=15, deadline=None)
@given(polyline_with_corners())
def test_property_polylines_with_corners(data):
    verts, seed = data
    pts = sample_rings([verts], spacing=0.01, noise=0.005, closed=[False], seed=seed)
    if shapely.linestrings(verts).is_simple is False:
        return  # self-crossing polylines have junctions, like the drawings above
    ordering = order_points(pts, 0.1, seed=seed % 5)
    check_coverage(pts, ordering)
    assert len(ordering.outliers) <= 0.01 * len(pts)


@pytest.mark.parametrize("seed", [0, 2, 4])
@pytest.mark.parametrize("run", [0.35, 0.4, 0.45])
def test_short_run_between_gaps_does_not_close_on_itself(seed, run):
    """Regression (found by hypothesis): a short, nearly straight run between two scan gaps
    has its two ends within the join distance; it must bridge the gaps, not become a loop."""
    rng = np.random.default_rng(seed)
    t = rng.uniform(0, 2 * np.pi, 1800)
    arc, gap = 10 * t, 0.33
    cut = ((arc > 20) & (arc < 20 + gap)) | ((arc > 20 + gap + run) & (arc < 20 + 2 * gap + run))
    t = t[~cut]
    pts = np.column_stack([10 * np.cos(t), 10 * np.sin(t)])
    ordering = order_points(pts, 0.15)
    assert len(ordering.contours) == 1 and ordering.contours[0].closed
    check_coverage(pts, ordering)


@pytest.mark.parametrize("noise", [0.0, 0.004])
def test_dense_scans_are_summarized_by_cell_atoms(noise):
    """Dense points go through per-cell moments (`cell_atoms`); the contours must not change."""
    from wavepoly.ordering.neighbourhoods import cell_atoms

    shape = glyph_outlines("B")
    pts = sample_rings(shape.rings, spacing=0.001, noise=noise, seed=5)
    atoms = cell_atoms(pts, 0.08)
    assert len(atoms.xy) < len(pts) / 4 and atoms.weight.sum() == len(pts)
    ordering = order_points(pts, 0.08)
    assert len(ordering.contours) == 3 and all(c.closed for c in ordering.contours)
    truth = densify(shape, 0.005)
    assert sorted(order_agreement(c.points, truth, closed=True)[0]
                  for c in ordering.contours) == [0, 1, 2]
    assert min(order_agreement(c.points, truth, closed=True)[1]
               for c in ordering.contours) >= 0.99
    assert len(ordering.outliers) <= 0.001 * len(pts)
    check_coverage(pts, ordering)


def test_a_sparse_sample_is_a_curve_not_noise():
    """A toothed curve sampled far more sparsely than the tolerance (as a crust test set:
    spacing 3, tolerance 0.02): the widened neighbourhoods hold a few points, whose spread is the
    curve's turns. Counted as noise, it widened them 4-fold and put 22 % of the crocodile's
    points out as outliers; now no point is an outlier and no noise is claimed."""
    t = np.linspace(0, 2 * np.pi, 90, endpoint=False)
    teeth = np.where(np.arange(90) % 2 == 0, 3.0, -3.0)  # a jaw's teeth: in, out, in...
    r = 40 + 8 * np.cos(3 * t) + np.where(t < np.pi, teeth, 0.0)
    pts = np.column_stack([r * np.cos(t), r * np.sin(t)])
    res = order_points(pts, 0.02)
    assert len(res.contours) == 1 and res.contours[0].closed
    assert len(res.outliers) == 0 and res.noise == 0.0


def test_the_shared_crocodile_keeps_every_point(shared_data):
    import wavepoly

    path = shared_data / "curves2d" / "hnn_crust" / "crocodile-conf.p2d"
    pts = wavepoly.as_planar(wavepoly.read_points(path))
    res = wavepoly.fit(pts, 0.02)
    assert len(res.outliers) == 0 and [c.closed for c in res.contours] == [True]
    assert res.validity.valid and not any("scatter" in n for n in res.notes)


def _ring_with_gap(radius, spacing, gap_angle):
    t = np.arange(gap_angle, 2 * np.pi, spacing / radius)
    return radius * np.column_stack([np.cos(t), np.sin(t)])


def test_rings_with_gaps_side_by_side_stay_two_rings():
    """Two rings 2 radii apart, each with a gap of 2.5 radii at the same place: each end faces
    its own ring's other end across the gap and joins it, not the nearer end beside it (which
    merged the two rings into one)."""
    pts = np.vstack([_ring_with_gap(3.0, 0.03, 0.25 / 3.0), _ring_with_gap(3.2, 0.03, 0.25 / 3.2)])
    ordering = order_points(pts, 0.1)
    assert [c.closed for c in ordering.contours] == [True, True]
    radii = sorted(float(np.linalg.norm(c.points, axis=1).mean()) for c in ordering.contours)
    assert np.allclose(radii, [3.0, 3.2], atol=0.02)


def test_strays_about_a_dense_wall_are_not_corners():
    """A dense wall with a halo of stray points 0.7-1 radii off both sides: the strays are a
    small share of each stretch's points, so none is inserted as a corner (they zigzagged the
    Intel map's walls, here out to 0.1); the wall's ordered curve stays straight."""
    rng = np.random.default_rng(4)
    wall = np.column_stack([rng.uniform(0, 10, 20000), rng.normal(0, 0.01, 20000)])
    side = rng.choice([-1.0, 1.0], 600)
    strays = np.column_stack([rng.uniform(0, 10, 600), side * rng.uniform(0.07, 0.1, 600)])
    ordering = order_points(np.vstack([wall, strays]), 0.1)
    (contour,) = ordering.contours
    assert np.abs(contour.points[:, 1]).max() < 0.02
    assert set(ordering.outliers.tolist()) <= set(range(len(wall), len(wall) + 600))
    assert len(ordering.outliers) <= 12


def test_a_ghost_wall_beside_a_dense_one_is_followed_not_zigzagged():
    """A laser map's double wall: a dense wall and a lighter one 1.6 radii beside it, each with
    scatter 0.2 radii, in a scan whose other walls scatter 0.4 radii. The neighbourhoods,
    widened for that scatter, span both walls, and the march zigzagged between them. Each
    such neighbourhood now gives a node on each wall, so the ordered points lie on the walls."""
    rng = np.random.default_rng(3)
    dense = np.column_stack([rng.uniform(0, 10, 30000), rng.normal(0, 0.02, 30000)])
    ghost = np.column_stack([rng.uniform(0, 10, 10000), rng.normal(0.16, 0.02, 10000)])
    other = np.column_stack([rng.uniform(0, 30, 60000), rng.normal(5, 0.04, 60000)])
    ordering = order_points(np.vstack([dense, ghost, other]), 0.1)
    assert 5 * ordering.noise > 0.16  # the widened neighbourhoods reach across the gap
    double = [c.points for c in ordering.contours if c.points[:, 1].max() < 1]
    assert 1 <= len(double) <= 2
    ordered = np.vstack(double)
    off_wall = np.minimum(np.abs(ordered[:, 1]), np.abs(ordered[:, 1] - 0.16))
    assert np.percentile(off_wall, 99) < 0.03
    assert len(ordering.outliers) < 0.01 * 100000


def test_noisy_curves_are_not_split_into_two_walls():
    """Bell-shaped scatter fills the middle between the two halves of a neighbourhood, and a
    few nodes that pass the test by chance are not a wall running alongside: noisy glyphs
    keep their closed outlines."""
    for text, rings in (("B", 3), ("kx", 2)):
        shape = glyph_outlines(text)
        pts = sample_rings(shape.rings, spacing=0.012, noise=0.04, seed=2)
        ordering = order_points(pts, 0.08)
        assert [c.closed for c in ordering.contours] == [True] * rings


def test_two_noisy_rings_in_one_window_measure_their_own_scatter():
    """Rings 3 radii apart with scatter radius / 8: the noise window (3 radii) holds both, and
    their spread about a line between them passed for noise 5.6 x too large; the widened
    neighbourhoods then spanned both rings and broke them into 20-40 pieces."""
    rng = np.random.default_rng(0)
    rings = []
    for r in (3.0, 3.3):
        t = rng.uniform(0, 2 * np.pi, int(2 * np.pi * r / (0.1 / 3)))
        rings.append(r * np.column_stack([np.cos(t), np.sin(t)]))
    pts = np.vstack(rings) + rng.normal(scale=0.0125, size=(sum(map(len, rings)), 2))
    ordering = order_points(pts, 0.1)
    assert ordering.noise < 2 * 0.0125
    assert [c.closed for c in ordering.contours] == [True, True]


def test_rings_whose_march_jumped_between_them_get_their_own_stretches_back():
    """Rings 1.5 radii apart with scatter radius / 8, sampled at random angles: where both
    have a gap at the same place the march jumped from one to the other and back, so each
    closed chain followed the other ring for a stretch; the two chains crossed twice and were
    cut into 4 open pieces. The stretches between the crossings are swapped back."""
    rng = np.random.default_rng(0)
    rings = []
    for r in (8.0, 8.15):
        t = rng.uniform(0, 2 * np.pi, int(2 * np.pi * r / (0.1 / 3)))
        rings.append(r * np.column_stack([np.cos(t), np.sin(t)]))
    pts = np.vstack(rings)
    pts = pts + rng.normal(scale=0.0125, size=pts.shape)
    ordering = order_points(pts, 0.1)
    assert [c.closed for c in ordering.contours] == [True, True]
    radii = sorted(float(np.linalg.norm(c.points, axis=1).mean()) for c in ordering.contours)
    assert np.allclose(radii, [8.0, 8.15], atol=0.02)


@pytest.mark.parametrize("disk_radius", [3.0, 5.0])
def test_a_small_traced_disk_with_noise_a_quarter_of_the_tolerance_is_a_clean_sampling(
        disk_radius):
    """A disk a few tolerances across, traced from a bitmap whose pixel is ε / 2.4 (scikit-
    image's binary blobs), sampled every ε / 3 with noise ε / 4: over a neighbourhood its
    points spread 0.34-0.6 radii about the regression line, most of it the disk's bend, and
    the scan was read as noisy (1 point of 3 disks an outlier); their own scatter is that of
    a clean sampling, and nothing is an outlier."""
    import wavepoly
    from benchmarks.silhouettes import bitmap, sample

    eps = 1.0
    t = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    disk = [disk_radius * np.column_stack([np.cos(t), np.sin(t)])]
    traced = bitmap(disk, int(np.hypot(2, 2) * disk_radius * 2.4))
    length = sum(shapely.LinearRing(r).length for r in traced)
    for seed in range(3):
        pts = sample(traced, int(3 * length / eps), eps / 4, seed)
        assert order_points(pts, eps, tolerance=eps).clean
        result = wavepoly.fit(pts, eps)
        assert [c.closed for c in result.contours] == [True]
        assert len(result.outliers) == 0


def test_repeated_points_do_not_change_the_spacing():
    # a scanner's repeated returns, a file merged with its copy: one sample each
    t = np.linspace(0, 2 * np.pi, 500, endpoint=False)
    pts = np.column_stack([np.cos(t), np.sin(t)])
    jitter = np.random.default_rng(0).normal(0, 1e-9, pts.shape)
    once = curve_spacing(pts)
    assert curve_spacing(np.vstack([pts, pts, pts])) == pytest.approx(once)
    assert curve_spacing(np.vstack([pts, pts + jitter])) == pytest.approx(once, rel=1e-6)


def test_points_per_radius_count_a_band_along_its_curve():
    """On a clean circle it is the radius over the spacing; across a band of noise as wide as
    the radius every point counts, where the spacing of neighbours sees points per area."""
    from wavepoly.ordering.spacing import points_per_radius

    t = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    circle = np.column_stack([np.cos(t), np.sin(t)])
    radius = 10 * 2 * np.pi / 2000
    assert points_per_radius(circle, radius) == pytest.approx(10, abs=0.5)
    rng = np.random.default_rng(0)
    s = rng.uniform(0, 2 * np.pi, 20_000)
    band = (1 + rng.normal(0, radius / 4, len(s)))[:, None] * np.column_stack(
        [np.cos(s), np.sin(s)])
    assert points_per_radius(band, radius) > 80  # 100 per radius along it, nearly all within
    assert radius / curve_spacing(band) < 25
    twice = np.vstack([circle, circle])  # a scanner's repeated returns count once
    assert points_per_radius(twice, radius) == pytest.approx(10, abs=0.5)


@pytest.mark.parametrize("seed", [4, 20, 23])
def test_a_silhouette_given_three_times_over_comes_out_as_given_once(seed):
    """Silhouettes sampled exactly (1000 points, ε = 1/150 of their size): every point three
    times halved the spacing measured, the radius was widened less, and these came out open
    or split (each is one closed outline given once)."""
    import wavepoly
    from benchmarks.bench_validity import SILHOUETTE_SAMPLINGS
    from benchmarks.silhouettes import sample, silhouette

    _, n, eps, noise = SILHOUETTE_SAMPLINGS[1]
    rings = silhouette(seed)
    pts = sample(rings, n, noise * eps, 1000 + seed)
    once = wavepoly.fit(pts, eps)
    thrice = wavepoly.fit(np.vstack([pts, pts, pts]), eps)
    assert [c.closed for c in thrice.contours] == [c.closed for c in once.contours]
    assert len(thrice.contours) == len(rings)
    assert thrice.validity.valid and len(thrice.outliers) == 0


def test_small_sharp_shapes_are_not_read_as_noise():
    """Two triangles 6 tolerances across, sampled with noise ε / 4: the windows that measure
    the noise spanned both sides and a corner and read a spread of a tolerance, the curves
    ran through the middle, and 73 of 116 points were left out; read as a clean sample they
    are the two triangles."""
    import wavepoly

    from .conftest import distance_to_output
    from .truth import independent_problems

    a = np.array([[0, 0], [6, 0], [3, -6]], float)
    pts = sample_rings([a, a + [8.0, 0]], spacing=1 / 3, noise=0.25, seed=1)
    result = wavepoly.fit(pts, 1.0)
    assert [c.closed for c in result.contours] == [True, True]
    assert len(result.outliers) == 0 and independent_problems(result) == []
    assert distance_to_output(pts, result).max() <= 1.0 + 1e-9
    assert any("read as an exact sample" in n for n in result.notes)


def traced_text(lines: list[str], height: float) -> np.ndarray:
    """The points a tracer gives for ``lines`` of text rasterized ``height`` pixels high: one
    where each letter's outline crosses a pixel edge (contourpy at half a pixel's height, as
    scikit-image's ``find_contours``), on a staircase spaced 0.5-1 pixel."""
    import contourpy
    from matplotlib.path import Path

    rings = [r - [0.0, 1.6 * height * k] for k, line in enumerate(lines)
             for r in glyph_outlines(line, height=height).rings]
    lo, hi = np.vstack(rings).min(axis=0) - 3, np.vstack(rings).max(axis=0) + 3
    x, y = np.meshgrid(np.arange(lo[0], hi[0]) + 0.5, np.arange(lo[1], hi[1]) + 0.5)
    centres = np.column_stack([x.ravel(), y.ravel()])
    crossings = sum(Path(r).contains_points(centres).astype(int) for r in rings)
    mask = (crossings % 2 == 1).reshape(x.shape).astype(float)  # counters are holes
    return np.vstack([line[:-1] for line in contourpy.contour_generator(z=mask).lines(0.5)])


TEXT = ["based segmentation", "of the page image", "wavelets and curves"]


@pytest.mark.parametrize("height", [10.0, 12.0])
def test_letters_packed_side_by_side_are_no_noise(height):
    """Three lines of text 10-12 pixels high, traced, at 1.43 pixels (scikit-image's page of
    text at its diagonal / 300). Over windows of three radii the letters' sharp walls fill
    the band from side to side, and over wider ones the lines of letters spread like a bell
    of a third of the window: read as noise 1461-1830 of 2370-2796 points were outliers.
    Such a spread is no bell (it cannot be measured again over a window three of it wide);
    read as a clean sample every point is within the tolerance."""
    import wavepoly

    from .conftest import distance_to_output
    from .truth import independent_problems

    pts = traced_text(TEXT, height)
    result = wavepoly.fit(pts, 1.43)
    assert not any("noisy scan" in n for n in result.notes)
    assert len(result.outliers) == 0 and independent_problems(result) == []
    assert distance_to_output(pts, result).max() <= 1.43 + 1e-9


def test_letters_read_as_noise_are_read_again_as_a_clean_sample():
    """Text 20 pixels high, traced, at 3 pixels: the first windows already see a spread of
    a third of them (the letters), the curves ran through its middle in 4 open zigzags and
    left 62 % of the points out. Read as a clean sample the letters leave 0.2 % out: though
    it has more open pieces than the noisy reading has contours (which would mark a noisy
    band fallen apart), it keeps ten times as many points and wins."""
    import wavepoly

    from .conftest import distance_to_output
    from .truth import independent_problems

    pts = traced_text(TEXT, 20.0)
    result = wavepoly.fit(pts, 3.0)
    assert any("read as an exact sample" in n for n in result.notes)
    assert len(result.outliers) == 0 and independent_problems(result) == []
    assert distance_to_output(pts, result).max() <= 3.0 + 1e-9
    assert sum(c.closed for c in result.contours) >= 15


@pytest.mark.parametrize("sigma, spacing", [(0.8, 0.33), (1.0, 0.2), (2.0, 0.1)])
def test_a_band_wider_than_the_tolerance_is_still_read_through_its_middle(sigma, spacing):
    # read as a clean sample it would zigzag through the band (4-9 % of it beyond the tolerance)
    import wavepoly

    t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    ring = 20 * np.column_stack([np.cos(t), np.sin(t)])
    pts = sample_rings([ring], spacing=spacing, noise=sigma, seed=1)
    result = wavepoly.fit(pts, 1.0)
    assert not any("read as an exact sample" in n for n in result.notes)
    assert any("run through the middle of the noise" in n for n in result.notes)


def test_a_parabolas_spread_leaves_out_the_curves_bend():
    """`bend_free_spread`: about their line, points on a bend spread by the bend's sagitta;
    about a parabola along it, by their noise only. On a straight noisy line the two agree."""
    from wavepoly.ordering.neighbourhoods import (
        bend_free_spread,
        cell_atoms,
        perpendicular_offsets,
        regression_step,
    )

    rng = np.random.default_rng(3)
    x = np.linspace(-1, 1, 4001)
    for bend, sigma in ((0.0, 0.02), (0.4, 0.0), (0.4, 0.02)):
        pts = np.column_stack([x, bend * x**2 + rng.normal(0, sigma, len(x))])
        atoms = cell_atoms(pts, 1 / 3)  # as `noise_level` sums them: windows of 3 radii
        xy, tangent, _, spread = regression_step(np.array([[0.0, 0.0]]), atoms, 1.0)
        offsets = perpendicular_offsets(xy, tangent, atoms, 1.0)
        free = bend_free_spread(xy, tangent, atoms, 1.0, offsets)[0]
        # (an atom summarizes a cell of its points, which along a steep bend also spread
        # across the window's line: 0.005 here)
        assert free == pytest.approx(sigma, abs=0.15 * sigma + 0.006)
        if bend:
            assert spread[0] > 5 * max(free, sigma)  # the line's spread counts the bend
        else:
            assert spread[0] == pytest.approx(free, rel=0.05)


@pytest.mark.parametrize("size, seed", [(5.0, 2), (3.5, 0), (3.5, 1), (5.0, 1), (4.5, 0)])
def test_small_shapes_with_noise_are_drawn_as_their_shapes(size, seed):
    """Two triangles and a disk 3.5-5 tolerances across, sampled every ε / 3 with noise ε / 4.
    Over windows of three radii their corners and bends looked like a spread of 0.7-0.86
    tolerances; neighbourhoods 5 x that wide took in whole shapes, and the march drew one
    piece round them all or left points out (5 of 143 at size 5, seed 2). The spread about a
    parabola along each window sizes them (size 5, seed 2); where the curves still ran
    through the middle and left 18 % of the points out (size 3.5, seed 0), or the spread was
    the shapes' own, 2.7-4.7 x the points' scatter, and outlines were left open (seeds 1),
    the scan is read as a clean sample. There a triangle's chain may stop at a corner, 2.7
    radii short of closing over its own points, and closes (size 4.5, seed 0)."""
    import wavepoly

    from .truth import independent_problems

    t = np.linspace(0, 2 * np.pi, 60, endpoint=False)
    disk = [2.5 * size, 0.0] + size / 2 * np.column_stack([np.cos(t), np.sin(t)])
    triangle = np.array([[0, 0], [size, 0], [size / 2, -size]])
    rings = [triangle, disk, triangle + [0, -2 * size]]
    pts = sample_rings(rings, spacing=1 / 3, noise=0.25, seed=seed)
    result = wavepoly.fit(pts, 1.0)
    assert [c.closed for c in result.contours] == [True, True, True]
    assert len(result.outliers) == 0 and independent_problems(result) == []
    drawn = shapely.MultiLineString([np.vstack([c.vertices, c.vertices[:1]])
                                     for c in result.contours])
    true = shapely.MultiLineString([np.vstack([r, r[:1]]) for r in rings])
    assert shapely.hausdorff_distance(true, drawn, densify=0.01) <= 1.5


def _arc_chain(gap: float, reach: float = 1.0, missing: float = 80.0):
    """Nodes half a reach apart along an arc that leaves out ``missing`` degrees of its circle,
    its ends ``gap`` reaches apart, linked into one chain, and points along it."""
    half = np.radians(missing / 2)
    r = gap * reach / (2 * np.sin(half))
    t = np.arange(half, 2 * np.pi - half, reach / (2 * r))
    xy = np.column_stack([r * np.cos(t), r * np.sin(t)])
    tangent = np.column_stack([-np.sin(t), np.cos(t)])
    ones = np.ones(len(xy))
    nodes = Nodes(xy, tangent, 0 * ones, 0 * ones, reach, 0.0)
    links = np.column_stack([np.arange(len(xy) - 1), np.arange(1, len(xy))])
    s = np.arange(half, 2 * np.pi - half, reach / (6 * r))
    return nodes, links, np.column_stack([r * np.cos(s), r * np.sin(s)])


def test_a_chain_closes_across_empty_space_only_along_points():
    """A chain whose end points at its start 6 reaches away (a stroke run out and round, a
    hook) closed across the empty gap on a clean scan: a thresholded photograph's text drew an
    edge across 13.8 tolerances of nothing. A join that wide now runs along points; with
    points along the gap (a notch's other wall) it closes as before."""
    nodes, links, pts = _arc_chain(6.0)
    closing = sorted((0, len(nodes.xy) - 1))
    joined = join_ends(nodes, links)  # no points to check against: closes
    assert closing in np.sort(joined, axis=1).tolist()
    bare = Support(cKDTree(pts), 1.0, every_wide_join=False)
    assert len(join_ends(nodes, links, bare)) == len(links)
    across = np.linspace(nodes.xy[-1], nodes.xy[0], 40)  # points along the gap
    walled = Support(cKDTree(np.vstack([pts, across])), 1.0, every_wide_join=False)
    assert closing in np.sort(join_ends(nodes, links, walled), axis=1).tolist()


def test_a_gap_in_a_smooth_outline_closes_without_points():
    """Ends that point at each other within 25 degrees across 6 reaches with no point between
    are a gap in the sampling of a smooth outline (a silhouette thinned to a quarter on one
    side): the chain closes there, points or none."""
    nodes, links, pts = _arc_chain(6.0, missing=10.0)
    bare = Support(cKDTree(pts), 1.0, every_wide_join=False)
    joined = np.sort(join_ends(nodes, links, bare), axis=1).tolist()
    assert sorted((0, len(nodes.xy) - 1)) in joined


def test_a_coarser_reading_that_folds_an_outline_onto_itself_is_not_kept():
    """`_coarser_reading`: where a clean reading left an outline open on a scan sparse on one
    side, a reading at the sparse side's radius is kept where it closes every outline, but
    not where the ring it closed is an outline walked out along one side of a stretch and
    back along the other (its mean width, twice its area over its perimeter, under its
    radius): in a plane through a shallow face the turbine blade's section came out so, a
    layer of 3 % of the section's area."""
    from wavepoly.ordering.rereading import FOLDED_WIDTH, _coarser_reading
    from wavepoly.types import OrderedContour, Ordering

    rng = np.random.default_rng(0)
    t = np.concatenate([rng.uniform(0, np.pi, 2000), rng.uniform(np.pi, 2 * np.pi, 600)])
    pts = 10 * np.column_stack([np.cos(t), np.sin(t)])  # 0.016 apart, then 0.05
    members = np.arange(len(pts))
    broken = Ordering([OrderedContour(pts[t < 6], False, members[t < 6])],
                      members[t >= 6], 0.05, clean=True)
    u = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    circle = np.column_stack([np.cos(u), np.sin(u)])
    for width, kept in ((0.05, False), (10.0, True)):
        inner = circle[::-1] * (10 - width)  # a strip ring 0.05 wide, or the whole disk
        ring = 10 * circle if width == 10.0 else np.vstack([10 * circle, inner])

        def read(radius, sparse, ring=ring):
            assert FOLDED_WIDTH * radius > 0.05  # the sparse side's three spacings
            return Ordering([OrderedContour(ring, True, members)], members[:0], radius,
                            clean=True)

        assert (_coarser_reading(broken, pts, 0.05, 0, read) is not None) == kept


def _twice_area(xy: np.ndarray) -> float:
    return float(np.dot(xy[:, 0], np.roll(xy[:, 1], -1)) - np.dot(xy[:, 1], np.roll(xy[:, 0], -1)))


@settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 4), st.integers(0, 4)), min_size=6, max_size=8,
                unique=True))
def test_sharpened_small_rings_keep_an_area(nodes):
    """A small closed chain of corners whose sharpened runs met at one point is left as it was:
    a ring that had an area keeps one. (A trial corner rule made such a ring of two equal
    points on the Intel map at 0.05, and its members were lost to both the output and the
    outliers.)"""
    xy = np.array(nodes, dtype=float)
    sharp = sharpen_corners(xy, True, cKDTree(xy), 1.0)
    assert _twice_area(sharp) != 0 or _twice_area(xy) == 0


def test_a_scan_with_more_neighbourhoods_than_fit_in_memory_is_read_at_a_wider_radius(
        monkeypatch):
    """The Freiburg map at 0.008 made 1.1 million neighbourhoods and ran out of 14 GB; the
    radius widens until they are at most `MAX_NODES` (here lowered to 300 for a circle of
    2000 points) and says so."""
    import wavepoly.ordering as ordering

    t = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    circle = np.column_stack([np.cos(t), np.sin(t)])
    assert len(ordering.order_points(circle, 0.01).contours) == 1
    monkeypatch.setattr(ordering, "MAX_NODES", 300)
    res = ordering.order_points(circle, 0.01)
    assert res.radius > 0.01 and any("fit in memory" in n for n in res.notes)
    assert [c.closed for c in res.contours] == [True] and len(res.outliers) == 0


def test_each_chain_is_walked_on_its_own_rows_as_over_the_whole_graph():
    """`chains_of` walks each component on its own rows of the link graph (over the whole
    graph each walk cost the graph's size, and kept a buffer of it: 50,000 nodes in 15,000
    chains took 24 s and 3.5 GB): the same depth-first order as over the whole graph, on
    paths, rings and branched chains."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import depth_first_order

    from wavepoly.ordering.marching import chains_of

    rng = np.random.default_rng(1)
    n, links, k = 3000, [], 0
    perm = rng.permutation(n)
    while k < n:
        run = perm[k:k + int(rng.integers(1, 40))]
        k += len(run)
        links += list(zip(run[:-1], run[1:]))
        if len(run) >= 3 and rng.random() < 0.4:
            links.append((run[-1], run[0]))
        if len(run) >= 4 and rng.random() < 0.2:
            links.append((run[1], run[3]))
    links = np.array(links, dtype=np.intp)
    graph = coo_matrix((np.ones(len(links)), tuple(links.T)), shape=(n, n)).tocsr()
    graph = graph + graph.T
    chains = chains_of(links, n)
    assert sum(len(c) for c in chains) == n
    for chain in chains:
        whole = depth_first_order(graph, chain.nodes[0], directed=False,
                                  return_predecessors=False)
        assert np.array_equal(chain.nodes, whole)
