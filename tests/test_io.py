"""Readers and writers: every format, the real files in ../shared/data, and bad input."""

from __future__ import annotations

import gzip
import json
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import wavepoly
from wavepoly import as_planar
from wavepoly.errors import DataError
from wavepoly.io import read_points, write_polygons
from wavepoly.io.atomic import atomic_path
from wavepoly.types import Contour, FitResult

NOT_POINTS = {"README.md", "README.txt", "README", "LICENSE", "gpl.txt", "bun.conf"}
EXPECTED_COUNTS = {"bunny_zipper.ply": 35947, "turbineblade.ply": 99519, "distcap.pts": 12745,
                   "cactus.pts": 3318, "family.gtn": 9990, "ventilator.gtn": 194}


def shared_point_files(root):
    """Every point file: not the licences/READMEs, nor the ground-truth SVG drawings (curves)."""
    return sorted(p for p in root.rglob("*")
                  if p.is_file() and p.name not in NOT_POINTS and p.suffix != ".svg")


def test_every_shared_file_reads(shared_data):
    files = shared_point_files(shared_data)
    assert len(files) >= 35
    for path in files:
        pts = read_points(path)
        assert pts.ndim == 2 and pts.shape[1] in (2, 3) and len(pts) >= 10, path
        assert np.isfinite(pts).all()
        if path.name in EXPECTED_COUNTS:
            assert len(pts) == EXPECTED_COUNTS[path.name], path


def test_licence_text_is_a_clear_error(shared_data):
    with pytest.raises(DataError, match="gpl.txt"):
        read_points(shared_data / "curves2d" / "noisy_sets" / "gpl.txt")


def test_carmen_log_gives_world_points(shared_data):
    pts = read_points(shared_data / "lidar2d" / "intel-corrected.log.gz")
    assert pts.shape[1] == 2
    assert 100_000 < len(pts) < 170_000  # ~160k returns less the no-returns
    extent = np.ptp(pts, axis=0)
    assert (extent > 10).all() and (extent < 100).all()  # a building, in metres


def test_hoppe_and_gtn_headers(shared_data):
    pts = read_points(shared_data / "scans3d" / "cactus.pts")
    assert pts.shape == (3318, 3)
    gtn = read_points(shared_data / "curves2d" / "hnn_crust" / "ventilator.gtn")
    p2d = read_points(shared_data / "curves2d" / "hnn_crust" / "ventilator.p2d")
    np.testing.assert_allclose(gtn, p2d)


def test_text_variants(tmp_path):
    f = tmp_path / "a.csv"
    f.write_text("x,y,z\n# comment\n1,2,3\n4,5,6  # trailing\n\n7,8,9\n")
    np.testing.assert_array_equal(read_points(f), [[1, 2, 3], [4, 5, 6], [7, 8, 9]])
    np.testing.assert_array_equal(read_points(f, columns=(2, 0)), [[3, 1], [6, 4], [9, 7]])
    xy = tmp_path / "b.xy"
    xy.write_text("0 0 1\n1 0 1\n1 1 1\n")
    assert read_points(xy).shape == (3, 2)
    with pytest.raises(DataError, match="column 5"):
        read_points(f, columns=(0, 5))


