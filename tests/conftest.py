"""Shared fixtures: the real data in ../shared/data (skipped cleanly when absent)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
import shapely
from hypothesis import settings

# CI runs the same examples every time (a red run must be reproducible); set
# WAVEPOLY_HYPOTHESIS=explore to search fresh random examples locally.
settings.register_profile("ci", derandomize=True, deadline=None, print_blob=True)
settings.register_profile("explore", derandomize=False, deadline=None, print_blob=True)
settings.load_profile(os.environ.get("WAVEPOLY_HYPOTHESIS", "ci"))

SHARED = Path(__file__).resolve().parents[1].parent / "shared" / "data"


@pytest.fixture(scope="session")
def shared_data() -> Path:
    if not SHARED.is_dir():
        pytest.skip(f"shared data not found at {SHARED} (only on the developers' machines)")
    return SHARED


def distance_to_output(points: np.ndarray, result) -> np.ndarray:
    """Independent check: distance of each point to the output contours, with shapely."""
    geoms = [shapely.linearrings(c.vertices) if c.closed else shapely.linestrings(c.vertices)
             for c in result.contours]
    union = shapely.union_all(geoms)
    return shapely.distance(shapely.points(points), union)


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
