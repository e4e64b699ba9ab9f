"""Many tiles as one cloud: read in chunks, sliced locally or on a real Dask cluster."""

from __future__ import annotations

import os
import signal

import numpy as np
import pytest

from wavepoly.errors import DataError, EngineError
from wavepoly.io.tiles import expand_sources, read_chunks, tile_layers, tile_summary
from wavepoly.slicing import plane_basis, slice_cloud
from wavepoly.tiled import slice_tiles

from .truth import las_tiles

laspy = pytest.importorskip("laspy")


def vase(n=60000, seed=5):
    """A vase with a wall of two sides: every layer an outer ring and a hole."""
    rng = np.random.default_rng(seed)
    t, h = rng.uniform(0, 2 * np.pi, n), rng.uniform(0, 10, n)
    r = 4.0 + np.sin(h / 2) + np.where(rng.random(n) < 0.5, 0.0, -1.2)
    pts = np.column_stack([r * np.cos(t), r * np.sin(t), h])
    return pts + rng.normal(scale=0.005, size=pts.shape)


def write_tiles(folder, cloud, count=3):
    """The cloud as LAZ tiles (`truth.las_tiles`)."""
    return las_tiles(folder, cloud, count)


@pytest.fixture(scope="module")
def tiles(tmp_path_factory):
    return write_tiles(tmp_path_factory.mktemp("tiles"), vase())


def signature(result):
    """What must agree between two runs: layers, their contours and vertices, their errors."""
    return [(la.bottom, la.slab_points, la.model_error,
             [(c.closed, c.vertices.tobytes()) for c in la.fit.contours])
            for la in result.layers]


def test_chunks_hold_every_point_of_a_tile_in_file_order(tiles):
    whole = np.concatenate([np.column_stack([f.x, f.y, f.z])
                            for f in [laspy.read(str(tiles[0]))]])
    chunks = list(read_chunks(tiles[0], size=7000))
    assert len(chunks) == int(np.ceil(len(whole) / 7000))
    np.testing.assert_array_equal(np.concatenate(chunks), whole)


def test_a_tile_splits_into_the_layers_of_its_points(tiles):
    basis = plane_basis("z")
    summary = tile_summary(tiles[1], basis)
    bottoms = np.linspace(summary.low, summary.high, 6)[:-1]
    parts = tile_layers(tiles[1], basis, bottoms)
    assert sum(len(p) for p in parts) == summary.count
    for k, part in enumerate(parts):
        assert np.all(part[:, 2] >= bottoms[k])
        if k + 1 < len(bottoms):
            assert np.all(part[:, 2] < bottoms[k + 1])


def test_sources_are_files_folders_and_patterns(tiles):
    folder = tiles[0].parent
    assert expand_sources([folder]) == tiles
    assert expand_sources([str(folder / "tile*.laz")]) == tiles
    with pytest.raises(DataError, match="matches no file"):
        expand_sources([str(folder / "none*.laz")])


def test_local_tiles_are_the_cloud_they_hold(tiles):
    cloud = np.concatenate([np.column_stack([f.x, f.y, f.z])
                            for f in (laspy.read(str(p)) for p in tiles)])
    from_tiles = slice_tiles(tiles, 0.05, layer_thickness=1.0, workers=1)
    assert signature(from_tiles) == signature(slice_cloud(cloud, 0.05, layer_thickness=1.0,
                                                          workers=1))
    assert all(len(la.fit.contours) == 2 for la in from_tiles.layers if la.slab_points > 1000)


def test_a_tile_with_nan_is_an_error_naming_it(tmp_path):
    bad = tmp_path / "bad.xyz"
    bad.write_text("0 0 0\n1 0 nan\n0 1 1\n1 1 2\n")
    with pytest.raises(DataError, match="bad.xyz"):
        slice_tiles([bad], 0.05, layer_thickness=1.0, workers=1)


# --- a real cluster on this machine -----------------------------------------------------------

distributed = pytest.importorskip("distributed")


@pytest.fixture(scope="module")
def cluster():
    """A scheduler and two worker processes on 127.0.0.1, stopped after the module."""
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=None) as c:
        yield c


def test_the_cluster_gives_the_layer_model_of_the_local_run(tiles, cluster):
    local = slice_tiles(tiles, 0.05, layer_thickness=1.0, workers=2)
    remote = slice_tiles(tiles, 0.05, layer_thickness=1.0, scheduler=cluster.scheduler_address)
    assert signature(remote) == signature(local)
    assert remote.engine == {"kind": "dask", "scheduler": cluster.scheduler_address,
                             "workers": 2}
    assert local.engine["kind"] == "local"


