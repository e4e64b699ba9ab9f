"""Ground truth for tests: dense noisy samples of known curves, and order-agreement measures."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import shapely
from scipy.spatial import cKDTree
from scipy.stats import kendalltau

from wavepoly.samples import TrueShape


def svg_shape(path: Path, per_ring: int = 4000) -> TrueShape:
    """Every sub-path of the SVG's paths, sampled densely in path order (y flipped up)."""
    from svgelements import SVG
    from svgelements import Path as SvgPath

    rings, closed = [], []
    for element in SVG.parse(str(path)).elements():
        if not isinstance(element, SvgPath) or not len(element):
            continue
        for sub in element.as_subpaths():
            sub = SvgPath(sub)
            if sub.length() <= 0:
                continue
            xy = np.asarray(sub.npoint(np.linspace(0.0, 1.0, per_ring, endpoint=False)))
            rings.append(xy * [1.0, -1.0])
            closed.append(bool(sub.closed))
    return TrueShape(rings, closed)


def diagonal(shape: TrueShape) -> float:
    allp = np.concatenate(shape.rings)
    return float(np.linalg.norm(np.ptp(allp, axis=0)))


def order_agreement(contour_points: np.ndarray, shape: TrueShape, closed: bool
                    ) -> tuple[int, float]:
    """(ring index, |Kendall tau|) between the contour's order and the true parameter order.

    Each ordered point takes the parameter of its nearest true sample; on a closed ring the
    parameters are unwrapped (steps taken modulo a full turn), which removes the start point
    and the direction.
    """
    lengths = [len(r) for r in shape.rings]
    offsets = np.cumsum([0, *lengths])
    tree = cKDTree(np.concatenate(shape.rings))
    _, idx = tree.query(contour_points)
    ring = np.searchsorted(offsets, idx, side="right") - 1
    main = np.bincount(ring).argmax()
    sel = ring == main
    t = (idx[sel] - offsets[main]) / lengths[main]
    if closed:
        step = np.diff(t)
        step = (step + 0.5) % 1.0 - 0.5
        t = np.concatenate([[t[0]], t[0] + np.cumsum(step)])
    tau = kendalltau(np.arange(len(t)), t).statistic
    return int(main), float(abs(tau))


def densify(shape: TrueShape, step: float) -> TrueShape:
    """The same rings resampled every ``step`` along their length (truth for nearest look-ups)."""
    rings = []
    for ring, closed in zip(shape.rings, shape.closed):
        verts = np.vstack([ring, ring[:1]]) if closed else ring
        cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(verts, axis=0), axis=1))])
        s = np.arange(0.0, cum[-1], step)
        rings.append(np.column_stack([np.interp(s, cum, verts[:, 0]),
                                      np.interp(s, cum, verts[:, 1])]))
    return TrueShape(rings, list(shape.closed))


def independent_problems(result) -> list[str]:
    """What a GIS or CAD user would check, with shapely directly: every closed contour a valid
    polygon, every open one simple, no two contours meeting except at an open one's end."""
    problems = []
    geoms = []
    for k, c in enumerate(result.contours):
        if c.closed:
            poly = shapely.Polygon(c.vertices)
            if not poly.is_valid or poly.area <= 0:
                problems.append(f"contour {k}: {shapely.is_valid_reason(poly)}")
            geoms.append(shapely.LinearRing(c.vertices))
        else:
            line = shapely.LineString(c.vertices)
            if not line.is_simple:
                problems.append(f"contour {k}: open and not simple")
            geoms.append(line)
    for i in range(len(geoms)):
        for j in range(i + 1, len(geoms)):
            meet = geoms[i].intersection(geoms[j])
            if meet.is_empty:
                continue
            ends = [c.vertices[[0, -1]] for c in (result.contours[i], result.contours[j])
                    if not c.closed]
            if ends:
                meet = meet.difference(shapely.MultiPoint(np.concatenate(ends)).buffer(1e-9))
            if not meet.is_empty:
                problems.append(f"contours {i} and {j} meet: {meet.geom_type}")
    return problems


def layer_agreement(mesh, result, eps: float) -> list[dict]:
    """Each layer against the exact section of ``mesh`` at its mid-plane: valid, closed,
    Hausdorff distance between the boundaries (in ε), and the area between the two regions
    (their symmetric difference) against the section's perimeter x ε. ``right`` when valid,
    closed, Hausdorff <= 1.5 ε and the area below perimeter x ε. ``hole``: the mid-plane
    crosses a hole of the mesh (`hole_spans`), where the section is open and judges nothing.
    """
    from wavepoly.sections import mesh_section
    from wavepoly.staircase import region
    from wavepoly.types import Contour

    rows, holes = [], hole_spans(mesh, result.basis)
    for layer in result.layers:
        truth = [Contour(xy, closed) for xy, closed in mesh_section(mesh, result.basis, layer.z)]
        got = layer.fit.contours
        row = {"z": layer.z, "truth": len(truth), "contours": len(got),
               "valid": layer.fit.validity is None or layer.fit.validity.valid,
               "closed": all(c.closed for c in got) and bool(got) == bool(truth),
               "hole": any(lo <= layer.z <= hi for lo, hi in holes)}
        if truth and got:
            lines = [shapely.linearrings(c.vertices) if c.closed else
                     shapely.linestrings(c.vertices) for c in truth]
            drawn = [shapely.linearrings(c.vertices) if c.closed else
                     shapely.linestrings(c.vertices) for c in got]
            hd = shapely.hausdorff_distance(shapely.union_all(lines), shapely.union_all(drawn),
                                            densify=0.05)
            a, b = region(truth), region(got)
            perimeter = sum(line.length for line in lines)
            row.update(hausdorff=hd / eps, area_ratio=(b.area / a.area if a.area else np.nan),
                       sym_diff=shapely.symmetric_difference(a, b).area / (perimeter * eps))
        else:
            row.update(hausdorff=0.0 if not truth and not got else np.inf,
                       area_ratio=np.nan, sym_diff=0.0 if not truth and not got else np.inf)
        row["right"] = bool(row["valid"] and row["closed"] and row["hausdorff"] <= 1.5
                            and row["sym_diff"] < 1.0)
        rows.append(row)
    return rows


