"""Layers are the object's true cross-sections: checked against the exact mesh sections."""

from __future__ import annotations

import numpy as np
import pytest

import wavepoly
from wavepoly.sections import mesh_section, section_points, surface_samples
from wavepoly.slicing import plane_basis

from .truth import layer_agreement, noisy_surface_cloud


def _mesh(shared_data, name):
    import trimesh

    return trimesh.load(shared_data / "scans3d" / name, process=False)


def _largest_gap(xy: np.ndarray) -> float:
    """The widest gap (as an arc length) between section points round a circle at 0."""
    angle = np.sort(np.arctan2(xy[:, 1], xy[:, 0]))
    gaps = np.diff(np.append(angle, angle[0] + 2 * np.pi))
    return float(gaps.max() * np.hypot(*xy.T).mean())


def test_a_sloped_band_becomes_a_line_on_the_mid_plane():
    """A cone's slab spreads over a band as wide as the slab times the slope; slid along the
    surface, its points lie on the circle of the cone's section at the mid-plane."""
    rng = np.random.default_rng(0)
    h = rng.uniform(0, 10, 60000)
    t = rng.uniform(0, 2 * np.pi, 60000)
    r = 10 - 0.8 * h  # a cone: the radius shrinks by 0.8 per unit of height
    cloud = np.column_stack([r * np.cos(t), r * np.sin(t), h])
    uvh = cloud[np.argsort(h)]
    surface = surface_samples(uvh)
    rows = slice(*np.searchsorted(uvh[:, 2], [4.0, 6.0]))
    band = np.hypot(*uvh[rows, :2].T)
    assert np.ptp(band) > 1.5  # the slab's points spread over 1.6 units of radius
    sec = section_points(surface, rows, 5.0)
    radius = np.hypot(*sec.T)
    # those whose neighbourhood reaches z = 5: the circle is covered without gaps
    assert _largest_gap(sec) < 0.05 * 6.0
    assert np.abs(radius - 6.0).max() < 0.02


def test_a_cap_inside_the_slab_gives_no_section():
    """A cylinder's flat top lies inside the slab but below its mid-plane: no section there."""
    rng = np.random.default_rng(1)
    t = rng.uniform(0, 2 * np.pi, 30000)
    side = np.column_stack([3 * np.cos(t), 3 * np.sin(t), rng.uniform(0, 5, 30000)])
    rr, tt = 3 * np.sqrt(rng.uniform(0, 1, 10000)), rng.uniform(0, 2 * np.pi, 10000)
    top = np.column_stack([rr * np.cos(tt), rr * np.sin(tt), np.full(10000, 5.0)])
    uvh = np.vstack([side, top])
    uvh = uvh[np.argsort(uvh[:, 2])]
    surface = surface_samples(uvh)
    rows = slice(*np.searchsorted(uvh[:, 2], [4.5, 6.5]))
    assert len(section_points(surface, rows, 5.5)) == 0
    assert abs(np.hypot(*section_points(surface, rows, 4.6).T).mean() - 3.0) < 0.01


def test_a_scan_denser_than_its_noise_is_thinned_to_planar_neighbourhoods():
    """At 0.05 noise on a cylinder of radius 5, the 24 nearest of 400k points span 0.1: noise,
    not the surface. Thinned, the tangent planes are planar again and most slab points give
    section points near the true circle (unthinned, 1 in 800 did); a clean scan of the
    same density keeps every point, and those whose neighbourhoods reach the plane slide."""
    from wavepoly.sections import node_step

    rng = np.random.default_rng(4)
    n = 400_000
    t, h = rng.uniform(0, 2 * np.pi, n), rng.uniform(0, 2, n)
    clean = np.column_stack([5 * np.cos(t), 5 * np.sin(t), h])
    noisy = clean + rng.normal(scale=0.05, size=clean.shape)
    for cloud, thinned in ((clean, False), (noisy, True)):
        uvh = cloud[np.argsort(cloud[:, 2], kind="stable")]
        assert (node_step(uvh)[0] > 1) == thinned
        surface = surface_samples(uvh)
        rows = slice(*np.searchsorted(surface.uvh[:, 2], [0.8, 1.2]))
        sec = section_points(surface, rows, 1.0)
        assert _largest_gap(sec) < 0.05 * 5.0
        assert np.abs(np.hypot(*sec.T) - 5).mean() < (0.06 if thinned else 1e-3)


