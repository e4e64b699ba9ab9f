"""Flat faces across the slicing axis, where adaptive layers end.

A face perpendicular to the axis (the top of a part's root, a step, a shelf) is a jump in the
cross-section: below it the section is the wide part, above it the narrow one. A layer whose
slab holds such a face has no one section to draw. Its mid-plane lies in the band of the face's
noisy points, where the section points of the steep walls beside it mix with those of the face.
Its staircase error is also large wherever the face is not on a layer boundary.

So adaptive layers end on the faces, as layer-based models for rapid prototyping do: a face
is then the top of one layer and the bottom of the next, and neither mid-plane lies in it.
Uniform layers keep the thickness they were asked for; where a face falls so near a
uniform layer's mid-plane that the plane lies in its noisy points, the layer's section is
taken in the middle of its larger part beside the face instead (`section_height`).

The faces are found from the cloud's own surface normals (`wavepoly.sections.surface_samples`).
The points whose normal lies within `FACE_TILT` of the axis are sorted by height and split
where consecutive heights are more than `FACE_GAP` tolerances apart. A group is a face when
it is thin (its middle half within `FACE_SPREAD` tolerances), flat in shape (`FACE_SLOPE`:
not the top of a dome), wide (`FACE_WIDTH`) and holds `FACE_SHARE` of the cloud. A face at
the cloud's bottom or top (`FACE_CLEARANCE`) is where the stack starts or stops
(`stack_ends`), not the lowest or highest noisy point.

References
----------
.. [1] Dolenc, A. & Mäkelä, I. (1994). Slicing procedures for layered manufacturing
   techniques. Computer-Aided Design 26(2), 119-126: flat areas are reproduced exactly when a
   layer boundary lies on them.
"""

from __future__ import annotations

import numpy as np

from .sections import quadric_fit, quadric_terms
from .types import FloatArray, SurfaceSamples

#: A point is on a face across the axis when its normal is within this many degrees of the
#: axis (the turbine blade's root faces, sampled with noise 1/1000 of the diagonal, have 14 %
#: of its points within it).
FACE_TILT = 10.0
#: Heights of one face's points are more than this many tolerances apart nowhere: a face's
#: noise (a fifth of the tolerance in the slicing benchmark) leaves gaps far smaller among
#: thousands of points. Two faces one tolerance apart stay two faces.
FACE_GAP = 0.5
#: A face's middle half spans at most this many tolerances of height (its interquartile
#: range; Gaussian noise of a fifth of the tolerance gives 0.27, the turbine blade's faces,
#: with a fillet along one, 0.28-0.47): a gently sloping back has flat normals over a wider
#: range of heights, and no one height to end a layer on.
FACE_SPREAD = 1.0
#: A face within this many tolerances of the cloud's lowest or highest point is the part's
#: bottom or top (a cap): only its own noise lies beyond it, up to 0.9 tolerances on the
#: turbine blade, and a layer there would hold that noise alone.
FACE_CLEARANCE = 2.0
#: A layer next to a face keeps its mid-plane this many standard deviations of the face's
#: heights (its interquartile range / 1.349) from it: there the face's own noisy points thin
#: out (0.3 % of a Gaussian lies beyond 3 sigma), and the section is that of the walls beside
#: it. At the thinnest adaptive layer of the slicing benchmark (two thirds of a tolerance)
#: the mid-plane lay 1.7 sigma from the face and took the face's points for a section.
FACE_SIGMAS = 3.0
#: A face's own shape (a quadratic in the plane coordinates fitted to its heights, between
#: its 5th and 95th percentile) rises at most this share of its width (0.7 degrees): the
#: turbine blade's faces 0.002-0.009, a fillet along one of them; the top of a dome, whose
#: normals lie within `FACE_TILT` of the axis, 0.034 at any size (a sphere with no noise, its
#: heights' interquartile range passing `FACE_SPREAD`), the bunny's back 0.03-0.06 and its
#: uneven base 0.013-0.02. A layer ended there would cut a curved surface, not a face.
FACE_SLOPE = 0.012
#: A face is at least this many tolerances across (the middle 90 % of its points each way):
#: the turbine blade's faces are 57-100 across; the tip of a small bump, whose few normals
#: along the axis lie on a disk a third of its radius across, is no face to end a layer on.
FACE_WIDTH = 10.0
#: A uniform layer's part beside a face holds at least this share of its points beyond the
#: face's noise (`section_height`), or it is no part of the object: beyond a cap only the
#: cap's noise lies there, 0.3 % of a Gaussian's points beyond 3 standard deviations.
PART_SHARE = 0.01
#: A Gaussian's interquartile range in standard deviations.
IQR_SIGMAS = 1.349
#: A face holds at least this share of the cloud's points: the turbine blade's root faces
#: hold 2.6 % and 7.5 %, its top 0.6 %; a few flat normals on a curved surface are no face.
FACE_SHARE = 0.002