def test_npy_ply_obj_off_pcd_las(tmp_path):
    pts = np.random.default_rng(0).normal(size=(50, 3))
    np.save(tmp_path / "p.npy", pts)
    np.testing.assert_allclose(read_points(tmp_path / "p.npy"), pts)

    from plyfile import PlyData, PlyElement

    vert = np.array([tuple(p) for p in pts], dtype=[("x", "f8"), ("y", "f8"), ("z", "f8")])
    for text in (True, False):
        path = tmp_path / f"p{text}.ply"
        PlyData([PlyElement.describe(vert, "vertex")], text=text).write(str(path))
        np.testing.assert_allclose(read_points(path), pts, atol=1e-6)

    (tmp_path / "m.obj").write_text("".join(f"v {x} {y} {z}\n" for x, y, z in pts) + "f 1 2 3\n")
    np.testing.assert_allclose(read_points(tmp_path / "m.obj"), pts)
    (tmp_path / "m.off").write_text("OFF\n50 1 0\n" + "".join(f"{x} {y} {z}\n" for x, y, z in pts)
                                    + "3 0 1 2\n")
    np.testing.assert_allclose(read_points(tmp_path / "m.off"), pts)

    header = ("VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 50\n"
              "HEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 50\n")
    (tmp_path / "a.pcd").write_text(header + "DATA ascii\n" +
                                    "".join(f"{x} {y} {z}\n" for x, y, z in pts))
    np.testing.assert_allclose(read_points(tmp_path / "a.pcd"), pts, atol=1e-6)
    (tmp_path / "b.pcd").write_bytes((header + "DATA binary\n").encode() +
                                     pts.astype("<f4").tobytes())
    np.testing.assert_allclose(read_points(tmp_path / "b.pcd"), pts, atol=1e-6)
    (tmp_path / "c.pcd").write_bytes((header + "DATA binary_compressed\n").encode() + b"\0" * 8)
    with pytest.raises(DataError, match="the PCD header's fields need"):
        read_points(tmp_path / "c.pcd")

    import laspy

    las = laspy.create(point_format=3, file_version="1.2")
    las.header.scales = [0.001] * 3
    las.header.offsets = [0.0] * 3
    las.x, las.y, las.z = pts[:, 0], pts[:, 1], pts[:, 2]
    for ext in ("las", "laz"):
        las.write(str(tmp_path / f"p.{ext}"))
        np.testing.assert_allclose(read_points(tmp_path / f"p.{ext}"), pts, atol=1e-3)


def test_carmen_synthetic(tmp_path):
    ranges = ["1.0", "81.9", "2.0"]  # the middle beam is a no-return (sensor maximum)
    line = f"FLASER 3 {' '.join(ranges)} 1.0 2.0 0.0 0 0 0 0 host 0\n"
    path = tmp_path / "s.log.gz"
    with gzip.open(path, "wt") as fh:
        fh.write("# header\nODOM 0 0 0 0 0 0 0\n" + line + line.replace("2.0 0.0", "2.0 1.5708"))
    pts = read_points(path, fmt="carmen")
    # beams at -90 and +90 degrees about theta = 0 from (1, 2): (1, 1) and (1, 4)
    np.testing.assert_allclose(pts[:2], [[1.0, 1.0], [1.0, 4.0]], atol=1e-9)
    assert len(pts) == 4


def _robotlaser(ranges, start, resolution, limit, pose, remissions=0):
    """A ROBOTLASER1 line: SICK type 0, ``ranges`` from ``start`` by ``resolution``."""
    values = " ".join(f"{r:g}" for r in ranges)
    rem = " ".join(["0.5"] * remissions)
    return (f"ROBOTLASER1 0 {start:.9f} {resolution * len(ranges):.9f} {resolution:.9f} "
            f"{limit:g} 0.01 0 {len(ranges)} {values} {remissions} {rem} "
            f"{pose[0]} {pose[1]} {pose[2]} 0 0 0 0 0 0 0 0 1.0 host 1.0\n")


def test_carmen_robotlaser_takes_its_own_field_of_view(tmp_path):
    """A 270 degree scanner's ROBOTLASER1 line: beam i at start + i * resolution about the
    laser's heading; returns at the line's range limit are no-returns."""
    step = np.radians(135.0)
    line = _robotlaser([1.0, 2.0, 30.0], -step, step, 30.0, (1.0, 2.0, np.pi / 2), 3)
    path = tmp_path / "s.clf"
    path.write_text("PARAM robot_use_laser on\n" + line)
    pts = read_points(path)
    # heading +90 degrees: beams at -45 and +90 degrees from (1, 2); the third is at the limit
    np.testing.assert_allclose(pts, [[1 + np.sqrt(0.5), 2 - np.sqrt(0.5)], [1.0, 4.0]],
                               atol=1e-6)


def test_carmen_no_returns_a_hair_below_the_sensor_maximum_are_dropped(tmp_path):
    """No-returns written as 81.83 and, on a dazzled beam, 81.82: neither is a wall 80 m out."""
    path = tmp_path / "max.log"
    path.write_text("FLASER 5 1.0 81.83 81.82 1.0 1.0 0.0 0.0 0.0 0 0 0 0 host 0\n")
    h = np.sqrt(0.5)  # beams at -90, -45, 0, 45 and 90 degrees
    np.testing.assert_allclose(read_points(path), [[0.0, -1.0], [h, h], [0.0, 1.0]], atol=1e-9)