def test_a_shallow_ridge_is_followed_along_its_bend_not_its_tangent():
    """A ridge h = -x^2 / 2 under noise, cut 0.02 below its crest: the section is |x| = 0.2
    where the slope is 0.2. Sliding along the quadric's bend places the points closer than
    the tangent plane, which overshoots toward the crest; above the crest, no points."""
    import dataclasses

    rng = np.random.default_rng(1)
    x, y = rng.uniform(-1, 1, 40_000), rng.uniform(-1, 1, 40_000)
    uvh = np.column_stack([x, y, -0.5 * x**2 + rng.normal(scale=0.005, size=len(x))])
    surface = surface_samples(uvh[np.argsort(uvh[:, 2])])
    tangent = dataclasses.replace(surface, bend=np.zeros_like(surface.bend))

    def worst(s):
        xy = section_points(s, slice(None), -0.02)
        return np.abs(np.abs(xy[:, 0]) - 0.2).max()

    assert worst(surface) < 0.02 and worst(surface) < 0.7 * worst(tangent)
    assert len(section_points(surface, slice(None), 0.02)) == 0


def test_mesh_section_of_a_box_is_its_rectangle():
    import trimesh

    box = trimesh.creation.box(extents=(4.0, 2.0, 1.0))
    [(xy, closed)] = mesh_section(box, plane_basis("z"), 0.1)
    assert closed and len(xy) >= 4
    assert np.allclose(np.ptp(xy, axis=0), [4.0, 2.0])


@pytest.mark.parametrize("name, axis", [("turbineblade.ply", "z"), ("bunny_zipper.ply", "y")])
def test_uniform_layers_match_the_exact_sections(shared_data, name, axis):
    """Clouds sampled from the meshes' faces with noise 0.1 % of the diagonal, ε = 5 σ:
    each layer against the mesh's section at its mid-plane, 95 % right where the mesh is
    closed (the bunny's layers across its holes have no solid section to be judged by)."""
    mesh = _mesh(shared_data, name)
    diag = float(np.linalg.norm(mesh.extents))
    sigma = 0.001 * diag
    eps = 5 * sigma
    cloud = noisy_surface_cloud(mesh, 300_000, sigma)
    res = wavepoly.slice_cloud(cloud, eps, axis=axis, layer_thickness=diag / 60, workers=2)
    rows = layer_agreement(mesh, res, eps)
    assert all(r["valid"] for r in rows)
    assert np.mean([r["right"] for r in rows if not r["hole"]]) >= 0.95
    hausdorff = np.array([r["hausdorff"] for r in rows])
    assert np.median(hausdorff) <= 1.2
    closed_truth = [r for r in rows if r["truth"] == 1]
    assert np.mean([r["closed"] for r in closed_truth]) >= 0.95
    sym = np.array([r["sym_diff"] for r in closed_truth])
    assert np.mean(sym < 1.0) >= 0.95
    from wavepoly.io.layers import layer_mesh

    solid = layer_mesh(res)  # a ledge layer of open pieces no longer cuts it in two
    assert solid.is_watertight and solid.body_count == 1


def test_slicing_the_mesh_gives_exact_layers_and_one_printable_solid(shared_data, tmp_path):
    """--from-mesh: the exact sections, simplified within ε: every layer right, and the STL
    one watertight solid with the mesh's volume within 3 %. (With its vertices on the
    section, the fewest-vertex polygon cut inside every convex stretch: 6 % short at
    diag / 60; the vertices now move out until each layer keeps its section's area.)"""
    import trimesh

    mesh = _mesh(shared_data, "turbineblade.ply")
    diag = float(np.linalg.norm(mesh.extents))
    eps = 0.005 * diag
    res = wavepoly.slice_mesh(mesh, eps, layer_thickness=diag / 100)
    rows = layer_agreement(mesh, res, eps)
    assert all(r["right"] for r in rows)
    wavepoly.write_layers(tmp_path / "blade.stl", res)
    solid = trimesh.load(tmp_path / "blade.stl")
    assert solid.is_watertight and solid.is_winding_consistent and solid.body_count == 1
    assert 0.97 * mesh.volume <= solid.volume <= 1.03 * mesh.volume


