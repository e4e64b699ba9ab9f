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

#: The shared scans: ``WAVEPOLY_SHARED_DATA`` when set, else ``../shared/data`` beside the repo.
SHARED = Path(os.environ.get("WAVEPOLY_SHARED_DATA") or
              Path(__file__).resolve().parents[1].parent / "shared" / "data")


@pytest.fixture(scope="session")
def shared_data() -> Path:
    if not SHARED.is_dir():
        pytest.skip(f"shared data not found at {SHARED} (only on the developers' machines; "
                    "set WAVEPOLY_SHARED_DATA to point at it)")
    return SHARED


def _edge_tree(result) -> shapely.STRtree | None:
    """shapely's STRtree over every edge of the output contours (None: no contour)."""
    edges = []
    for c in result.contours:
        v = np.vstack([c.vertices, c.vertices[:1]]) if c.closed else c.vertices
        edges.append(np.stack([v[:-1], v[1:]], axis=1))
    return shapely.STRtree(shapely.linestrings(np.concatenate(edges))) if edges else None


def distance_to_output(points: np.ndarray, result) -> np.ndarray:
    """Independent check: distance of each point to the output contours, with shapely (an
    STRtree over the edges, faster than one union on a laser map)."""
    tree = _edge_tree(result)
    if tree is None:
        return np.full(len(points), np.inf)
    _, dist = tree.query_nearest(shapely.points(points), return_distance=True,
                                 all_matches=False)
    return dist


def within_output(points: np.ndarray, result, distance: float) -> np.ndarray:
    """Independent check: which points lie within ``distance`` of the output contours
    (shapely's ``dwithin`` over the edge tree; some 5 times faster than the distances)."""
    tree = _edge_tree(result)
    near = np.zeros(len(points), dtype=bool)
    if tree is not None:
        near[tree.query(shapely.points(points), predicate="dwithin", distance=distance)[0]] = True
    return near



def teeth(result, short: float = 2.0, turn: float = 135.0) -> int:
    """Vertices where the output turns back by more than ``turn`` degrees between two edges
    shorter than ``short`` tolerances: the teeth of a zigzag through a band of points. A
    contour no wider than that (a speck's ring, a chair leg's triangle) draws no band and
    has none (`benchmarks.bench_validity._teeth`)."""
    from wavepoly.geometry import turn_backs

    short *= result.tolerance
    return sum(turn_backs(c.vertices, c.closed, short, turn) for c in result.contours
               if np.ptp(c.vertices, axis=0).max() > short)


def assert_rings_drawn(rings: list[np.ndarray], pts: np.ndarray, result, eps: float) -> None:
    """The silhouette sweep's *right* (`benchmarks.bench_validity`), asserted: every contour
    closed, one per ring, no outliers, valid by wavepoly's check and the independent one,
    and every point within ε."""
    from benchmarks.bench_validity import _one_per_ring

    from .truth import independent_problems

    assert all(c.closed for c in result.contours), [c.closed for c in result.contours]
    assert _one_per_ring(rings, result.contours, eps)
    assert len(result.outliers) == 0
    assert result.validity.valid and independent_problems(result) == []
    assert distance_to_output(pts, result).max() <= eps * (1 + 1e-9)
