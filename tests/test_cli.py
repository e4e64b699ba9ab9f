"""The command line: exit codes, one-line errors, no half-written outputs, info on real files."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from wavepoly.samples import glyph_outlines, sample_rings


def run(*args: str, cwd=None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "wavepoly", *map(str, args)],
                          capture_output=True, text=True, cwd=cwd, timeout=300)


@pytest.fixture(scope="module")
def glyph_file(tmp_path_factory):
    pts = sample_rings(glyph_outlines("O").rings, spacing=0.03, noise=0.01, seed=1)
    path = tmp_path_factory.mktemp("cli") / "o.xy"
    np.savetxt(path, pts)
    return path


def test_help_and_version():
    out = run("--help")
    assert out.returncode == 0
    for cmd in ("info", "order", "fit", "demo"):
        assert cmd in out.stdout
    version = run("--version")
    assert version.returncode == 0 and version.stdout.startswith("wavepoly ")


def test_info(glyph_file):
    out = run("info", glyph_file)
    assert out.returncode == 0, out.stderr
    assert "points:" in out.stdout and "suggested tolerance" in out.stdout


def test_info_walks_shared_data(shared_data):
    for name in ("scans3d/turbineblade.ply", "curves2d/hnn_crust/family.gtn",
                 "scans3d/bunny_range_scans/bun000.ply", "curves2d/noisy_sets/stair.xym"):
        out = run("info", shared_data / name)
        assert out.returncode == 0, (name, out.stderr)
        assert "dimensions:" in out.stdout


def test_fit_writes_outputs(glyph_file, tmp_path):
    out = run("fit", glyph_file, "-t", "0.08", "-o", tmp_path / "o.geojson",
              "--report", tmp_path / "r.json", "--plot", tmp_path / "f.png")
    assert out.returncode == 0, out.stderr
    doc = json.loads((tmp_path / "o.geojson").read_text())
    assert doc["features"][0]["geometry"]["type"] == "Polygon"
    assert len(doc["features"][0]["geometry"]["coordinates"]) == 2  # the O and its hole
    report = json.loads((tmp_path / "r.json").read_text())
    assert report["max_error"] <= 0.08
    keys = {"input_points", "ordered_points", "levels_decomposed", "coarsest_level",
            "mscs_per_level", "wavelet_vertices", "final_vertices", "max_error", "mean_error",
            "closed"}
    assert keys <= set(report["contours"][0])
    assert set(report["timings"]) >= {"ordering", "decomposition", "reconstruction"}
    assert (tmp_path / "f.png").stat().st_size > 1000


@pytest.mark.parametrize("content", ["", "1 2\n", "1 2\n1 2\n1 2\n", "1 2\nnan 1\n3 3\n",
                                     "1 2\n3 4\njunk here\n"])
def test_bad_data_exit_1(tmp_path, content):
    src = tmp_path / "bad.xy"
    src.write_text(content)
    out = run("fit", src, "-t", "0.1", "-o", tmp_path / "out.geojson")
    assert out.returncode == 1
    assert out.stderr.startswith("error: ") and "bad.xy" in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1 and "Traceback" not in out.stderr
    assert not (tmp_path / "out.geojson").exists()


def test_missing_file_and_directory(tmp_path):
    for target, message in ((tmp_path / "none.xy", "no such file"), (tmp_path, "directory")):
        out = run("info", target)
        assert out.returncode == 1 and message in out.stderr


@pytest.mark.parametrize("tol", ["0", "-1", "nan"])
def test_bad_tolerance_exit_2(glyph_file, tmp_path, tol):
    out = run("fit", glyph_file, "-t", tol, "-o", tmp_path / "out.geojson")
    assert out.returncode == 2
    assert "tolerance" in out.stderr and "Traceback" not in out.stderr
    assert not (tmp_path / "out.geojson").exists()


def test_usage_errors_exit_2(glyph_file, tmp_path):
    assert run("fit", glyph_file).returncode == 2  # missing options
    assert run("nonsense").returncode == 2
    out = run("fit", glyph_file, "-t", "0.1", "-o", tmp_path / "out.xyz")
    assert out.returncode == 2 and "output must end" in out.stderr


def test_debug_shows_traceback(tmp_path):
    src = tmp_path / "bad.xy"
    src.write_text("1 2\n")
    out = run("--debug", "info", src)
    assert out.returncode != 0 and "Traceback" in out.stderr


def test_outputs_are_checked_before_any_work(glyph_file, tmp_path):
    """The input is never overwritten, and a bad output path writes nothing at all."""
    import shutil

    src = tmp_path / "same.xy"
    shutil.copy(glyph_file, src)
    before = src.read_bytes()
    (tmp_path / "sub").mkdir()
    for extra in (["-o", str(src)], ["-o", str(tmp_path / "sub" / ".." / "same.xy")],
                  ["-o", str(tmp_path / "o.geojson"), "--report", str(src)],
                  ["-o", str(tmp_path / "o.geojson"), "--report",
                   str(tmp_path / "no" / "such" / "r.json")],
                  ["-o", str(tmp_path / "o.geojson"), "--plot", str(tmp_path / "out.xyz")],
                  ["-o", str(tmp_path / "o.geojson"), "--report", str(tmp_path / "o.geojson")]):
        out = run("fit", src, "-t", "0.08", *extra)
        assert out.returncode == 2, (extra, out.stderr)
        assert out.stderr.count("\n") == 1 and "error:" in out.stderr
    assert src.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["same.xy", "sub"]


def _processes_with(marker: str) -> list[int]:
    """Live processes whose command line holds ``marker`` (the run's unique folder)."""
    import os

    pids = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/cmdline", "rb") as fh:
                    if marker.encode() in fh.read():
                        pids.append(int(entry))
            except OSError:
                continue
    return pids


def _first_progress_line(proc, timeout: float = 60.0) -> str:
    """The stderr of ``proc`` up to and including its first "fitting layers" line."""
    import select
    import time

    seen, deadline = "", time.monotonic() + timeout
    while time.monotonic() < deadline:
        ready, _, _ = select.select([proc.stderr], [], [], 0.5)
        if ready:
            line = proc.stderr.readline()
            seen += line
            if not line or line.startswith("fitting layers: "):
                return seen
    return seen


@pytest.mark.parametrize("sig, code", [("SIGTERM", 143), ("SIGINT", 130)])
def test_a_signal_stops_a_slice_cleanly(tmp_path, sig, code):
    """Ctrl-C (to the whole process group) or SIGTERM during a slice on the local pool: the
    right exit code within seconds, a one-line message, no output, no temporary file, and
    no worker left running."""
    import os
    import signal
    import time

    rng = np.random.default_rng(0)
    t, h = rng.uniform(0, 2 * np.pi, 400_000), rng.uniform(0, 40, 400_000)
    cloud = np.column_stack([5 * np.cos(t), 5 * np.sin(t), h])
    np.save(tmp_path / "cloud.npy", cloud)
    out = tmp_path / "model.stl"
    proc = subprocess.Popen([sys.executable, "-m", "wavepoly", "slice", str(tmp_path / "cloud.npy"),
                             "-t", "0.02", "--layer", "0.02", "-o", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    # the signal goes once the pool is at work (its first progress line), not after a fixed
    # wait that a loaded machine may not have reached
    seen = _first_progress_line(proc)
    assert proc.poll() is None, proc.communicate()
    if sig == "SIGINT":
        os.killpg(proc.pid, signal.SIGINT)
    else:
        proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=20)
    err = seen + err
    assert proc.returncode == code, err
    *progress, last = err.strip().splitlines()  # plain progress lines, then one message
    assert all(line.startswith("fitting layers: ") for line in progress)
    assert "interrupted" in last or "terminated" in last
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cloud.npy"]
    time.sleep(0.5)
    assert _processes_with(str(tmp_path)) == []


def test_a_read_only_output_is_replaced_only_with_force(glyph_file, tmp_path):
    target = tmp_path / "o.geojson"
    target.write_text("{}")
    target.chmod(0o444)
    out = run("fit", glyph_file, "-t", "0.08", "-o", target)
    assert out.returncode == 2 and "read-only" in out.stderr
    assert target.read_text() == "{}"
    out = run("fit", glyph_file, "-t", "0.08", "-o", target, "--force")
    assert out.returncode == 0, out.stderr
    assert json.loads(target.read_text())["type"] == "FeatureCollection"


def test_order_writes_its_contours_and_info_measures_a_cloud_in_3d(glyph_file, tmp_path):
    import csv

    out = run("order", glyph_file, "-r", "0.08", "-o", tmp_path / "ordered.csv")
    assert out.returncode == 0, out.stderr
    with open(tmp_path / "ordered.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert {r["contour"] for r in rows} == {"0", "1"}  # the O and its hole
    assert all(r["closed"] == "1" for r in rows)
    assert len(rows) > 50
    rng = np.random.default_rng(2)
    t, h = rng.uniform(0, 2 * np.pi, 20000), rng.uniform(0, 22, 20000)
    np.save(tmp_path / "part.npy", np.column_stack([5 * np.cos(t), 5 * np.sin(t), h]))
    info = run("info", tmp_path / "part.npy")
    spacing = float(info.stdout.split("spacing:")[1].split()[0])
    assert "in 3D" in info.stdout and spacing > 0.05  # not the x-y projection's 0.0005


def test_long_work_logs_plain_progress_lines_when_stderr_is_not_a_terminal(tmp_path,
                                                                            monkeypatch):
    """Work past `LOG_AFTER` seconds logs a plain line per tenth of it; the delay is taken
    out here (in-process), so that a small job shows the lines a long one would."""
    from typer.testing import CliRunner

    from wavepoly import console
    from wavepoly.cli import app

    monkeypatch.setattr(console, "LOG_AFTER", 0.0)
    rng = np.random.default_rng(0)
    t, h = rng.uniform(0, 2 * np.pi, 20_000), rng.uniform(0, 30, 20_000)
    np.save(tmp_path / "cloud.npy", np.column_stack([np.cos(t), np.sin(t), h]))
    out = CliRunner().invoke(app, ["slice", str(tmp_path / "cloud.npy"), "-t", "0.02",
                                   "--layer", "0.3", "-o", str(tmp_path / "m.cli")])
    assert out.exit_code == 0, out.output
    lines = [ln for ln in out.stderr.splitlines() if ln.startswith("fitting layers: ")]
    assert 3 <= len(lines) <= 11 and lines[-1].endswith("/100")