def flat_faces(surface: SurfaceSamples, tolerance: float) -> tuple[FloatArray, FloatArray]:
    """Heights of the flat faces across the axis, sorted, and the thickness of a layer next
    to each that keeps its mid-plane clear of the face's noise (`FACE_SIGMAS`).

    Parameters
    ----------
    surface : the cloud's surface samples (its height is ``surface.uvh[:, 2]``).
    tolerance : the slicing tolerance, the scale of the face's noise.

    Returns
    -------
    heights : the median height of each face's points.
    clear : twice `FACE_SIGMAS` standard deviations of each face's heights.

    Examples
    --------
    >>> import numpy as np
    >>> from wavepoly.sections import surface_samples
    >>> rng = np.random.default_rng(0)
    >>> t = rng.uniform(0, 2 * np.pi, 16000)
    >>> tube = np.column_stack([np.cos(t), np.sin(t), rng.uniform(0, 2, 16000)])
    >>> shelf = np.column_stack([rng.uniform(-0.7, 0.7, (4000, 2)), np.full(4000, 1.0)])
    >>> uvh = np.vstack([tube, shelf, shelf + [0, 0, 1]])  # a shelf, and a lid (a cap)
    >>> faces, clear = flat_faces(surface_samples(uvh[np.argsort(uvh[:, 2])]), 0.05)
    >>> faces.round(3).tolist(), clear.round(3).tolist()
    ([1.0, 2.0], [0.0, 0.0])
    """
    flat = surface.uvh[np.abs(surface.normals[:, 2]) >= np.cos(np.radians(FACE_TILT))]
    flat = flat[np.argsort(flat[:, 2], kind="stable")]
    cuts = np.flatnonzero(np.diff(flat[:, 2]) > FACE_GAP * tolerance) + 1
    least = FACE_SHARE * len(surface.uvh)
    heights, clear = [], []
    for group in np.split(flat, cuts):
        if len(group) < least:
            continue
        spread, across = _spread(group[:, 2]), _across(group[:, :2])
        if (spread <= FACE_SPREAD * tolerance and across >= FACE_WIDTH * tolerance
                and _shape_span(group) <= FACE_SLOPE * across):
            heights.append(float(np.median(group[:, 2])))
            clear.append(2 * FACE_SIGMAS * spread / IQR_SIGMAS)
    return np.array(heights), np.array(clear)


def stack_ends(surface: SurfaceSamples, faces: FloatArray, tolerance: float
               ) -> tuple[float, float, np.ndarray]:
    """Where a stack of layers starts and stops, and the faces between.

    A face within `FACE_CLEARANCE` tolerances of the cloud's lowest (highest) point is the
    part's bottom (top): the stack starts (stops) on it, not on the lowest (highest) noisy
    point, which lies up to three standard deviations of the noise beyond it. Elsewhere the
    stack spans the cloud.

    Returns
    -------
    bottom, top : heights where the stack starts and stops.
    inside : which of the ``faces`` lie between them.
    """
    low, high = float(surface.uvh[0, 2]), float(surface.uvh[-1, 2])
    clear = FACE_CLEARANCE * tolerance
    bottom = float(faces[0]) if len(faces) and faces[0] - clear <= low else low
    top = float(faces[-1]) if len(faces) and faces[-1] + clear >= high else high
    if top <= bottom:  # one flat face: a slab thinner than the clearance
        return low, high, np.zeros(len(faces), dtype=bool)
    return bottom, top, (faces > bottom) & (faces < top)


def _shape_span(group: FloatArray) -> float:
    """The height a quadratic fitted to a group's heights over its plane coordinates spans
    between its 5th and 95th percentile: the group's own shape, not its noise."""
    u, v = (group[:, :2] - group[:, :2].mean(axis=0)).T
    terms = quadric_terms(u, v)
    coef, _ = quadric_fit(terms[None], group[None, :, 2])
    low, high = np.percentile(terms @ coef[0], [5, 95])
    return float(high - low)


def _across(uv: FloatArray) -> float:
    """The diagonal of the box that holds the middle 90 % of a group's points each way."""
    low, high = np.percentile(uv, [5, 95], axis=0)
    return float(np.linalg.norm(high - low))


def _spread(heights: FloatArray) -> float:
    """The height between a group's first and third quartile."""
    low, high = np.percentile(heights, [25, 75])
    return float(high - low)


def section_height(surface: SurfaceSamples, bottom: float, top: float, tolerance: float
                   ) -> tuple[float, float | None]:
    """Where to take the section of the slab [bottom, top] given its points' surface samples:
    its mid-plane, or, where that lies in the noisy points of a flat face (within half the
    face's clearance), the mid-plane of the slab's larger part beside the face.

    A uniform layer keeps the thickness asked for, so a face may fall anywhere in it; at the
    mid-plane the face's points mix with the walls' and the section is neither part's. The
    larger part's section, which the layer then stands for, is taken at that part's middle,
    and at least half the face's clearance from it. Beyond a cap the larger part may hold
    the cap's noise alone (`PART_SHARE`); the section then stays at the mid-plane.

    Returns
    -------
    height : the section's height.
    face : the face's height when the section was moved off the mid-plane, else None.
    """
    z = 0.5 * (bottom + top)
    faces, clear = flat_faces(surface, tolerance)
    near = np.flatnonzero(np.abs(faces - z) < clear / 2)
    if not len(near):
        return z, None
    face, half = float(faces[near[0]]), float(clear[near[0]] / 2)
    end = bottom if face >= z else top  # the far end of the larger part
    side = np.sign(end - face)
    height = face + side * max(half, 0.5 * abs(end - face))
    beyond = np.count_nonzero(side * (surface.uvh[:, 2] - face) > half)
    if not bottom < height < top or beyond < PART_SHARE * len(surface.uvh):
        return z, None  # the part beyond a cap holds the cap's noise alone
    return float(height), face
