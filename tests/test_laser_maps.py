"""Made-up laser maps (`benchmarks.laser`), whose true walls are known: the promises hold on
maps the ordering was not tuned on."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

import wavepoly

from .conftest import distance_to_output, teeth
from .truth import independent_problems


@pytest.fixture(scope="module")
def floor_3():
    from benchmarks.laser import laser_map

    return laser_map(3)


def _drawn(result):
    return [shapely.LineString(np.vstack([c.vertices, c.vertices[:1]]) if c.closed
                               else c.vertices) for c in result.contours]


def test_a_made_up_map_at_four_times_its_scatter(floor_3):
    """At 0.1 (its walls' scatter about 0.022): valid, outliers under 1 %, no teeth, and
    what is drawn lies along the true surfaces (people standing by aside)."""
    pts, walls = floor_3
    result = wavepoly.fit(pts, 0.1)
    assert independent_problems(result) == [] and result.validity.valid
    inliers = np.setdiff1d(np.arange(len(pts)), result.outliers)
    assert distance_to_output(pts[inliers], result).max() <= 0.1 * (1 + 1e-9)
    assert len(result.outliers) <= 0.01 * len(pts) and teeth(result) == 0
    lines = _drawn(result)
    off = sum(line.difference(walls.buffer(0.2)).length for line in lines)
    assert off <= 0.05 * sum(line.length for line in lines)
    assert result.suggested_tolerance is None


def test_a_made_up_map_at_twice_its_scatter_runs_through_the_middle(floor_3):
    """At 0.05, some 2.2 x the scatter: the walls run through the middle of their bands (no
    teeth), the points beyond the tolerance are listed, and a tolerance is suggested."""
    pts, _ = floor_3
    result = wavepoly.fit(pts, 0.05)
    assert result.validity.valid and teeth(result) <= 1
    assert 0.06 <= result.suggested_tolerance <= 0.08
    assert len(result.outliers) <= 0.06 * len(pts)


def test_a_made_up_map_below_twice_its_scatter_is_not_read_as_an_exact_sample():
    """Map 0 at 0.04: through the middle its walls left 11 % out, and the scan was read
    again as a clean sample (as small shapes whose corners look like noise are), which held
    every point by zigzagging through the bands: 247 teeth in 140 s. A band of 20 points per
    radius is no such sample; it runs through the middle and a tolerance is suggested."""
    from benchmarks.laser import laser_map

    pts, _ = laser_map(0)
    result = wavepoly.fit(pts, 0.04)
    assert result.validity.valid and teeth(result) <= 5
    assert not any("read as an exact sample" in n for n in result.notes)
    assert result.suggested_tolerance is not None


def test_a_made_up_map_whose_band_is_wider_than_the_radius_is_not_read_as_an_exact_sample():
    """Map 0 at 0.03, 1.4 x its scatter: the disc holds part of a band (11.5 points per
    radius, under a dense curve's 12), and read exactly the walls broke into 678 open pieces
    zigzagging through their bands, 5 per ring closed, kept because they left a twentieth
    of the points out that the middle did (183 teeth in 180 s). Shapes packed side by side
    read exactly come out as rings; this runs through the middle and a tolerance is
    suggested."""
    from benchmarks.laser import laser_map

    pts, _ = laser_map(0)
    result = wavepoly.fit(pts, 0.03)
    assert result.validity.valid and teeth(result) <= 5
    assert not any("read as an exact sample" in n for n in result.notes)
    assert result.suggested_tolerance is not None


def _along_and_across(result, box, axis):
    """Drawn length inside ``box`` within 30 degrees of ``axis`` (0: x, 1: y), and the rest."""
    along = across = 0.0
    for line in _drawn(result):
        for part in shapely.get_parts(line.intersection(box)):
            d = np.diff(np.asarray(part.coords), axis=0)
            length = np.linalg.norm(d, axis=1)
            steep = np.abs(d[:, axis]) >= np.cos(np.radians(30)) * length
            along += length[steep].sum()
            across += length[~steep].sum()
    return along, across


def test_a_double_wall_far_from_the_scanner_is_two_lines():
    """Map 7's wall at x = 17 is two faces 0.15 m apart, scanned from far off (ε 0.1): the
    neighbourhoods centred between them are nearly round, with their principal axis across
    the wall, and the march stepped from face to face. Tested across that axis too, they
    split onto the faces (`wavepoly.ordering.walls`): two lines along the wall, not a zigzag
    (the code before drew 1.2 m of 8.7 across it, 14 %)."""
    from benchmarks.laser import FAR_BEAMS, FAR_RANGE, laser_map

    pts, _ = laser_map(7, FAR_RANGE, FAR_BEAMS)
    result = wavepoly.fit(pts, 0.1)
    assert result.validity.valid
    along, across = _along_and_across(result, shapely.box(16.6, -5.0, 17.3, -1.6), axis=1)
    assert along >= 2 * 3.2  # both faces, nearly all their length
    assert across <= 0.05 * (along + across)


def test_a_double_wall_below_the_scatter_follows_its_faces():
    """At ε 0.05 (below twice the scatter) map 7's corridor wall, faces 0.15 m apart: a node
    on the dense face found the far face from a disc that reached only the near edge of its
    band, and put a node between the faces; measured again over a window centred on each
    face (`wavepoly.ordering.walls`), the lines follow the faces (the code before drew 24 %
    of the length across the wall, with 4 teeth)."""
    from benchmarks.laser import FAR_BEAMS, FAR_RANGE, laser_map

    pts, _ = laser_map(7, FAR_RANGE, FAR_BEAMS)
    result = wavepoly.fit(pts, 0.05)
    assert result.validity.valid
    along = across = 0.0
    for box in (shapely.box(9.8, -0.3, 11.4, 0.1), shapely.box(7.8, -0.3, 8.3, 0.1)):
        a, b = _along_and_across(result, box, axis=0)
        along, across = along + a, across + b
    assert across <= 0.15 * (along + across)


@pytest.mark.parametrize("family, char", [("STIXGeneral", "A"), ("cmr10", "A"), ("cmr10", "$")])
def test_a_clean_glyph_at_a_coarse_tolerance_is_not_split_across(family, char):
    """The test across a round neighbourhood's axis is a noisy scan's: on a clean glyph at
    ε 0.8 (hairlines under half an ε) it split the round nodes where two strokes meet, and
    the 'A's counter or a '$''s closed into the outline."""
    from wavepoly.samples import glyph_outlines, sample_rings

    shape = glyph_outlines(char, height=20.0, family=family)
    pts = sample_rings(shape.rings, spacing=0.1, noise=0.1, seed=13)
    result = wavepoly.fit(pts, 0.8)
    assert [c.closed for c in result.contours] == [True] * len(shape.rings)
    assert independent_problems(result) == [] and len(result.outliers) == 0


def _square_room(n, sigma, side=4.0, seed=0):
    """A square room's four walls, ``n`` points scattered across them with Gaussian noise of
    ``sigma`` (a laser map's walls seen from many poses), and the walls' square."""
    rng = np.random.default_rng(seed)
    t = rng.uniform(0, 4 * side, n)
    wall, s = np.divmod(t, side)
    corners = np.array([[0, 0], [side, 0], [side, side], [0, side], [0, 0]], dtype=float)
    a, b = corners[wall.astype(int)], corners[wall.astype(int) + 1]
    normal = np.column_stack([-(b - a)[:, 1], (b - a)[:, 0]]) / side
    pts = a + (b - a) * (s / side)[:, None] + normal * rng.normal(0, sigma, n)[:, None]
    return pts, shapely.LinearRing(corners[:-1])


def test_a_band_wider_than_the_usual_windows_is_measured_as_noise():
    """Walls 0.05 across (one sigma) at a radius of 0.014: the windows of 3-12 radii are
    filled from side to side and fit no bell, which read as no noise at all, and the scan
    was read as a clean sample. Windows of 24 radii fit the bell and measure it."""
    from wavepoly.ordering.noise import noise_at
    from wavepoly.ordering.spacing import curve_spacing

    pts, _ = _square_room(40000, 0.05)
    radius = 3 * curve_spacing(pts)
    noise, _ = noise_at(pts, radius)
    assert radius < 0.02 and 0.8 * 0.05 <= noise <= 1.2 * 0.05


def test_a_tolerance_far_below_the_scatter_reads_the_walls_through_the_middle():
    """Walls 0.04 across at a tolerance of 0.005, what `wavepoly info` suggests for so dense
    a scan. Read at the spacing's radius, the neighbourhoods (at most 4 radii) could not
    follow the band: 46 closed and 617 open zigzags in 30 s (on the Freiburg map: 24 GB and no
    end). The radius is widened to the spread: one ring through the middle of the walls, and
    a tolerance suggested."""
    pts, square = _square_room(60000, 0.04)
    result = wavepoly.fit(pts, 0.005)
    assert any("the points spread" in n and "radius widened" in n for n in result.notes)
    assert [c.closed for c in result.contours] == [True]
    assert independent_problems(result) == [] and teeth(result) == 0
    # the walls through the middle of their bands, the corners rounded by neighbourhoods
    # 0.19 wide
    ring = result.contours[0].vertices
    corners = np.array(square.coords[:-1])
    along = np.linalg.norm(ring[:, None] - corners[None], axis=2).min(axis=1) > 0.3
    assert shapely.distance(shapely.points(ring[along]), square).max() <= 0.02
    assert shapely.hausdorff_distance(_drawn(result)[0], square) <= 2.5 * 0.04
    assert result.suggested_tolerance is not None and result.suggested_tolerance >= 0.08
