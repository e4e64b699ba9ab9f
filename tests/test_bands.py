"""One layer from its band: the same section as from the whole cloud, or a call for a wider band."""

from __future__ import annotations

import numpy as np

from wavepoly.bands import band_of, fit_layer_job, layer_error_job, layer_starts, section_rows
from wavepoly.geometry import to_plane
from wavepoly.sections import section_points, surface_samples
from wavepoly.slicing import band_jobs, error_jobs, fit_bands, layer_specs, uniform_layers
from wavepoly.staircase import layer_errors
from wavepoly.types import LayerJob


def cone(n=40000, seed=3):
    """A cone, so that every slab point slides along a slope to the mid-plane."""
    rng = np.random.default_rng(seed)
    t, h = rng.uniform(0, 2 * np.pi, n), rng.uniform(0, 8, n)
    r = 6.0 - 0.5 * h
    pts = np.column_stack([r * np.cos(t), r * np.sin(t), h])
    return pts + rng.normal(scale=0.01, size=pts.shape)


def sorted_plane(pts):
    uvh = to_plane(pts, np.eye(3))
    return uvh[np.argsort(uvh[:, 2], kind="stable")]


def test_the_band_gives_the_section_of_the_whole_cloud():
    uvh = sorted_plane(cone())
    bottoms, thick = uniform_layers(uvh[0, 2], uvh[-1, 2], 1.0)
    specs = layer_specs(bottoms, thick, 0.05, None, None)
    starts = layer_starts(uvh[:, 2], bottoms)
    whole = surface_samples(uvh)
    for k in (0, 3, len(specs) - 2):
        first, stop, low, high = band_of(bottoms, thick, k, 1)
        band = uvh[starts[first]:starts[stop]]
        rows = section_rows(band[:, 2], specs[k])
        from_band = section_points(surface_samples(band, rows=rows), slice(None), specs[k].z)
        offset = starts[first]
        rows_whole = slice(rows.start + offset, rows.stop + offset)
        from_whole = section_points(whole, rows_whole, specs[k].z)
        np.testing.assert_allclose(from_band, from_whole, atol=1e-12)
        assert len(from_band) > 100


def test_a_band_too_narrow_for_the_neighbourhoods_asks_for_a_wider_one():
    uvh = sorted_plane(cone(4000))
    bottoms, thick = uniform_layers(uvh[0, 2], uvh[-1, 2], 0.05)
    specs = layer_specs(bottoms, thick, 0.05, None, None)
    starts = layer_starts(uvh[:, 2], bottoms)
    k = len(specs) // 2
    first, stop, _, _ = band_of(bottoms, thick, k, 1)
    assert fit_layer_job(LayerJob(specs[k], uvh[starts[first]:starts[stop]])) is None
    calls = []

    def run(tasks):
        calls.append(len(tasks))
        return [fit_layer_job(j) for j in band_jobs(uvh, starts, tasks)]

    fits = fit_bands(specs, run)
    assert all(f is not None for f in fits) and len(calls) > 1 and calls[-1] < calls[0]


def test_error_jobs_give_the_staircase_error_of_the_whole_stack():
    uvh = sorted_plane(cone())
    bottoms, thick = uniform_layers(uvh[0, 2], uvh[-1, 2], 1.0)
    specs = layer_specs(bottoms, thick, 0.05, None, None)
    starts = layer_starts(uvh[:, 2], bottoms)
    fits = fit_bands(specs, lambda tasks: [fit_layer_job(j)
                                           for j in band_jobs(uvh, starts, tasks)])
    contours = [f.contours for f in fits]
    jobs = error_jobs(specs, contours, lambda k: uvh[starts[k]:starts[k + 1]])
    got = [layer_error_job(j) for j in jobs]
    assert got == layer_errors(uvh, bottoms, bottoms + thick, contours)
    assert 0 < max(got) < 0.5  # at most half a layer on this slope