def test_carmen_log_with_both_kinds_reads_each_scan_once(tmp_path):
    """A converted log keeps FLASER lines beside ROBOTLASER1: the scans are placed once."""
    flaser = "FLASER 3 1.0 1.0 1.0 0.0 0.0 0.0 0 0 0 0 host 0\n"
    robot = _robotlaser([1.0, 1.0, 1.0], -np.pi / 2, np.pi / 2, 80.0, (0.0, 0.0, 0.0))
    path = tmp_path / "both.clf.gz"
    with gzip.open(path, "wt") as fh:
        fh.write((flaser + robot) * 2)
    pts = read_points(path)
    assert len(pts) == 6
    np.testing.assert_allclose(pts[:3], [[0.0, -1.0], [1.0, 0.0], [0.0, 1.0]], atol=1e-6)


@pytest.mark.parametrize("line, message", [
    ("FLASER 180 1.0 2.0 3.0 0 0 0\n", "line 2: FLASER says 180 values, but the line is too short"),
    ("FLASER x 1.0\n", "line 2: FLASER has no reading count"),
    ("FLASER 3 1.0 2.0 abc 0 0 0 0 0 0\n", "line 2: 'abc' is not a number"),
    ("FLASER 3 1.0 2.0 3.0 nan 0 0 0 0 0\n", "line 2: a reading or the pose is not finite"),
    ("ROBOTLASER1 0 -1.5 3.1 1.0 80 0.01 0 3 1 1 1 5 0.5\n",
     "line 2: ROBOTLASER1 says 5 values, but the line is too short"),
    ("ODOM 0 0 0 0 0 0\n", "has no FLASER or ROBOTLASER1 lines"),
])
def test_carmen_lines_that_lie_are_refused_by_line(tmp_path, line, message):
    path = tmp_path / "bad.log"
    path.write_text("# a CARMEN log\n" + line)
    with pytest.raises(DataError, match=message):
        read_points(path)


@pytest.mark.parametrize("content, message", [
    ("", "no numeric rows"),
    ("# only a comment\n", "no numeric rows"),
    ("1 2\n", "only 1 point"),
    ("1 2\n1 2\n1 2\n", "identical"),
    ("1 2\nnan 3\n4 5\n", "NaN"),
    ("1 2\ninf 3\n4 5\n", "NaN or infinite"),
    ("1 2\n3 4\nhello world\n", "line 3 is not numeric"),
    ("1\n2\n3\n", "need 2 or more"),
])
def test_bad_text_input(tmp_path, content, message):
    path = tmp_path / "bad.xyz"
    path.write_text(content)
    with pytest.raises(DataError, match=message) as info:
        read_points(path)
    assert str(path) in str(info.value)


def test_missing_directory_unknown_and_truncated(tmp_path):
    with pytest.raises(DataError, match="no such file"):
        read_points(tmp_path / "nope.xyz")
    with pytest.raises(DataError, match="is a directory"):
        read_points(tmp_path)
    (tmp_path / "a.weird").write_text("1 2\n")
    with pytest.raises(DataError, match="unknown point format"):
        read_points(tmp_path / "a.weird")
    from plyfile import PlyData, PlyElement

    vert = np.zeros(100, dtype=[("x", "f4"), ("y", "f4"), ("z", "f4")])
    full = tmp_path / "full.ply"
    PlyData([PlyElement.describe(vert, "vertex")], text=False).write(str(full))
    cut = tmp_path / "cut.ply"
    cut.write_bytes(full.read_bytes()[:-200])
    with pytest.raises(DataError, match="cut.ply"):
        read_points(cut)


def test_as_planar():
    flat = np.column_stack([np.zeros(5), np.arange(5.0), np.arange(5.0) ** 2])
    np.testing.assert_array_equal(as_planar(flat), flat[:, 1:])
    with pytest.raises(DataError, match="3D"):
        as_planar(np.random.default_rng(0).normal(size=(10, 3)))


def _nested_result() -> FitResult:
    square = lambda s, o=0.0: np.array([[o, o], [s, o], [s, s], [o, s]], dtype=float)  # noqa: E731
    outer = Contour(square(10.0), True, 0.01)
    hole = Contour(square(8.0, 2.0)[::-1], True, 0.02)
    island = Contour(square(5.0, 4.0), True)
    line = Contour(np.array([[20.0, 0.0], [25.0, 5.0]]), False)
    return FitResult([outer, hole, island, line], 0.1, 0.02, 0.01, np.empty(0, int), 100,
                     parents=[-1, 0, 1, -1])