def test_a_mesh_with_a_hole_gives_closed_layers_and_one_solid():
    """A cylinder's mesh with a window cut in its side (a hole in a scan): the layers across
    the window are bridged as a cloud's are, and the stack stays one solid."""
    import trimesh

    from wavepoly.io.layers import layer_mesh

    tube = trimesh.creation.cylinder(radius=5.0, height=10.0, sections=64).subdivide_to_size(0.5)
    centres = tube.triangles_center
    window = (np.abs(centres[:, 2]) < 1.5) & (centres[:, 0] > 4.0) & (np.abs(centres[:, 1]) < 0.3)
    holed = trimesh.Trimesh(tube.vertices, tube.faces[~window], process=False)
    assert window.any() and not holed.is_watertight
    res = wavepoly.slice_mesh(holed, 0.05, layer_thickness=1.0)
    assert all(c.closed for la in res.layers for c in la.fit.contours)
    solid = layer_mesh(res)
    assert solid.is_watertight and solid.body_count == 1


def test_the_bunny_mesh_with_holes_slices_into_one_solid(shared_data):
    """The zippered bunny has five holes: its layers are right wherever its mesh is closed,
    and the STL is one solid with the volume of the mesh with its holes fanned shut."""
    from wavepoly.io.layers import layer_mesh

    from .truth import closed_mesh

    mesh = _mesh(shared_data, "bunny_zipper.ply")
    diag = float(np.linalg.norm(mesh.extents))
    eps = 0.005 * diag
    res = wavepoly.slice_mesh(mesh, eps, layer_thickness=diag / 60, axis="y")
    rows = layer_agreement(mesh, res, eps)
    assert all(r["right"] for r in rows if not r["hole"]) and sum(r["hole"] for r in rows) <= 3
    solid = layer_mesh(res)  # the mesh's own loops at the base holes fill: no voids
    assert solid.is_watertight and solid.body_count == 1
    assert abs(solid.volume / closed_mesh(mesh).volume - 1) < 0.03


def test_cli_slices_from_the_mesh_onto_the_build_plate(shared_data, tmp_path):
    import json

    from typer.testing import CliRunner

    from wavepoly.cli import app

    path = shared_data / "scans3d" / "turbineblade.ply"
    out, report = tmp_path / "blade.cli", tmp_path / "r.json"
    run = CliRunner().invoke(app, ["slice", str(path), "-t", "0.25", "--layer", "2",
                                   "--from-mesh", "-o", str(out), "--report", str(report)])
    assert run.exit_code == 0, run.output
    assert "0 invalid" in run.output
    heights = [float(line.split("/")[1]) for line in out.read_text().splitlines()
               if line.startswith("$$LAYER/")]
    assert min(heights) > 0 and heights == sorted(heights)
    doc = json.loads(report.read_text())
    assert doc["build_plate_offset"] == pytest.approx(-106.086, abs=0.01)
    assert all(layer["valid"] for layer in doc["per_layer"])


def test_projection_onto_the_local_quadric_removes_noise_not_curvature():
    """Each point is projected onto the least-squares quadric of its neighbourhood before it
    slides: on a clean cylinder of radius 2 it does not move (the plane through the
    neighbourhood's centroid lies r^2 / 6R = 0.006 inside), and at 0.01 noise it halves the
    distance to the true wall."""
    rng = np.random.default_rng(0)
    t, h = rng.uniform(0, 2 * np.pi, 5000), rng.uniform(0, 4, 5000)
    clean = np.column_stack([2 * np.cos(t), 2 * np.sin(t), h])
    clean = clean[np.argsort(h)]
    assert np.abs(surface_samples(clean).offset).max() < 1e-3
    s = surface_samples(clean + rng.normal(scale=0.01, size=clean.shape))
    projected = s.uvh - s.offset[:, None] * s.normals
    raw_error = np.abs(np.hypot(*s.uvh[:, :2].T) - 2).mean()
    assert np.abs(np.hypot(*projected[:, :2].T) - 2).mean() < 0.6 * raw_error


