"""Stubs: short open pieces whose points other contours already hold go; others stay."""

from __future__ import annotations

import numpy as np

import wavepoly
from wavepoly.stubs import redundant_stubs
from wavepoly.types import Contour

from .conftest import teeth, within_output


def _wall_with(stub, cluster):
    wall = Contour(np.array([[0.0, 0.0], [10.0, 0.0]]), False)
    pts = np.vstack([np.column_stack([np.linspace(0, 10, 500), np.zeros(500)]), cluster])
    return pts, [wall, Contour(stub, False)]


def test_a_stub_beside_a_wall_goes_and_the_points_stay_covered():
    """A cluster of returns 0.04 off a wall, drawn as a stub 0.03 long: every point near it is
    within the tolerance 0.1 of the wall, so the stub goes."""
    cluster = np.array([[5.0, 0.04], [5.02, 0.05], [5.03, 0.03]])
    pts, contours = _wall_with(np.array([[5.0, 0.04], [5.03, 0.04]]), cluster)
    gone, farthest = redundant_stubs(pts, np.empty(0, dtype=np.intp), contours, 0.1)
    assert gone.tolist() == [False, True]
    assert 0.05 - 1e-9 <= farthest <= 0.1


def test_a_stub_with_points_of_its_own_stays():
    """The same stub 0.16 off the wall: its points are beyond the tolerance of the wall, so it
    stays; listed as outliers, they no longer count, and it goes."""
    cluster = np.array([[5.0, 0.16], [5.02, 0.17], [5.03, 0.15]])
    pts, contours = _wall_with(np.array([[5.0, 0.16], [5.03, 0.16]]), cluster)
    assert redundant_stubs(pts, np.empty(0, dtype=np.intp), contours, 0.1)[0].tolist() == [
        False, False]
    outliers = np.arange(500, 503)
    assert redundant_stubs(pts, outliers, contours, 0.1)[0].tolist() == [False, True]


def test_two_stubs_covering_each_other_keep_one():
    """Two stubs over the same points, apart from any wall: the shorter is checked first and
    goes (the longer holds its points); the longer then has no other contour, and stays."""
    cluster = np.array([[5.0, 1.0], [5.02, 1.0], [5.04, 1.0]])
    pts, contours = _wall_with(np.array([[5.0, 1.0], [5.04, 1.0]]), cluster)
    contours.append(Contour(np.array([[5.0, 1.0], [5.03, 1.0]]), False))
    gone, _ = redundant_stubs(pts, np.empty(0, dtype=np.intp), contours, 0.1)
    assert gone.tolist() == [False, False, True]


def test_the_fit_drops_stubs_and_keeps_every_point_within_the_tolerance(shared_data):
    """The Freiburg map at 0.1: the open pieces shorter than two tolerances whose points the
    walls beside them hold go (514 open pieces were 300), and every point that is not an
    outlier stays within the tolerance."""
    pts = wavepoly.read_points(shared_data / "lidar2d" / "freiburg-079-corrected.log.gz")
    res = wavepoly.fit(pts, 0.1)
    inliers = np.setdiff1d(np.arange(len(pts)), res.outliers)
    assert within_output(pts[inliers], res, 0.1 * (1 + 1e-9)).all()
    assert res.max_error <= 0.1 and res.validity.valid
    assert sum(not c.closed for c in res.contours) < 400
    assert (res.validity.n_closed, res.validity.n_open) == (
        sum(c.closed for c in res.contours), sum(not c.closed for c in res.contours))
    assert len(res.outliers) <= 0.01 * len(pts)
    # no outlier is within the tolerance of the output; the ghost walls are strokes of their
    # own instead of the teeth of a zigzag (381 teeth when the corner insertion reached them)
    assert not within_output(pts[res.outliers], res, 0.1).any()
    assert teeth(res) < 300