def test_geojson_nesting(tmp_path):
    path = tmp_path / "out.geojson"
    write_polygons(path, _nested_result())
    doc = json.loads(path.read_text())
    kinds = [f["geometry"]["type"] for f in doc["features"]]
    assert kinds == ["Polygon", "Polygon", "LineString"]  # outer+hole, island, open line
    assert len(doc["features"][0]["geometry"]["coordinates"]) == 2  # shell and one hole
    ring = doc["features"][0]["geometry"]["coordinates"][0]
    assert ring[0] == ring[-1]


def test_svg_dxf_csv(tmp_path):
    result = _nested_result()
    write_polygons(tmp_path / "o.svg", result)
    root = ET.parse(tmp_path / "o.svg").getroot()
    paths = root.findall(".//{http://www.w3.org/2000/svg}path")
    assert len(paths) == 4 and paths[0].get("d").endswith("Z")
    write_polygons(tmp_path / "o.dxf", result)
    import ezdxf

    polylines = list(ezdxf.readfile(tmp_path / "o.dxf").modelspace().query("LWPOLYLINE"))
    assert [p.closed for p in polylines] == [True, True, True, False]
    write_polygons(tmp_path / "o.csv", result)
    rows = (tmp_path / "o.csv").read_text().splitlines()
    assert rows[0] == "contour,vertex,x,y,closed" and len(rows) == 1 + 4 + 4 + 4 + 2
    with pytest.raises(DataError, match="unknown polygon format"):
        write_polygons(tmp_path / "o.xyz", result)


def test_atomic_write_leaves_nothing_on_failure(tmp_path):
    target = tmp_path / "out.txt"
    with pytest.raises(RuntimeError), atomic_path(target) as tmp:
        tmp.write_text("half")
        raise RuntimeError("interrupted")
    assert list(tmp_path.iterdir()) == []


# -- reliability: hostile files, built here -----------------------------------------------------


def test_a_pipe_is_refused_not_waited_on(tmp_path):
    import os

    fifo = tmp_path / "points.xyz"
    os.mkfifo(fifo)
    with pytest.raises(DataError, match="not a regular file"):
        read_points(fifo)


def test_las_headers_that_lie_are_refused_at_once(tmp_path):
    import os

    import laspy

    (tmp_path / "noise.las").write_bytes(b"LASF" + os.urandom(500))
    with pytest.raises(DataError, match="noise.las"):
        read_points(tmp_path / "noise.las")
    header = laspy.LasHeader(point_format=3, version="1.2")
    las = laspy.LasData(header)
    las.x, las.y, las.z = np.arange(10.0), np.arange(10.0) ** 2, np.zeros(10)
    las.write(tmp_path / "ok.las")
    assert read_points(tmp_path / "ok.las").shape == (10, 3)
    raw = bytearray((tmp_path / "ok.las").read_bytes())
    raw[100:104] = (2**32 - 1).to_bytes(4, "little")  # the VLR count
    (tmp_path / "vlr.las").write_bytes(bytes(raw))
    with pytest.raises(DataError, match="4294967295 variable-length records"):
        read_points(tmp_path / "vlr.las")


@pytest.mark.parametrize("count", ["1000000000", "9223372036854775808", "-60"])
def test_gtn_count_headers_that_lie_are_refused(tmp_path, count):
    rows = "\n".join(f"{k} {k * 0.1:.3f} {np.sin(k):.3f}" for k in range(60))
    path = tmp_path / "lie.gtn"
    path.write_text(f"{count} 2 0 0\n{rows}\n")
    with pytest.raises(DataError, match="count header says .* but 60 rows follow"):
        read_points(path)


def test_endless_lines_are_refused_without_holding_them(tmp_path):
    path = tmp_path / "one.xyz"
    path.write_text("1 " * 200_000)
    with pytest.raises(DataError, match="longer than"):
        read_points(path)


