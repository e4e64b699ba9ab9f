"""Large clouds: 10^7 points into ~100 layers, from one PLY and from LAZ tiles, in the local
pool and on a Dask cluster of 1 and 2 workers (issues "Speed" and "Beyond one machine").

The cloud is made here (points sampled on the shared turbine blade's faces, 0.1 % noise) and
deleted afterwards; nothing is committed. Each run is a separate process that reports its own
wall time and peak memory (and its pool's); the Dask workers are separate ``dask worker``
processes whose peak memory (VmHWM) is read before they are stopped.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from .common import ROOT, SHARED, table

POINTS = 10_000_000
LAYERS = 100
TILES = 4
NOISE = 0.001
EPS_PER_NOISE = 5.0


def run() -> str:
    mesh_path = SHARED / "scans3d" / "turbineblade.ply"
    if not mesh_path.exists():
        return "## Large clouds\n\n(shared turbine blade absent: skipped)\n"
    with tempfile.TemporaryDirectory(prefix="wavepoly-large-") as tmp:
        folder = Path(tmp)
        made, eps, thickness = _make_cloud(mesh_path, folder)
        runs = [("one PLY (float32), local pool of 2", [folder / "cloud.ply"], None),
                (f"{TILES} LAZ tiles, local pool of 2", [folder / "tiles"], None)]
        rows, models = [], {}
        for label, sources, _ in runs:
            res = _slice(sources, eps, thickness)
            rows.append(_row(label, res, "—"))
            models[label] = res["model"]
        for workers in (1, 2):
            with _cluster(folder, workers) as (address, pids):
                res = _slice([folder / "tiles"], eps, thickness, scheduler=address)
                worker_peak = max(_peak_mb(pid) for pid in pids)
            rows.append(_row(f"{TILES} LAZ tiles, Dask, {workers} worker(s)", res,
                             f"{worker_peak:.0f}"))
            models[f"dask {workers}"] = res["model"]
    same = len({json.dumps(m) for label, m in models.items() if "PLY" not in label}) == 1
    return ("## Large clouds: 10^7 points into ~100 layers\n\n"
            f"{POINTS:,} points sampled on the turbine blade's faces (σ = {NOISE:.1%} of the "
            f"diagonal, ε = {EPS_PER_NOISE:g} σ = {eps:.3g}), {LAYERS} uniform layers of "
            f"{thickness:.3g}; made in {made:.1f} s and written as one binary PLY (float32) and "
            f"as {TILES} LAZ tiles (cut across x). Each row is `wavepoly slice` in a process of "
            "its own on this 2-core machine: wall time from start to the written .cli; peak "
            "resident memory (VmHWM) of the driver (the process that reads and plans) and of "
            "the largest Dask worker (separate `dask worker` processes, `--nthreads 1`); the "
            "largest pool worker's and the driver-and-pool total as sampled proportional set "
            "sizes (shared pages counted once), every 0.2 s.\n\n"
            + table(["run", "seconds", "points/s", "layers", "vertices", "driver MB",
                     "pool worker MB", "Dask worker MB", "total MB"], rows)
            + f"\n\nThe tiles give the same layer model in the pool and on the cluster "
              f"(layers, contours, vertices, errors): **{'yes' if same else 'NO'}**. "
              "The PLY differs in the last digits of its float32 coordinates from the "
              "tiles' 0.1 µm grid, hence its own vertices.\n\n" + MODEL)


MODEL = """**How it grows (on paper).** The driver reads and holds the cloud only in the local
pool: 3 copies of 24 bytes per point (the points, their plane coordinates sorted by height,
and the bands being sent), so 10^8 points need about 7 GB and 10^7 about 0.7 GB besides
Python's 0.2 GB. A layer's job holds its band (the slab and two layers either side: 5 N / L
points for N points in L layers) and the tangent planes of its slab; its time is that of
the KD-tree of the band and of the fit of its section, about linear in N / L, so the pool's
time is about c N / cores with c ≈ 5 µs per point on this machine (10^8 points: ~4 min on 2
cores, ~30 s on 16).

