"""`wavepoly demo`: built-in data in, polygons, report and figures out, within the tolerance."""

from __future__ import annotations

import json

import shapely

from wavepoly.demo import DEMO_TOLERANCE, demo_points, run_demo


def test_demo_writes_everything_within_the_tolerance(tmp_path):
    lines = []
    run_demo(tmp_path, echo=lines.append)
    names = {p.name for p in tmp_path.iterdir()}
    assert names == {"input-points.xy", "polygons.svg", "polygons.geojson", "polygons.dxf",
                     "report.json", "fit.png", "ordering.png", "levels.png", "mscs.png"}
    report = json.loads((tmp_path / "report.json").read_text())
    assert report["max_error"] <= DEMO_TOLERANCE * (1 + 1e-9)
    assert report["outliers"] == 0 and len(report["contours"]) == 9
    doc = json.loads((tmp_path / "polygons.geojson").read_text())
    for feature in doc["features"]:
        assert shapely.geometry.shape(feature["geometry"]).is_valid
    assert lines[-1].startswith("wrote ")
    assert len(demo_points()) == report["points"]
