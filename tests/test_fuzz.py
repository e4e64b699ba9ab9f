"""Hypothesis mutates the bytes of small valid files of every format: each read ends in a clean
refusal (DataError) or valid points, within a time bound, never a raw exception or a hang."""

from __future__ import annotations

import gzip
import io
import time

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from wavepoly import DataError, read_points

#: No read of a file of a few hundred bytes may take longer than this.
TIME_BOUND = 5.0


def _samples() -> dict[str, bytes]:
    rng = np.random.default_rng(0)
    pts = rng.normal(size=(12, 3))
    text = "\n".join(" ".join(f"{v:.4f}" for v in p) for p in pts) + "\n"
    ply = ("ply\nformat ascii 1.0\nelement vertex 12\nproperty float x\nproperty float y\n"
           "property float z\nend_header\n" + text)
    pcd = ("# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
           "WIDTH 12\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 12\nDATA ascii\n" + text)
    off = "OFF\n12 1 0\n" + text + "3 0 1 2\n"
    obj = "".join(f"v {p[0]:.4f} {p[1]:.4f} {p[2]:.4f}\n" for p in pts) + "f 1 2 3\n"
    gtn = "12 2 0 0\n" + "".join(f"{k} {p[0]:.4f} {p[1]:.4f}\n" for k, p in enumerate(pts))
    flaser = "".join(f"FLASER 5 1.0 1.5 2.0 1.5 1.0 {k * 0.1:.1f} 0.0 0.0 0 0 0 0 0 0\n"
                     for k in range(12))
    npy = io.BytesIO()
    np.save(npy, pts)
    return {"xyz": text.encode(), "csv": text.replace(" ", ",").encode(), "ply": ply.encode(),
            "pcd": pcd.encode(), "off": off.encode(), "obj": obj.encode(), "gtn": gtn.encode(),
            "log.gz": gzip.compress(flaser.encode()), "npy": npy.getvalue()}


SAMPLES = _samples()


@st.composite
def mutated(draw):
    fmt = draw(st.sampled_from(sorted(SAMPLES)))
    data = bytearray(SAMPLES[fmt])
    for _ in range(draw(st.integers(1, 6))):
        kind = draw(st.sampled_from(["flip", "insert", "delete", "truncate"]))
        at = draw(st.integers(0, max(0, len(data) - 1)))
        if kind == "flip" and data:
            data[at] = draw(st.integers(0, 255))
        elif kind == "insert":
            data[at:at] = draw(st.binary(min_size=1, max_size=16))
        elif kind == "delete" and data:
            del data[at:at + draw(st.integers(1, 16))]
        elif kind == "truncate":
            del data[at:]
    return fmt, bytes(data)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                 HealthCheck.function_scoped_fixture])
@given(mutated())
def test_mutated_files_are_refused_cleanly_or_read(tmp_path, case):
    fmt, data = case
    path = tmp_path / f"fuzz.{fmt}"
    path.write_bytes(data)
    t0 = time.perf_counter()
    try:
        pts = read_points(path)
    except DataError as exc:
        message = str(exc)
        assert message.startswith(str(path)) and "\n" not in message
    else:
        assert pts.ndim == 2 and pts.shape[1] in (2, 3) and np.isfinite(pts).all()
    assert time.perf_counter() - t0 < TIME_BOUND


@pytest.mark.parametrize("fmt", sorted(SAMPLES))
def test_the_unmutated_samples_read(tmp_path, fmt):
    path = tmp_path / f"ok.{fmt}"
    path.write_bytes(SAMPLES[fmt])
    assert len(read_points(path)) >= 5