On a Dask cluster the driver holds no points: the per-tile counts and height ranges, the
layer plan, and the layers' contours (kilobytes per layer). Per layer, what crosses the
network is its band (5 N / L points of 24 bytes, sent once from the workers that split the
tiles to the one that fits it) and its contours back; each tile is read twice (the summary,
then the split) by the worker that holds it. The workers together hold about 2 copies of
the cloud while the layers are split and merged (the tiles' pieces and the merged layers),
so 10^9 points (24 GB each copy) need about 50 GB of worker memory across the cluster, e.g.
8 machines of 8 GB, and the time is the pool's divided by the workers, plus the reading of
the tiles, which is parallel too."""


def _make_cloud(mesh_path: Path, folder: Path) -> tuple[float, float, float]:
    import trimesh
    from plyfile import PlyData, PlyElement

    if str(ROOT) not in sys.path:  # the cloud makers live beside the tests
        sys.path.insert(0, str(ROOT))
    from tests import truth

    t0 = time.perf_counter()
    mesh = trimesh.load(mesh_path, process=False)
    diag = float(np.linalg.norm(mesh.extents))
    pts = truth.noisy_surface_cloud(mesh, POINTS, NOISE * diag, seed=7)
    vertex = np.empty(len(pts), dtype=[("x", "<f4"), ("y", "<f4"), ("z", "<f4")])
    vertex["x"], vertex["y"], vertex["z"] = pts.T
    PlyData([PlyElement.describe(vertex, "vertex")]).write(str(folder / "cloud.ply"))
    del vertex
    truth.las_tiles(folder / "tiles", pts, TILES)
    height = float(mesh.extents[2])
    return time.perf_counter() - t0, EPS_PER_NOISE * NOISE * diag, height / LAYERS


def _slice(sources, eps: float, thickness: float, scheduler: str | None = None) -> dict:
    """One `wavepoly slice` in its own process (this module's runner)."""
    args = {"sources": [str(s) for s in sources], "eps": eps, "thickness": thickness,
            "scheduler": scheduler}
    out = subprocess.run([sys.executable, "-m", "benchmarks.bench_large", json.dumps(args)],
                         capture_output=True, text=True, cwd=ROOT, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def _row(label: str, res: dict, dask_peak: str) -> list:
    return [label, f"{res['seconds']:.1f}", f"{res['points'] / res['seconds']:,.0f}",
            res["layers"], res["vertices"], f"{res['driver_mb']:.0f}",
            f"{res['pool_mb']:.0f}" if res["pool_mb"] else "—", dask_peak,
            f"{res['total_mb']:.0f}"]


class _cluster:
    """A `dask scheduler` and ``workers`` `dask worker` processes on 127.0.0.1 (stopped on
    leaving); yields the address and the workers' process ids."""

    def __init__(self, folder: Path, workers: int):
        self.file, self.workers, self.procs = folder / f"scheduler-{workers}.json", workers, []

    def __enter__(self):
        bin_dir = Path(sys.executable).parent
        quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
        self.procs.append(subprocess.Popen(
            [bin_dir / "dask", "scheduler", "--host", "127.0.0.1", "--port", "0",
             "--no-dashboard", "--scheduler-file", self.file], **quiet))
        for _ in range(self.workers):
            self.procs.append(subprocess.Popen(
                [bin_dir / "dask", "worker", "--scheduler-file", self.file, "--nthreads", "1",
                 "--no-nanny", "--no-dashboard", "--host", "127.0.0.1",
                 "--memory-limit", "0"], **quiet))
        from distributed import Client

        for _ in range(600):
            if self.file.exists():
                break
            time.sleep(0.1)
        with Client(scheduler_file=str(self.file), timeout=60) as client:
            client.wait_for_workers(self.workers, timeout=60)
            address = client.scheduler.address
        return address, [p.pid for p in self.procs[1:]]

    def __exit__(self, *exc_info):
        for proc in reversed(self.procs):
            proc.terminate()
        for proc in self.procs:
            try:
                proc.wait(timeout=30)
            except subprocess.TimeoutExpired:  # a worker still reconnecting: stop it
                proc.kill()
                proc.wait()


def _peak_mb(pid: int) -> float:
    """Peak resident memory (VmHWM) of a running process, in MB."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) / 1024.0
    return float("nan")


def _descendants(pid: int) -> list[int]:
    """``pid`` and all its living descendants."""
    children: dict[int, list[int]] = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        children.setdefault(int(fields[1]), []).append(int(stat.parent.name))
    out, todo = [], [pid]
    while todo:
        p = todo.pop()
        out.append(p)
        todo.extend(children.get(p, []))
    return out


def _pss_mb(pid: int) -> float:
    """Proportional set size of a process (shared pages split among their users), in MB."""
    try:
        for line in Path(f"/proc/{pid}/smaps_rollup").read_text().splitlines():
            if line.startswith("Pss:"):
                return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return 0.0


class _Sampler:
    """The largest total memory (PSS) of this process and its descendants, sampled."""

    def __init__(self, period: float = 0.2):
        import threading

        self.period, self.peak, self.worker_peak = period, 0.0, 0.0
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self) -> None:
        me = os.getpid()
        while not self.stop.wait(self.period):
            tree = _descendants(me)
            sizes = {p: _pss_mb(p) for p in tree}
            self.peak = max(self.peak, sum(sizes.values()))
            others = [v for p, v in sizes.items() if p != me]
            self.worker_peak = max([self.worker_peak, *others])

    def close(self) -> tuple[float, float]:
        self.stop.set()
        self.thread.join()
        return self.peak, self.worker_peak


def _runner(args: dict) -> None:
    """Slice as the command does, in this process, and print the figures as JSON."""
    import wavepoly
    from wavepoly.io.report import slice_report

    sampler = _Sampler()
    t0 = time.perf_counter()
    res = wavepoly.slice_tiles(args["sources"], args["eps"], layer_thickness=args["thickness"],
                               scheduler=args["scheduler"], workers=2)
    out = Path(tempfile.mkdtemp(prefix="wavepoly-large-out-")) / "model.cli"
    wavepoly.write_layers(out, res)
    seconds = time.perf_counter() - t0
    doc = slice_report(res, args["sources"])
    model = [(la["contours"], la["vertices"], la["model_error"]) for la in doc["per_layer"]]
    total, worker = sampler.close()
    print(json.dumps({
        "seconds": seconds, "points": res.n_points, "layers": len(res.layers),
        "vertices": res.n_vertices, "model": model, "driver_mb": _peak_mb(os.getpid()),
        "total_mb": total, "pool_mb": worker if args["scheduler"] is None else 0.0}))
    os.remove(out)


if __name__ == "__main__":
    if len(sys.argv) == 2 and sys.argv[1].startswith("{"):
        _runner(json.loads(sys.argv[1]))
    else:
        print(run())
