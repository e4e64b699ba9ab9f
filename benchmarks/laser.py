"""Made-up laser maps: a floor of rooms off a corridor, scanned by a robot driving through it.

The two laser maps in shared/ (Intel, Freiburg) are what the ordering was tuned on; these are
others of the same kind whose truth is known: walls with a thickness (a room's wall and the next
room's 0.12-0.25 m apart), doors, desks and cabinets, pillars and chair legs, people walking
by. The robot drives along the corridor and into each room, and at every pose a 180-degree
scanner measures the range to the first surface along each beam, with range noise and the
small error of the pose that scan matching leaves (a wall seen from many poses comes out as a
band a few centimetres wide).
"""

from __future__ import annotations

import numpy as np
import shapely
from shapely import affinity

#: Beams per scan over the scanner's 180 degrees, and its range (m).
BEAMS = 181
MAX_RANGE = 8.0
#: A long-range scanner (m, beams over 180 degrees): at 30 m the heading error alone moves a
#: return 0.16 m, so a far wall comes out as a sparse band as wide as a thin wall.
FAR_RANGE = 30.0
FAR_BEAMS = 361
#: Range noise (m), and the pose error scan matching leaves (m, degrees).
RANGE_NOISE = 0.01
POSE_NOISE = 0.02
HEADING_NOISE = 0.3
#: Robot poses this far apart (m) along its path.
STEP = 0.25
#: Share of scans that see a person (two legs) standing near the robot.
PEOPLE = 0.15


def floor(seed: int) -> tuple[shapely.Geometry, np.ndarray]:
    """The free space of floor ``seed`` (where the robot can be, furniture cut out) and the
    robot's path through it (corridor and every room, there and back)."""
    rng = np.random.default_rng(seed)
    length, corridor = rng.uniform(20, 36), rng.uniform(1.6, 2.6)
    depth = [rng.uniform(3.5, 6.0), rng.uniform(3.5, 6.0)]  # rooms below, above
    y0 = 0.0
    free = [shapely.box(0, y0, length, y0 + corridor)]
    path = [np.array([0.6, corridor / 2])]
    furniture = []
    for side in (0, 1):
        x = 0.0
        while x < length - 2.5:
            width = min(rng.uniform(2.5, 6.0), length - x)
            wall = rng.uniform(0.12, 0.25)  # half on either side
            lo, hi = x + wall / 2, x + width - wall / 2
            outer = rng.uniform(0.15, 0.3)
            y_lo, y_hi = ((-depth[0], -outer) if side == 0 else
                          (corridor + outer, corridor + depth[1]))
            free.append(shapely.box(lo, y_lo, hi, y_hi))
            door = rng.uniform(lo + 0.2, hi - 1.1)
            free.append(shapely.box(door, y_hi - 0.01, door + 0.9, corridor / 2) if side == 0
                        else shapely.box(door, corridor / 2, door + 0.9, y_lo + 0.01))
            furniture += _furnish(rng, lo, y_lo, hi, y_hi, door, side)
            centre = np.array([(lo + hi) / 2, (y_lo + y_hi) / 2])
            gate = np.array([door + 0.45, corridor / 2])
            inside = np.array([door + 0.45, (y_hi - 0.6) if side == 0 else (y_lo + 0.6)])
            path += [gate, inside, centre, inside, gate]
            x += width
    path.append(np.array([length - 0.6, corridor / 2]))
    for _ in range(rng.integers(1, 4)):  # pillars in the corridor's walls
        furniture.append(shapely.Point(rng.uniform(1, length - 1), rng.choice([0.0, corridor]))
                         .buffer(rng.uniform(0.15, 0.3), 16))
    space = shapely.unary_union(free).difference(shapely.unary_union(furniture))
    path = np.array(path)
    return space, _walk(path, space)


def _furnish(rng, lo, y_lo, hi, y_hi, door, side) -> list[shapely.Geometry]:
    """Desks and cabinets against a room's walls, a table with chair legs in its middle."""
    items = []
    for _ in range(rng.integers(0, 4)):
        w, d = rng.uniform(0.6, 1.8), rng.uniform(0.4, 0.8)
        x = rng.uniform(lo, max(lo, hi - w))
        if abs(x + w / 2 - (door + 0.45)) < w / 2 + 0.9:
            continue  # keep the door clear
        far = y_lo if side == 0 else y_hi - d
        items.append(shapely.box(x, far, x + w, far + d))
    if rng.uniform() < 0.6 and hi - lo > 3.0:
        cx, cy = (lo + hi) / 2 + rng.uniform(-0.5, 0.5), (y_lo + y_hi) / 2 + rng.uniform(-0.3, 0.3)
        items.append(affinity.rotate(shapely.box(cx - 0.6, cy - 0.4, cx + 0.6, cy + 0.4),
                                     rng.uniform(0, 90)))
        for dx, dy in ((-0.9, 0), (0.9, 0), (0, -0.7), (0, 0.7)):
            items.append(shapely.Point(cx + dx, cy + dy).buffer(0.025, 8))
    return items