def test_a_thin_walls_section_lies_on_its_two_faces():
    """A slab 0.08 thick, thinner than a neighbourhood (radius about 0.25): each point is
    fitted to its own face, so the section points lie on the two faces, not on the plane down
    the wall's middle that the neighbourhood as a whole gives."""
    rng = np.random.default_rng(3)
    n = 40000
    face = rng.integers(0, 2, n)
    wall = np.column_stack([0.08 * face, rng.uniform(-6, 6, n), rng.uniform(0, 6, n)])
    wall += rng.normal(scale=0.002, size=wall.shape)
    uvh = wall[np.argsort(wall[:, 2])]
    surface = surface_samples(uvh)
    rows = slice(*np.searchsorted(surface.uvh[:, 2], [2.0, 4.0]))
    x = section_points(surface, rows, 3.0)[:, 0]
    off_face = np.minimum(np.abs(x), np.abs(x - 0.08))
    assert len(x) > 300
    assert np.percentile(off_face, 99) < 0.01
    assert min(np.sum(x < 0.04), np.sum(x > 0.04)) > 0.4 * len(x)


def test_a_thin_shells_shallow_section_lies_on_its_two_faces():
    """The cap of a hollow ball whose shell (0.08) is thinner than a neighbourhood, cut 0.2
    below its pole: the surface meets the plane at 21 degrees, so the points are fitted again
    as height fields over a wider neighbourhood, which holds both faces; each is fitted to
    its own face, and the section points lie on the outer and the inner circle, not between
    them (0.95 in the median: the layer drew a disc)."""
    rng = np.random.default_rng(7)
    caps = []
    for radius in (3.0, 2.92):
        d = rng.normal(size=(40000, 3))
        d = d[d[:, 2] > 0.73 * np.linalg.norm(d, axis=1)][:4000]
        caps.append(radius * d / np.linalg.norm(d, axis=1, keepdims=True))
    cap = np.vstack(caps) + rng.normal(scale=0.002, size=(8000, 3))
    uvh = cap[np.argsort(cap[:, 2])]
    surface = surface_samples(uvh)
    rows = slice(*np.searchsorted(surface.uvh[:, 2], [2.6, 3.0]))
    r = np.hypot(*section_points(surface, rows, 2.8).T)
    outer, inner = np.sqrt(3.0**2 - 2.8**2), np.sqrt(2.92**2 - 2.8**2)
    assert np.percentile(np.minimum(np.abs(r - outer), np.abs(r - inner)), 95) < 0.02
    assert min(np.sum(r > (outer + inner) / 2), np.sum(r < (outer + inner) / 2)) > 0.3 * len(r)


def test_a_shallow_dome_gives_its_ring_and_a_face_in_the_plane_none():
    """A sphere's top cut 0.3 below its pole meets the plane at 25 degrees, shallower than a
    tangent plane's noise allows: a wider height-field fit whose slope stands out of the noise
    gives the ring (an ear's tip on the bunny was missing). A flat face lying in the plane,
    whose noisy slopes are no signal, gives no section."""
    rng = np.random.default_rng(5)
    n = 40000
    d = rng.normal(size=(n, 3))
    d[:, 2] = np.abs(d[:, 2])
    ball = 3 * d / np.linalg.norm(d, axis=1, keepdims=True)
    ball += rng.normal(scale=0.01, size=ball.shape)
    uvh = ball[np.argsort(ball[:, 2])]
    surface = surface_samples(uvh)
    rows = slice(*np.searchsorted(uvh[:, 2], [2.5, 2.9]))
    sec = section_points(surface, rows, 2.7)
    ring = np.sqrt(9 - 2.7**2)
    assert len(sec) > 50 and _largest_gap(sec) < 0.3 * ring
    assert np.abs(np.hypot(*sec.T) - ring).max() < 0.06
    face = np.column_stack([rng.uniform(-3, 3, (n, 2)), rng.normal(scale=0.01, size=n)])
    face = face[np.argsort(face[:, 2])]
    flat = surface_samples(face)
    assert len(section_points(flat, slice(None), 0.0)) < 0.001 * n


def test_strays_leave_the_section_and_corners_stay():
    """A slide gone wrong puts a few section points off the line of their neighbours (the
    bunny's tail: a spike of 1.7 tolerances); they are dropped, and the points of a square's
    sharp corners, off no line of their own neighbours, are kept."""
    from wavepoly.sections import _without_strays

    rng = np.random.default_rng(6)
    s = rng.uniform(0, 4, 4000)
    side = np.floor(s).astype(int)
    f = s - side
    corners = np.array([[0.0, 0], [1, 0], [1, 1], [0, 1], [0, 0]])
    square = corners[side] + f[:, None] * (corners[side + 1] - corners[side])
    square += rng.normal(scale=0.002, size=square.shape)
    strays = np.array([[0.5, 0.03], [0.52, 0.035], [0.3, 0.97]])
    kept = _without_strays(np.vstack([square, strays]))
    assert not any(np.any(np.all(kept == p, axis=1)) for p in strays)
    assert len(kept) >= 0.97 * len(square)
    for c in corners[:4]:  # each corner keeps its nearest points
        assert np.min(np.hypot(*(kept - c).T)) < 0.01


