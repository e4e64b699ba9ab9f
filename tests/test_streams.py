"""wavepoly in a shell pipe and in Python streams: file objects in and out, '-' for stdio,
and units that are never wrong."""

from __future__ import annotations

import io
import json
import subprocess
import sys

import ezdxf
import numpy as np
import pytest
import shapely

import wavepoly
from wavepoly.errors import DataError, ParameterError
from wavepoly.samples import glyph_outlines, sample_rings


@pytest.fixture(scope="module")
def points():
    return sample_rings(glyph_outlines("B").rings, spacing=0.03, noise=0.01, seed=2)


@pytest.fixture(scope="module")
def result(points):
    return wavepoly.fit(points, 0.08)


def test_points_are_read_from_binary_and_text_file_objects(points, tmp_path):
    text = "\n".join(f"{x!r} {y!r}" for x, y in points.tolist())
    for stream in (io.BytesIO(text.encode()), io.StringIO(text)):
        np.testing.assert_array_equal(wavepoly.read_points(stream, format="xy"), points)
    np.save(tmp_path / "p.npy", points)
    with open(tmp_path / "p.npy", "rb") as fh:
        np.testing.assert_array_equal(wavepoly.read_points(fh, format="npy"), points)


def test_a_file_object_needs_its_format_and_errors_name_it():
    with pytest.raises(ParameterError, match="needs its format"):
        wavepoly.read_points(io.BytesIO(b"0 0\n1 1\n"))
    stream = io.BytesIO(b"0 0\n1 nan\n2 2\n")
    stream.name = "scan-from-camera"
    with pytest.raises(DataError, match="^scan-from-camera: 1 point"):
        wavepoly.read_points(stream, format="xy")


@pytest.mark.parametrize("fmt", ["geojson", "svg", "csv", "dxf"])
def test_polygons_go_to_text_and_binary_file_objects(result, tmp_path, fmt):
    wavepoly.write_polygons(tmp_path / f"ref.{fmt}", result)
    reference = (tmp_path / f"ref.{fmt}").read_bytes()
    binary, text = io.BytesIO(), io.StringIO()
    wavepoly.write_polygons(binary, result, fmt)
    wavepoly.write_polygons(text, result, format=fmt)
    if fmt != "dxf":  # a DXF carries the time of its writing
        assert binary.getvalue() == reference
        assert text.getvalue() == reference.decode()
    assert binary.getvalue() and text.getvalue()


def test_geojson_follows_rfc_7946_and_shapely_reads_it_back(result):
    doc = json.loads(_geojson(result))
    assert "crs" not in doc and doc["type"] == "FeatureCollection"
    shapes = [shapely.geometry.shape(f["geometry"]) for f in doc["features"]]
    assert all(s.is_valid for s in shapes)
    assert abs(sum(s.area for s in shapes) - result.to_shapely().area) < 1e-9


def _geojson(result) -> str:
    out = io.StringIO()
    wavepoly.write_polygons(out, result, "geojson")
    return out.getvalue()


def test_dxf_and_svg_claim_only_the_unit_given(result, tmp_path):
    wavepoly.write_polygons(tmp_path / "a.dxf", result)
    assert ezdxf.readfile(tmp_path / "a.dxf").header["$INSUNITS"] == 0  # unitless
    for name, code in (("mm", 4), ("cm", 5), ("m", 6), ("in", 1)):
        wavepoly.write_polygons(tmp_path / f"{name}.dxf", result, units=name)
        assert ezdxf.readfile(tmp_path / f"{name}.dxf").header["$INSUNITS"] == code
    wavepoly.write_polygons(tmp_path / "a.svg", result, units="mm")
    head = (tmp_path / "a.svg").read_text().splitlines()[0]
    view = [float(v) for v in head.split('viewBox="')[1].split('"')[0].split()]
    assert f'width="{view[2]:.6g}mm"' in head
    with pytest.raises(ParameterError, match="units must be one of"):
        wavepoly.write_polygons(tmp_path / "b.dxf", result, units="furlong")


def _wavepoly(*args, stdin=None):
    return subprocess.run([sys.executable, "-m", "wavepoly", *map(str, args)], input=stdin,
                          capture_output=True, timeout=300)


def test_the_command_sits_in_a_pipe(points, result):
    text = "\n".join(f"{x!r} {y!r}" for x, y in points.tolist()).encode()
    out = _wavepoly("fit", "-", "--format", "xy", "-t", "0.08", "-o", "-",
                    "--output-format", "geojson", stdin=text)
    assert out.returncode == 0, out.stderr
    assert out.stdout.decode() == _geojson(result)  # only the polygons on standard output
    assert b"wrote standard output" in out.stderr


def test_stdio_needs_its_formats():
    out = _wavepoly("fit", "-", "-t", "0.08", "-o", "x.geojson", stdin=b"0 0\n")
    assert out.returncode == 2 and b"needs --format" in out.stderr
    out = _wavepoly("info", "-", "-o", "-", stdin=b"0 0\n")
    assert out.returncode == 2
    out = _wavepoly("fit", "-", "--format", "xy", "-t", "0.08", "-o", "-", stdin=b"0 0\n")
    assert out.returncode == 2 and b"--output-format" in out.stderr


def test_georeferenced_results_go_to_a_geopackage_in_their_crs(points, tmp_path):
    raw = pytest.importorskip("pyogrio.raw")
    shifted = points + [500_000.0, 5_700_000.0]  # UTM-like coordinates
    result = wavepoly.fit(shifted, 0.08)
    wavepoly.write_polygons(tmp_path / "b.gpkg", result, crs="EPSG:25832")
    meta, _, wkb, fields = raw.read(tmp_path / "b.gpkg")
    assert meta["crs"] == "EPSG:25832" and [p.name for p in tmp_path.iterdir()] == ["b.gpkg"]
    shapes = shapely.from_wkb(wkb)
    assert all(s.is_valid for s in shapes)
    assert abs(sum(s.area for s in shapes) - result.to_shapely().area) < 1e-6
    with pytest.raises(ParameterError, match="GeoPackage"):
        wavepoly.write_polygons(tmp_path / "b.geojson", result, crs="EPSG:25832")
    with pytest.raises(ParameterError, match="EPSG:NNNN"):
        wavepoly.write_polygons(tmp_path / "c.gpkg", result, crs="UTM 32")