def test_a_layer_of_open_pieces_between_closed_ones_keeps_the_better_neighbour():
    """A ledge layer whose section gave only open pieces would cut the solid in two: it takes
    the closed contours of the neighbour that give its slab the smaller staircase error, and
    says so; its own section points are outliers. An open layer with no closed neighbour stays
    as it is."""
    from dataclasses import replace

    from wavepoly.bands import held_over
    from wavepoly.types import Contour, FitResult

    def square(half):
        v = half * np.array([[-1.0, -1], [1, -1], [1, 1], [-1, 1]])
        return FitResult([Contour(v, True)], 0.1, 0.05, 0.02, np.array([], int), 40)

    pieces = [Contour(np.array([[-2.0, -2.05], [2.0, -2.05], [2.0, 2.0]]), False)]
    ledge = FitResult(pieces, 0.1, 0.05, 0.02, np.array([], int), 30, z=1.5)
    wide, narrow = square(2.0), square(1.0)
    t = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    for r, kept in ((1.0, narrow), (2.0, wide)):  # the slab: the walls of one of them
        slab = np.column_stack([r * np.sign(np.cos(t)), r * np.sin(t), 1.2 + 0.6 * t / 7])
        asked = []

        def errors_of(asks, slab=slab, asked=asked):  # only the ledge layer's slab has points
            asked.extend(k for k, _ in asks)
            return [layer_error_job(replace(job, slab=slab if k == 1 else np.empty((0, 3))))
                    for k, job in asks]

        fits = held_over([wide, ledge, narrow], np.array([0.0, 1, 2]), np.array([1.0, 2, 3]),
                         errors_of)
        assert sorted(set(asked)) == [0, 1, 2] and fits[0] is wide and fits[2] is narrow
        assert np.array_equal(fits[1].contours[0].vertices, kept.contours[0].vertices)
        assert fits[1].z == 1.5 and fits[1].n_points == 30 and len(fits[1].outliers) == 30
        side = "below" if kept is wide else "above"
        assert f"closed layer {side} are kept" in fits[1].notes[-1]
    lone = [ledge, FitResult([], 0.1, 0, 0, np.array([], int), 0)]
    assert held_over(lone, np.zeros(2), np.ones(2), errors_of)[0] is ledge
    gap = [wide, ledge, ledge, ledge, narrow]  # three broken layers: a gap in the scan
    assert held_over(gap, np.arange(5.0), np.arange(1.0, 6), errors_of)[1:4] == [ledge] * 3


def test_an_end_of_the_stack_seen_full_of_holes_stands_on_the_solid():
    """Three broken layers under the first closed one (a base that the scanner saw through
    holes): their points lie within the closed layer's region, but for a stray, so they take
    its contours; points far outside it (a side that the scans never saw) leave the run as
    it is."""
    from dataclasses import replace

    from wavepoly.bands import held_over
    from wavepoly.types import Contour, FitResult

    ring = FitResult([Contour(2.0 * np.array([[-1.0, -1], [1, -1], [1, 1], [-1, 1]]), True)],
                     0.1, 0.05, 0.02, np.array([], int), 40)
    piece = FitResult([Contour(np.array([[-2.0, -2.05], [2.0, -2.05], [2.0, 2.0]]), False)],
                      0.1, 0.05, 0.02, np.array([], int), 30)
    stack = [piece, piece, piece, ring, ring]
    for shift, kept in ((0.0, True), (3.0, False)):
        t = np.linspace(0, 1, 200)
        walls = np.column_stack([-1.9 + 3.8 * t + shift, np.full_like(t, -1.95), t])
        walls[0, :2] = [5.0, 5.0]  # a stray where the base meets the table

        def errors_of(asks, walls=walls):
            return [layer_error_job(replace(job, slab=walls + [0, 0, k])) for k, job in asks]

        fits = held_over(stack, np.arange(5.0), np.arange(1.0, 6), errors_of, tolerance=0.1)
        assert all((f.contours[0] is ring.contours[0]) == kept for f in fits[:3])


def test_a_section_of_slivers_walked_along_its_walls_stands_for_no_solid():
    """A plane along a face closes the band of points along a wall into a sliver narrower
    than the tolerance (walked out along one side and back along the other): it counts as
    open, and the layer as broken (`bands.FOLDED_SECTION`), while a thin wall of a part two
    tolerances wide is a solid."""
    from wavepoly.bands import _broken
    from wavepoly.types import Contour, FitResult

    def layer(width: float) -> FitResult:
        wall = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, width], [0.0, width]])
        piece = Contour(np.array([[0.0, 5.0], [4.0, 5.0]]), False)
        return FitResult([Contour(wall, True), piece], 1.0, 0.0, 0.0,
                         np.empty(0, dtype=np.intp), 100)

    assert _broken(layer(0.5)) and not _broken(layer(2.0))