def test_a_worker_killed_mid_run_loses_no_layer(tiles, cluster):
    local = slice_tiles(tiles, 0.05, layer_thickness=0.5, workers=2)
    with distributed.Client(cluster) as client:
        pids = list(client.run(os.getpid).values())
    killed = []

    def kill_one(done, total):
        if not killed:
            os.kill(pids[0], signal.SIGKILL)
            killed.append(done)

    remote = slice_tiles(tiles, 0.05, layer_thickness=0.5, scheduler=cluster.scheduler_address,
                         progress=kill_one)
    assert killed and killed[0] < len(local.layers)
    assert signature(remote) == signature(local)


def test_an_unreachable_scheduler_is_a_one_line_error(monkeypatch, tiles):
    import wavepoly.tiled

    monkeypatch.setattr(wavepoly.tiled, "CONNECT_TIMEOUT", 1)
    with pytest.raises(EngineError, match="cannot reach the Dask scheduler at tcp://127.0.0.1:9"):
        slice_tiles(tiles, 0.05, layer_thickness=1.0, scheduler="tcp://127.0.0.1:9")


def _wavepoly(*args, env=None):
    import subprocess
    import sys

    return subprocess.run([sys.executable, "-m", "wavepoly", *map(str, args)],
                          capture_output=True, text=True, env=env, timeout=300)


def test_the_command_slices_tiles_on_a_scheduler_as_it_does_here(tiles, cluster, tmp_path):
    import json

    here, there = tmp_path / "here.cli", tmp_path / "there.cli"
    report = tmp_path / "there.json"
    out = _wavepoly("slice", *tiles, "-t", "0.05", "--layer", "1", "-o", here)
    assert out.returncode == 0, out.stderr
    env = {**os.environ, "DASK_SCHEDULER_ADDRESS": cluster.scheduler_address}
    out = _wavepoly("slice", tiles[0].parent / "*.laz", "-t", "0.05", "--layer", "1",
                    "-o", there, "--report", report, env=env)
    assert out.returncode == 0, out.stderr
    assert there.read_bytes() == here.read_bytes()
    doc = json.loads(report.read_text())
    assert doc["engine"]["kind"] == "dask" and doc["input"] == [str(p) for p in tiles]


def test_the_command_names_an_unreachable_scheduler_and_writes_nothing(tiles, tmp_path):
    out = _wavepoly("slice", tiles[0], "-t", "0.05", "--layer", "1", "-o", tmp_path / "m.cli",
                    "--scheduler", "tcp://127.0.0.1:9")
    assert out.returncode == 1
    assert out.stderr.strip().count("\n") == 0
    assert "cannot reach the Dask scheduler at tcp://127.0.0.1:9" in out.stderr
    assert list(tmp_path.iterdir()) == []


def test_adaptive_layers_of_tiles_run_here_on_their_union(tiles, tmp_path):
    import json

    out = _wavepoly("slice", tiles[0].parent, "-t", "0.1", "--adaptive", "-o",
                    tmp_path / "a.cli", "--report", tmp_path / "a.json")
    assert out.returncode == 0, out.stderr
    doc = json.loads((tmp_path / "a.json").read_text())
    assert doc["adaptive"] and doc["points"] == 60000 and doc["input"] == [str(p) for p in tiles]
    assert doc["model_error"] <= 0.1 * (1 + 1e-9)


def test_a_float32_ply_stays_float32_and_slices_as_its_widened_cloud(tmp_path):
    """A binary PLY of float32 vertices is read (memory-mapped, in chunks) as float32, half the
    memory of a widened cloud, and its layer model is that of the same points as float64."""
    from plyfile import PlyData, PlyElement

    cloud = vase(20000).astype(np.float32)
    vertex = np.empty(len(cloud), dtype=[("x", "<f4"), ("y", "<f4"), ("z", "<f4")])
    vertex["x"], vertex["y"], vertex["z"] = cloud.T
    path = tmp_path / "vase.ply"
    PlyData([PlyElement.describe(vertex, "vertex")]).write(str(path))
    chunks = list(read_chunks(path, size=7000))
    assert [c.dtype for c in chunks] == [np.float32] * 3
    np.testing.assert_array_equal(np.concatenate(chunks), cloud)
    from_file = slice_tiles([path], 0.05, layer_thickness=2.0, workers=1)
    widened = slice_cloud(cloud.astype(np.float64), 0.05, layer_thickness=2.0, workers=1)
    assert signature(from_file) == signature(widened)
