"""Built-in test shapes: glyph outlines from matplotlib's bundled DejaVu Sans, sampled like a scan.

Glyphs are real outlines with sharp corners, arcs and holes, and they come with an installed
dependency, so the demo and the tests need no data files.

>>> shape = glyph_outlines("B", height=20.0)
>>> len(shape.rings), [bool(c) for c in shape.closed]     # outline and two holes
(3, [True, True, True])
>>> pts = sample_rings(shape.rings, spacing=0.02, noise=0.01, seed=1)
>>> pts.shape[1]
2
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .types import FloatArray


@dataclass(frozen=True)
class TrueShape:
    """Known curves: ``rings[k]`` is a (m, 2) polyline, closed (last vertex != first) or open."""

    rings: list[FloatArray]
    closed: list[bool]

    def corners(self, min_turn_deg: float = 35.0) -> FloatArray:
        """Vertices where a ring turns by more than ``min_turn_deg`` degrees."""
        out = []
        for ring, closed in zip(self.rings, self.closed):
            prev = np.roll(ring, 1, axis=0) - ring
            nxt = np.roll(ring, -1, axis=0) - ring
            cos = np.einsum("ij,ij->i", prev, nxt) / (
                np.linalg.norm(prev, axis=1) * np.linalg.norm(nxt, axis=1))
            turn = 180.0 - np.degrees(np.arccos(np.clip(cos, -1, 1)))
            mask = turn > min_turn_deg
            if not closed:
                mask[[0, -1]] = False
            out.append(ring[mask])
        return np.concatenate(out) if out else np.empty((0, 2))


def glyph_outlines(text: str = "B8", *, height: float = 20.0, family: str = "DejaVu Sans"
                   ) -> TrueShape:
    """Closed outlines of ``text`` in ``family``; a capital is about ``height`` units high.

    Bezier arcs are flattened finely by matplotlib, so the rings are true to the glyph within
    about height / 2000.
    """
    from matplotlib.font_manager import FontProperties
    from matplotlib.textpath import TextPath

    zoom = 200.0  # matplotlib flattens Beziers to about 0.1 unit: flatten large, then scale
    path = TextPath((0.0, 0.0), text, size=zoom * height / 0.73,
                    prop=FontProperties(family=family))
    rings = []
    for poly in path.to_polygons(closed_only=True):
        ring = _drop_repeats(np.asarray(poly, dtype=float) / zoom)
        if len(ring) >= 3:
            rings.append(ring)
    return TrueShape(rings, [True] * len(rings))


def _drop_repeats(ring: FloatArray) -> FloatArray:
    if np.allclose(ring[0], ring[-1]):
        ring = ring[:-1]
    step = np.linalg.norm(np.diff(ring, axis=0, append=ring[:1]), axis=1)
    return ring[step > 1e-12]


def sample_rings(rings: list[FloatArray], *, spacing: float, noise: float = 0.0,
                 closed: list[bool] | None = None, density_ratio: float = 1.0, seed: int = 0
                 ) -> FloatArray:
    """Scan-like samples of polylines: random positions along each ring, Gaussian noise, shuffled.

    spacing : mean distance between samples along the curve (units of the rings).
    noise : standard deviation of the isotropic Gaussian noise added to each sample.
    density_ratio : the density varies smoothly along each ring by up to this factor.
    """
    rng = np.random.default_rng(seed)
    closed = closed or [True] * len(rings)
    out = []
    for ring, is_closed in zip(rings, closed):
        verts = np.vstack([ring, ring[:1]]) if is_closed else ring
        seg = np.linalg.norm(np.diff(verts, axis=0), axis=1)
        cum = np.concatenate([[0.0], np.cumsum(seg)])
        n = max(int(cum[-1] / spacing), 3)
        grid = np.linspace(0.0, 1.0, 2049)
        density = 1.0 + (density_ratio - 1.0) * 0.5 * (1.0 + np.sin(2 * np.pi * grid))
        cdf = np.concatenate([[0.0], np.cumsum(0.5 * (density[1:] + density[:-1]))])
        u = np.interp(rng.uniform(0.0, cdf[-1], n), cdf, grid)  # inverse-CDF sampling
        s = u * cum[-1]
        pts = np.column_stack([np.interp(s, cum, verts[:, 0]), np.interp(s, cum, verts[:, 1])])
        out.append(pts + rng.normal(0.0, noise, pts.shape) if noise > 0 else pts)
    pts = np.concatenate(out)
    return pts[rng.permutation(len(pts))]


def scattered_ellipses(count: int, *, across: tuple[float, float], clearance: float,
                       box: float, seed: int = 0) -> list[FloatArray]:
    """Outlines of ``count`` ellipses ``across`` (smallest, largest) wide, their short axes
    0.6-1 x as long, turned at random and placed at random in a ``box``-wide square, each at
    least ``clearance`` from every other: small shapes a few tolerances apart, as stars in a
    photograph or rivets in a slice.

    >>> rings = scattered_ellipses(5, across=(1.0, 3.0), clearance=2.0, box=30.0)
    >>> len(rings), rings[0].shape
    (5, (64, 2))
    """
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 2 * np.pi, 64, endpoint=False)
    placed: list[tuple[FloatArray, float]] = []
    rings = []
    for _ in range(1000 * count):  # rejection sampling: a crowded box gives up
        if len(rings) == count:
            break
        size, centre = rng.uniform(*across), rng.uniform(0.0, box, 2)
        if any(np.hypot(*(centre - c)) < (size + s) / 2 + clearance for c, s in placed):
            continue
        turn, squash = rng.uniform(0.0, np.pi), rng.uniform(0.6, 1.0)
        ellipse = 0.5 * size * np.column_stack([np.cos(t), squash * np.sin(t)])
        rotation = np.array([[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]])
        placed.append((centre, size))
        rings.append(centre + ellipse @ rotation.T)
    if len(rings) < count:
        raise ValueError(f"only {len(rings)} of {count} ellipses fit in the box")
    return rings