def test_conf_scans_must_lie_in_its_folder_and_content_is_not_quoted(tmp_path):
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "secret.xyz").write_text("SECRET-TOKEN-beta second line of it\n1 2 3\n")
    scans = tmp_path / "scans"
    scans.mkdir()
    conf = scans / "bun.conf"
    conf.write_text("bmesh ../outside/secret.xyz 0 0 0 0 0 0 1\n")
    with pytest.raises(DataError, match="not in the .conf's folder") as err:
        read_points(conf)
    assert "SECRET" not in str(err.value)
    conf.write_text(f"bmesh {outside / 'secret.xyz'} 0 0 0 0 0 0 1\n")
    with pytest.raises(DataError, match="not in the .conf's folder"):
        read_points(conf)
    conf.write_text("bmesh bun.conf 0 0 0 0 0 0 1\n")
    with pytest.raises(DataError, match="may not name another .conf"):
        read_points(conf)
    (scans / "bad.xyz").write_text("SECRET-TOKEN-beta second line of it, and much more\n")
    conf.write_text("bmesh bad.xyz 0 0 0 0 0 0 1\n")
    with pytest.raises(DataError) as err:
        read_points(conf)
    assert "much more" not in str(err.value)


def test_coordinates_whose_distances_overflow_are_refused(tmp_path):
    path = tmp_path / "huge.xyz"
    np.savetxt(path, np.array([[0.0, 0.0, 0.0], [1e300, 1.0, 0.0], [2.0, 1e300, 0.0]]))
    with pytest.raises(DataError, match="overflow"):
        read_points(path)


def test_a_failed_write_names_the_target_and_leaves_nothing(tmp_path):
    def fail(tmp):
        raise OSError(28, "No space left on device")

    target = tmp_path / "out.geojson"
    with pytest.raises(DataError, match="out.geojson: cannot write: No space left on device"):
        with atomic_path(target) as tmp:
            fail(tmp)
    assert list(tmp_path.iterdir()) == []
    (tmp_path / "dir.geojson").mkdir()
    with pytest.raises(DataError, match="dir.geojson: is a folder"):
        with atomic_path(tmp_path / "dir.geojson"):
            pass


def test_a_gzip_bomb_is_refused_at_its_first_line(tmp_path):
    """A small .log.gz that inflates to 64 MiB of NULs: refused within the first 64 KiB."""
    import gzip
    import time

    path = tmp_path / "bomb.log.gz"
    with gzip.open(path, "wb", compresslevel=9) as fh:
        for _ in range(64):
            fh.write(b"\0" * (1 << 20))
    assert path.stat().st_size < 200_000
    t0 = time.perf_counter()
    with pytest.raises(DataError, match="longer than"):
        read_points(path)
    assert time.perf_counter() - t0 < 2.0


def test_pcd_point_counts_that_lie_are_refused(tmp_path):
    rows = "\n".join(f"{k} {k * 0.5} 0" for k in range(12))
    head = ("# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
            "WIDTH {n}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {n}\nDATA ascii\n")
    (tmp_path / "ok.pcd").write_text(head.format(n=12) + rows)
    assert read_points(tmp_path / "ok.pcd").shape == (12, 3)
    (tmp_path / "lie.pcd").write_text(head.format(n=1000000000) + rows)
    with pytest.raises(DataError, match="says 1000000000 points but 12 rows"):
        read_points(tmp_path / "lie.pcd")


@pytest.mark.parametrize("text", [
    "x,y,z\n1,2,3\n4,5,6\n7,8,9.5\n",
    "# a comment\n1 2 3  # trailing\n4 5 6\n\n7 8 9\n",
    "1\t2\n3\t4\n5\t6.25\n",
    "p 1 2 3\np 4 5 6\np 7 8 9\n",
    "3 2 0 0\n0 1.0 2.0\n1 3.0 4.0\n2 5.0 6.5\n",
])
def test_the_fast_table_reader_agrees_with_the_line_parser(tmp_path, text, monkeypatch):
    import wavepoly.io.readers as readers

    path = tmp_path / "t.txt"
    path.write_text(text)
    fast = read_points(path)
    monkeypatch.setattr(readers, "_read_table_fast", lambda *args: None)
    np.testing.assert_array_equal(fast, read_points(path))


