"""The records fit the user's toolbox: GeoJSON geometry for shapely / GeoPandas, short reprs."""

from __future__ import annotations

import json

import numpy as np
import shapely
import shapely.geometry

import wavepoly
from wavepoly.samples import glyph_outlines, sample_rings
from wavepoly.staircase import region


def glyph_fit(letter="B"):
    pts = sample_rings(glyph_outlines(letter).rings, spacing=0.02, noise=0.01, seed=0)
    return wavepoly.fit(pts, 0.08)


def test_a_fit_is_a_valid_multipolygon_with_its_holes():
    result = glyph_fit("B")
    geom = shapely.geometry.shape(result)
    assert geom.geom_type == "MultiPolygon" and geom.is_valid
    assert sum(len(p.interiors) for p in geom.geoms) == 2
    assert abs(geom.area - region(result.contours).area) < 1e-9
    assert result.to_shapely().equals(geom)
    json.dumps(result.__geo_interface__)  # plain GeoJSON: numbers and lists only


def test_open_contours_are_lines_and_mixed_results_a_collection():
    t = np.linspace(0, 3, 400)
    arc = np.column_stack([t, np.sin(t)])
    ring = np.column_stack([8 + np.cos(2 * np.pi * t / 3), np.sin(2 * np.pi * t / 3)])
    result = wavepoly.fit(np.vstack([arc, ring]), 0.02)
    geom = result.to_shapely()
    assert geom.geom_type == "GeometryCollection"
    kinds = sorted(g.geom_type for g in geom.geoms)
    assert kinds == ["MultiLineString", "MultiPolygon"]
    for c in result.contours:
        assert c.to_shapely().geom_type == ("Polygon" if c.closed else "LineString")


def test_layers_are_features_with_their_heights_and_a_model_a_collection():
    rng = np.random.default_rng(0)
    t, h = rng.uniform(0, 2 * np.pi, 20000), rng.uniform(0, 10, 20000)
    res = wavepoly.slice_cloud(np.column_stack([5 * np.cos(t), 5 * np.sin(t), h]), 0.1,
                               layer_thickness=2.0, workers=1)
    doc = res.__geo_interface__
    assert doc["type"] == "FeatureCollection" and len(doc["features"]) == len(res.layers)
    feature = res.layers[1].__geo_interface__
    assert feature["properties"]["z"] == res.layers[1].z
    disc = shapely.geometry.shape(feature)
    assert disc.is_valid and abs(disc.area - np.pi * 25) < 2 * np.pi * 5 * 0.1  # ring x ε
    assert [g.geom_type for g in res.to_shapely()] == ["MultiPolygon"] * len(res.layers)


def test_reprs_are_one_short_line():
    result = glyph_fit("O")
    for obj in (result, result.contours[0]):
        text = repr(obj)
        assert "\n" not in text and len(text) < 200 and "array" not in text
    assert "all valid" in repr(result)