def test_a_simplified_section_keeps_its_area_and_the_tolerance():
    """The fewest-vertex polygon of a circle within ε, its vertices on the circle, is 6 %
    short of its area (every chord sags inside); moved out along their normals, the vertices
    give the circle's area within 0.5 %, and every point of the circle stays within ε."""
    import shapely

    from wavepoly.polylines import fit_polylines

    t = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    circle = 10 * np.column_stack([np.cos(t), np.sin(t)])
    (contour,) = fit_polylines([(circle, True)], 0.5).contours
    area = shapely.Polygon(contour.vertices).area
    assert abs(area / shapely.Polygon(circle).area - 1) < 0.005
    fine = np.linspace(0, 2 * np.pi, 20000, endpoint=False)
    dense = 10 * np.column_stack([np.cos(fine), np.sin(fine)])
    ring = shapely.LinearRing(contour.vertices)
    assert shapely.distance(shapely.points(dense), ring).max() <= 0.5 * (1 + 1e-9)
    assert shapely.is_valid(shapely.Polygon(contour.vertices))


def _off_square(xy: np.ndarray, half: float) -> np.ndarray:
    """Distance of each point from the square [-half, half]² (its outline)."""
    a = np.abs(xy)
    inside = a.max(axis=1) <= half
    out = np.hypot(*np.maximum(a - half, 0.0).T)
    return np.where(inside, half - a.max(axis=1), out)


def _block_sections():
    """Section points of the stepped block (a 4 x 4 x 1 block under a 2 x 2 x 1 one, noise
    ε / 5) at heights along its walls, each with its square's half-width."""
    from .test_flat_faces import stepped_block

    pts = stepped_block()
    surface = surface_samples(pts[np.argsort(pts[:, 2])])
    heights = surface.uvh[:, 2]
    for z in (0.15, 0.3, 0.5, 0.7, 0.85, 0.95, 1.05, 1.15, 1.3, 1.5, 1.7, 1.85):
        rows = slice(*np.searchsorted(heights, [z - 0.05, z + 0.05]))
        yield section_points(surface, rows, z), (2.0 if z < 1 else 1.0)


def _corner_gaps(sections) -> np.ndarray:
    """Per section, the farthest of the square's corners from its nearest section point."""
    from scipy.spatial import cKDTree

    signs = np.array([[1, 1], [-1, 1], [-1, -1], [1, -1]])
    return np.array([cKDTree(xy).query(half * signs)[0].max() for xy, half in sections])


def test_a_boxs_vertical_corners_survive_in_its_sections():
    """A point beside a vertical edge has a neighbourhood on both walls, whose plane is
    neither; it takes the plane of a flatter neighbourhood it lies on, so the section points
    run into the corners (measured, ε 0.05: the farthest corner 0.51 ε from them in the median
    section, at most 1.88 ε, at 1.05 where the edges stand on the step; with each point's own
    plane 1.54 and 2.75 ε, as the next test shows). And no section point strays from the walls
    (0.51 ε at most), beside the step's face either: at 0.95 and 1.05 its rim's height fits,
    which span the edge, had slid points 1.9 ε off the walls along the edge's tilt."""
    eps = 0.05
    sections = list(_block_sections())
    assert max(_off_square(xy, half).max() for xy, half in sections) < 0.6 * eps
    gaps = _corner_gaps(sections)
    assert np.median(gaps) < 0.6 * eps and gaps.max() < 2.0 * eps


def test_without_the_flatter_neighbours_planes_the_corners_are_cut(monkeypatch):
    """The test above can fail: a point keeps its own plane however it straddles an edge."""
    import wavepoly.sections as sections

    monkeypatch.setattr(sections, "EDGE_FLATNESS", np.inf)
    gaps = _corner_gaps(_block_sections())
    assert np.median(gaps) > 1.2 * 0.05
