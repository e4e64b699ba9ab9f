"""CARMEN laser logs (``.log``, ``.clf``, gzipped or not): each scan's returns placed in the
world by the laser's pose, as the SLAM data sets of the Radish repository give them.

Two kinds of line carry a scan with its pose:

``FLASER n r1 .. rn x y theta odom_x odom_y odom_theta ...``
    the front laser of the older logs: n beams spread over 180 degrees, -90 .. +90 about the
    heading ``theta`` of the (corrected) pose ``x y``;
``ROBOTLASER1 type start fov resolution max_range accuracy mode n r1 .. rn m e1 .. em
lx ly ltheta rx ry rtheta ...``
    the newer logs: beam i at ``ltheta + start + i * resolution`` from the laser's own pose
    ``lx ly``, any field of view (a 270 degree scanner's too), its maximum range said per line.

A log holding both kinds (a converted log keeps its old lines beside the new) is read from its
ROBOTLASER1 lines alone: they say the field of view and the range limit, and reading both
would place every scan twice. Returns at the range limit or within 1 % of it (for FLASER, the
largest range in the log: the sensor's maximum) and non-positive ones are no-returns and are
dropped.

References
----------
.. [1] M. Montemerlo, N. Roy, S. Thrun, "Perspectives on standardization in mobile robot
   programming: the Carnegie Mellon Navigation (CARMEN) toolkit", IROS 2003.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import DataError
from .text import bounded_lines, is_number, no_columns, open_text, snippet

#: Extensions of CARMEN logs (`wavepoly.io.readers.detect_format`).
CARMEN_SUFFIXES = (".log", ".log.gz", ".clf", ".clf.gz")
#: FLASER beams span this field of view (radians): the SICK front laser of the older logs.
FLASER_FOV = np.pi
#: A return within this share of the range limit is a no-return, not a wall: loggers write
#: the sensor's maximum for a beam that saw nothing, and a dazzled beam a hair below it (a log
#: whose no-returns read 81.83 and 81.82 would otherwise draw an arc of points 80 m out).
NO_RETURN_SHARE = 0.99
#: Fields of a ROBOTLASER1 line before its readings (the kind, type, start angle, field of
#: view, resolution, maximum range, accuracy, remission mode, count).
_ROBOTLASER_HEAD = 9


@dataclass
class _Scan:
    """One scan: beam angles about the laser's heading, ranges, range limit, pose (x y theta)."""

    angles: np.ndarray
    ranges: np.ndarray
    limit: float
    pose: np.ndarray


def read_carmen(path: Path, fmt: str, columns: tuple[int, ...] | None) -> np.ndarray:
    """The world points of every scan of a CARMEN log (module docstring): (N, 2) float64.

    Raises `DataError` naming the file (and the line, for a line that does not hold the
    readings and the pose its count promises) when the log has no scan with a pose.
    """
    no_columns(path, fmt, columns, "laser beams turned into points by their poses")
    front, robot = [], []
    with open_text(path) as fh:
        for lineno, line in enumerate(bounded_lines(fh, path), 1):
            if line.startswith("FLASER "):
                front.append(_flaser(line.split(), path, lineno))
            elif line.startswith("ROBOTLASER1 "):
                robot.append(_robotlaser(line.split(), path, lineno))
    scans = robot or front
    if not scans:
        raise DataError(f"{path}: CARMEN log has no FLASER or ROBOTLASER1 lines")
    if not robot:  # FLASER says no range limit: the largest reading is the sensor's maximum
        limit = max(float(s.ranges.max(initial=0.0)) for s in scans)
        for s in scans:
            s.limit = limit
    return np.concatenate([_world_points(s) for s in scans])


def _world_points(scan: _Scan) -> np.ndarray:
    x, y, theta = scan.pose
    keep = (scan.ranges > 0) & (scan.ranges < NO_RETURN_SHARE * scan.limit)
    angle, r = theta + scan.angles[keep], scan.ranges[keep]
    return np.column_stack([x + r * np.cos(angle), y + r * np.sin(angle)])


def _flaser(tokens: list[str], path: Path, lineno: int) -> _Scan:
    n = _count(tokens, 1, 3, path, lineno)
    ranges = _numbers(tokens[2:2 + n], path, lineno)
    pose = _numbers(tokens[2 + n:5 + n], path, lineno)
    angles = np.linspace(-FLASER_FOV / 2, FLASER_FOV / 2, n)
    return _Scan(angles, ranges, np.inf, pose)


def _robotlaser(tokens: list[str], path: Path, lineno: int) -> _Scan:
    n = _count(tokens, _ROBOTLASER_HEAD - 1, 1, path, lineno)
    start, _fov, resolution, limit = _numbers(tokens[2:6], path, lineno)
    first = _ROBOTLASER_HEAD
    ranges = _numbers(tokens[first:first + n], path, lineno)
    m = _count(tokens, first + n, 3, path, lineno)  # remissions, then the laser's pose
    pose = _numbers(tokens[first + n + 1 + m:first + n + 4 + m], path, lineno)
    return _Scan(start + resolution * np.arange(n), ranges, limit, pose)


def _count(tokens: list[str], at: int, after: int, path: Path, lineno: int) -> int:
    """The count at ``tokens[at]``, checked to leave that many values and ``after`` more."""
    kind = tokens[0]
    try:
        n = int(tokens[at])
    except (IndexError, ValueError):
        raise DataError(f"{path}: line {lineno}: {kind} has no reading count") from None
    if n < 0 or len(tokens) < at + 1 + n + after:
        raise DataError(f"{path}: line {lineno}: {kind} says {n} values, but the line is too "
                        "short to hold them and the pose")
    return n


def _numbers(tokens: list[str], path: Path, lineno: int) -> np.ndarray:
    try:
        values = np.array(tokens, dtype=np.float64)
    except ValueError:
        bad = next(t for t in tokens if not is_number(t))
        raise DataError(f"{path}: line {lineno}: {snippet(bad)} is not a number") from None
    if not np.isfinite(values).all():
        raise DataError(f"{path}: line {lineno}: a reading or the pose is not finite")
    return values