def partial_agreement(mesh, result, eps: float) -> list[dict]:
    """For a scan that saw only part of the object: per layer with a section and contours,
    ``on_truth``, the largest distance (in ε) of the drawn contours to the exact section
    (what is drawn lies on the object), and ``covered``, the fraction of the section's
    length within 1.5 ε of the drawn contours (how much of it the scan saw and the layer
    shows)."""
    from wavepoly.sections import mesh_section

    def lines(curves):
        return shapely.union_all([shapely.linearrings(xy) if closed else
                                  shapely.linestrings(xy) for xy, closed in curves])

    rows = []
    for layer in result.layers:
        truth = mesh_section(mesh, result.basis, layer.z)
        got = [(c.vertices, c.closed) for c in layer.fit.contours]
        if not truth or not got:
            continue
        exact, drawn = lines(truth), lines(got)
        along = shapely.points(shapely.get_coordinates(shapely.segmentize(drawn, eps / 10)))
        rows.append({"z": layer.z, "on_truth": float(shapely.distance(along, exact).max()) / eps,
                     "covered": float(shapely.length(shapely.intersection(
                         exact, shapely.buffer(drawn, 1.5 * eps))) / shapely.length(exact))})
    return rows


def hole_spans(mesh, basis: np.ndarray) -> list[tuple[float, float]]:
    """The heights (along ``basis[2]``) that each hole of the mesh spans: a loop of boundary
    edges (edges of one face). A plane within a hole's span meets an open surface there (the
    zippered bunny has four holes in its base and one in its side): its exact section bounds
    no region, so the layer's area cannot be judged against it, nor its closing."""
    import trimesh

    m = trimesh.Trimesh(np.asarray(mesh.vertices), np.asarray(mesh.faces), process=True)
    boundary = m.edges[trimesh.grouping.group_rows(m.edges_sorted, require_count=1)]
    heights = m.vertices @ np.asarray(basis)[2]
    return [(float(heights[loop].min()), float(heights[loop].max()))
            for loop in trimesh.graph.connected_components(boundary, min_len=3)]


def closed_mesh(mesh):
    """The mesh with each hole (`hole_spans`) fanned shut from its centroid, the fan wound
    against the faces along it: the solid that a scan with holes stands for, whose volume
    the layer model's is compared with."""
    import trimesh

    m = trimesh.Trimesh(np.asarray(mesh.vertices), np.asarray(mesh.faces), process=True)
    boundary = m.edges[trimesh.grouping.group_rows(m.edges_sorted, require_count=1)]
    vertices, faces = [m.vertices], [m.faces]
    for loop in trimesh.graph.connected_components(boundary, min_len=3):
        edges = boundary[np.isin(boundary[:, 0], loop)]
        centre = len(m.vertices) + len(vertices) - 1
        vertices.append(m.vertices[np.unique(edges)].mean(axis=0, keepdims=True))
        faces.append(np.column_stack([edges[:, 1], edges[:, 0], np.full(len(edges), centre)]))
    return trimesh.Trimesh(np.vstack(vertices), np.vstack(faces), process=False)


def noisy_surface_cloud(mesh, n: int, sigma: float, seed: int = 0) -> np.ndarray:
    """``n`` points sampled uniformly on the mesh's faces, with Gaussian noise ``sigma``."""
    import trimesh

    pts, _ = trimesh.sample.sample_surface(mesh, n, seed=seed)
    return pts + np.random.default_rng(seed).normal(scale=sigma, size=pts.shape)


def las_tiles(folder, cloud: np.ndarray, count: int) -> list:
    """The cloud as ``count`` LAZ tiles cut across x (as a survey is), 0.1 µm grid, each
    tile's points in the cloud's order; the paths, in order."""
    import laspy

    folder.mkdir(parents=True, exist_ok=True)
    order = np.argsort(cloud[:, 0], kind="stable")
    paths = []
    for k, part in enumerate(np.array_split(order, count)):
        header = laspy.LasHeader(point_format=0, version="1.2")
        header.scales, header.offsets = [1e-4] * 3, cloud.min(axis=0)
        las = laspy.LasData(header)
        pts = cloud[np.sort(part)]
        las.x, las.y, las.z = pts[:, 0], pts[:, 1], pts[:, 2]
        paths.append(folder / f"tile{k}.laz")
        las.write(str(paths[-1]))
    return paths


def blob_sweep_case(seed: int, noise: float):
    """The validity benchmark's blob sweep image ``seed`` (blob size 0.1, ε = diagonal / 150),
    sampled every ε / 3 with noise ``noise`` ε, and its fit: (points, result, true rings)."""
    import wavepoly
    from benchmarks.silhouettes import blobs, sample

    rings = blobs(seed, 0.1)
    eps = 256 * np.sqrt(2) / 150
    length = sum(shapely.LinearRing(r).length for r in rings)
    pts = sample(rings, int(3 * length / eps), noise * eps, seed)
    return pts, wavepoly.fit(pts, eps), rings