def depth_image(h=60, w=80):
    """An organized cloud as a depth camera writes it: a grid of pixels, every 7th without a
    return (NaN), float32, quantized like a sensor (so that LZF has something to compress)."""
    yy, xx = np.mgrid[0:h, 0:w]
    z = np.round(1.5 + 0.2 * np.sin(xx / 9.0), 3)
    pts = np.column_stack([xx.ravel() * 0.01, yy.ravel() * 0.01, z.ravel()]).astype(np.float32)
    pts[::7] = np.nan
    return pts


def test_binary_compressed_pcd_of_a_known_writer_is_read_and_its_holes_dropped(tmp_path):
    pypcd4 = pytest.importorskip("pypcd4")
    pts = depth_image()
    cloud = pypcd4.PointCloud.from_xyz_points(pts)
    cloud.metadata.width, cloud.metadata.height = 80, 60
    for encoding in (pypcd4.Encoding.BINARY_COMPRESSED, pypcd4.Encoding.BINARY,
                     pypcd4.Encoding.ASCII):
        path = tmp_path / f"depth-{encoding.value}.pcd"
        cloud.save(path, encoding)
        with pytest.warns(wavepoly.ReadNote, match="686 of 4800 points have no coordinates"):
            got = read_points(path)
        keep = ~np.isnan(pts).any(axis=1)
        np.testing.assert_allclose(got, pts[keep], rtol=1e-6)
    assert b"DATA binary_compressed" in (tmp_path / "depth-binary_compressed.pcd").read_bytes()


def test_corrupt_lzf_data_is_an_error_naming_the_file(tmp_path):
    pypcd4 = pytest.importorskip("pypcd4")
    cloud = pypcd4.PointCloud.from_xyz_points(depth_image())
    path = tmp_path / "bad.pcd"
    cloud.save(path, pypcd4.Encoding.BINARY_COMPRESSED)
    raw = bytearray(path.read_bytes())
    raw[-40:] = b"\xff" * 40  # back references before the start of the output
    path.write_bytes(bytes(raw))
    with pytest.raises(DataError, match="bad.pcd: the compressed data"):
        read_points(path)


def test_lzf_decoder_matches_liblzf():
    lzf = pytest.importorskip("lzf")
    from wavepoly.io.lzf import decompress

    rng = np.random.default_rng(3)
    for size in (1, 31, 32, 300, 70_000):
        data = np.repeat(rng.integers(0, 6, size // 3 + 1, dtype=np.uint8), 3)[:size].tobytes()
        packed = lzf.compress(data) or None
        if packed is None:  # liblzf gives up when the output would not be smaller
            continue
        assert decompress(packed, len(data)) == data


def test_columns_choose_on_every_reader_that_has_columns_and_are_refused_elsewhere(tmp_path):
    from plyfile import PlyData, PlyElement

    rng = np.random.default_rng(8)
    table = rng.normal(size=(50, 4))
    vertex = np.empty(50, dtype=[("x", "<f8"), ("y", "<f8"), ("z", "<f8"), ("w", "<f8")])
    for k, name in enumerate("xyzw"):
        vertex[name] = table[:, k]
    PlyData([PlyElement.describe(vertex, "vertex")]).write(str(tmp_path / "a.ply"))
    np.testing.assert_array_equal(read_points(tmp_path / "a.ply", columns=(1, 3)),
                                  table[:, [1, 3]])
    with pytest.raises(DataError, match="asked for column 7 but the file has 4 vertex"):
        read_points(tmp_path / "a.ply", columns=(0, 7))
    (tmp_path / "a.obj").write_text("".join(f"v {x} {y} {z}\n" for x, y, z, _ in table))
    with pytest.raises(DataError, match="--columns does not apply to .obj"):
        read_points(tmp_path / "a.obj", columns=(0, 1))


def test_streamed_geojson_is_the_text_of_the_whole_collection(tmp_path):
    import json

    import wavepoly
    from wavepoly.io.writers import geojson_features, write_geojson
    from wavepoly.samples import glyph_outlines, sample_rings

    fits = [wavepoly.fit(sample_rings(glyph_outlines(g).rings, spacing=0.03, noise=0.01,
                                      seed=3), 0.08) for g in "BO"]
    write_geojson(tmp_path / "s.geojson", fits)
    whole = {"type": "FeatureCollection",
             "features": [f for r in fits for f in geojson_features(r)]}
    assert (tmp_path / "s.geojson").read_text() == json.dumps(whole)