def _walk(path: np.ndarray, space: shapely.Geometry) -> np.ndarray:
    """Poses (x, y, heading) every `STEP` along the path, kept where they are in free space."""
    poses = []
    for a, b in zip(path[:-1], path[1:]):
        n = max(1, int(np.linalg.norm(b - a) / STEP))
        heading = np.arctan2(*(b - a)[::-1])
        t = np.arange(n)[:, None] / n
        xy = a + t * (b - a)
        poses.append(np.column_stack([xy, np.full(n, heading)]))
    poses = np.vstack(poses)
    inside = shapely.contains_xy(space.buffer(-0.2), poses[:, 0], poses[:, 1])
    return poses[inside]


def scan(space: shapely.Geometry, poses: np.ndarray, seed: int, max_range: float = MAX_RANGE,
         beams: int = BEAMS) -> np.ndarray:
    """The laser hits from every pose: the first surface along each of ``beams`` beams over
    180 degrees, within ``max_range``."""
    rng = np.random.default_rng(seed)
    a, b = _segments(space)
    hits = []
    for x, y, heading in poses:
        people = _people(rng, space, x, y) if rng.uniform() < PEOPLE else None
        pa, pb = (a, b) if people is None else (np.vstack([a, people[0]]),
                                                np.vstack([b, people[1]]))
        angles = heading + np.radians(np.linspace(-90, 90, beams))
        d = np.column_stack([np.cos(angles), np.sin(angles)])
        r = _first_hit(np.array([x, y]), d, pa, pb)
        r = r + rng.normal(0, RANGE_NOISE, len(r))
        ok = r < max_range
        # what the map shows: the hits placed from the pose scan matching estimated
        ex, ey = x + rng.normal(0, POSE_NOISE), y + rng.normal(0, POSE_NOISE)
        eh = angles[ok] + np.radians(rng.normal(0, HEADING_NOISE))
        hits.append(np.column_stack([ex + r[ok] * np.cos(eh), ey + r[ok] * np.sin(eh)]))
    return np.vstack(hits)


def _people(rng, space, x, y):
    """Two legs of a person standing 1-3 m from the robot, as segments (or None)."""
    at = np.array([x, y]) + rng.uniform(1, 3) * np.array(
        [np.cos(t := rng.uniform(0, 2 * np.pi)), np.sin(t)])
    if not shapely.contains_xy(space.buffer(-0.3), *at):
        return None
    legs = shapely.union_all([shapely.Point(at + [dx, 0]).buffer(0.07, 8)
                              for dx in (-0.12, 0.12)])
    return _segments(legs)


def _segments(geom: shapely.Geometry) -> tuple[np.ndarray, np.ndarray]:
    """Start and end points of every edge of the geometry's boundary."""
    lines = shapely.get_parts(shapely.boundary(geom))
    a, b = [], []
    for line in lines:
        c = np.asarray(line.coords)
        a.append(c[:-1])
        b.append(c[1:])
    return np.vstack(a), np.vstack(b)


def _first_hit(origin: np.ndarray, directions: np.ndarray, a: np.ndarray, b: np.ndarray
               ) -> np.ndarray:
    """Range along each direction from ``origin`` to the nearest segment a-b (inf: none)."""
    ex, ey = (b - a).T[:, None, :]               # (1, S) each
    wx, wy = (a - origin).T[:, None, :]
    dx, dy = directions.T[:, :, None]            # (B, 1) each
    denom = dx * ey - dy * ex
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (wx * ey - wy * ex) / denom
        u = (wx * dy - wy * dx) / denom
    hit = (np.abs(denom) > 1e-12) & (t > 0) & (u >= 0) & (u <= 1)
    return np.where(hit, t, np.inf).min(axis=1)


def laser_map(seed: int, max_range: float = MAX_RANGE, beams: int = BEAMS
              ) -> tuple[np.ndarray, shapely.Geometry]:
    """The points of made-up laser map ``seed`` and the true surfaces (the free space's
    boundary) they were measured from, by a scanner of ``beams`` beams reaching
    ``max_range`` (`FAR_RANGE`, `FAR_BEAMS`: the far walls' returns sparse, and spread by
    the heading error over a band as wide as a thin wall)."""
    space, poses = floor(seed)
    return scan(space, poses, seed, max_range, beams), shapely.boundary(space)
