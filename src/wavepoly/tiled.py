"""Many scan files as one cloud, sliced in this process's pool or on a Dask cluster.

Locally, the tiles are read chunk by chunk into one cloud and sliced by `slice_cloud`. On a
cluster (``scheduler``: an address, or ``"local"`` for a cluster of ``workers`` processes on
this machine) nothing of the cloud passes through this process:

1. each worker reads a tile in chunks and returns its count and height range
   (`wavepoly.io.tiles.tile_summary`); the layers are planned from these figures alone;
2. each tile is read again and split by layer on a worker (`tile_layers`), and each layer's
   pieces are merged on a worker into that layer's points, sorted by height (`merge_layer`);
3. each layer is fitted from its band (`wavepoly.bands.fit_layer_job`), and then its
   staircase error is computed (`layer_error_job`): only the band's layers travel to it.

The layers come out the same as from the local run (the same band, the same rows in the same
order, the same job). Dask keeps the graph of every piece, so a worker that dies mid-run
costs only the recomputation of what it held.
"""

from __future__ import annotations

import operator
import os
import signal
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np

from .bands import farther_jobs, fit_layer_job, held_over, layer_error_job
from .errors import DataError, EngineError
from .io.tiles import expand_sources, merge_layer, read_cloud, tile_layers, tile_summary
from .slicing import (
    error_jobs,
    fit_bands,
    layer_model,
    layer_specs,
    plane_basis,
    slice_cloud,
    uniform_layers,
)
from .types import DEFAULT_RELATIVE_TOLERANCE, ErrorJob, FloatArray, LayerJob, SliceResult
from .validate import check_relative_tolerance, check_tolerance

#: Seconds to wait for a Dask scheduler before saying it cannot be reached.
CONNECT_TIMEOUT = 10
#: The environment variable that names the scheduler when ``--scheduler`` is not given.
SCHEDULER_VARIABLE = "DASK_SCHEDULER_ADDRESS"


def slice_tiles(sources: Sequence[str | Path], tolerance: float, *, layer_thickness: float,
                axis: str | FloatArray = "z", band: float | None = None,
                relative_tolerance: float | None = DEFAULT_RELATIVE_TOLERANCE,
                scheduler: str | None = None, workers: int | None = None,
                fmt: str | None = None, columns: Sequence[int] | None = None,
                progress: Callable[[int, int], None] | None = None) -> SliceResult:
    """Slice the union of scan files (paths, folders, glob patterns) into uniform layers.

    Parameters
    ----------
    sources : the tiles; folders give their point files, patterns their matches.
    tolerance, layer_thickness, axis, band, relative_tolerance : as in `slice_cloud`.
    scheduler : None: the local process pool (``workers`` processes); ``"local"``: a Dask
        cluster of ``workers`` processes started here and stopped at the end; otherwise the
        address of a running Dask scheduler (``tcp://host:8786``).
    workers : processes of the local pool or cluster (default: all cores).
    fmt, columns : as in `wavepoly.read_points`, for every tile.
    progress : called as ``progress(done, total)`` as layers are fitted.
    """
    paths = expand_sources(sources)
    if not paths:
        raise DataError("no scan file given")
    if scheduler is None:
        cloud = read_cloud(paths, fmt=fmt, columns=columns)
        return slice_cloud(cloud, tolerance, axis=axis, layer_thickness=layer_thickness,
                           band=band, relative_tolerance=relative_tolerance, workers=workers,
                           progress=progress)
    tolerance = check_tolerance(tolerance)
    step = check_tolerance(layer_thickness, "layer_thickness")
    relative_tolerance = check_relative_tolerance(relative_tolerance)
    if band is not None:
        band = check_tolerance(band, "band")
    with _Cluster(scheduler, workers) as (client, engine):
        return _slice_on(client, engine, paths, tolerance, step, plane_basis(axis), band,
                         relative_tolerance, fmt, columns, progress)


class _Cluster:
    """A Dask client for ``scheduler`` (an address, or "local" for a cluster started here and
    stopped on leaving), with the engine record of the report."""

    def __init__(self, scheduler: str, workers: int | None):
        self.scheduler, self.workers, self.cluster, self.client = scheduler, workers, None, None

    def __enter__(self):
        try:
            from distributed import Client, LocalCluster
        except ImportError:
            raise EngineError("slicing on a Dask cluster needs the dask extra: "
                              "pip install 'wavepoly[dask]'") from None
        if self.scheduler == "local":
            count = self.workers or os.cpu_count() or 1
            # the workers inherit an ignored Ctrl-C: the caller stops them (as the local pool)
            main = threading.current_thread() is threading.main_thread()
            previous = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
            try:
                self.cluster = LocalCluster(n_workers=count, threads_per_worker=1,
                                            processes=True, dashboard_address=None,
                                            host="127.0.0.1")
            finally:
                if main:
                    signal.signal(signal.SIGINT, previous)
            self.client = Client(self.cluster)
            address = self.cluster.scheduler_address
        else:
            address = self.scheduler
            try:
                self.client = Client(address, timeout=CONNECT_TIMEOUT)
            except (OSError, TimeoutError, ValueError) as exc:
                raise EngineError(f"cannot reach the Dask scheduler at {address}: "
                                  f"{str(exc).splitlines()[0] if str(exc) else 'timed out'}"
                                  ) from None
        count = len(self.client.scheduler_info().get("workers", {}))
        return self.client, {"kind": "dask", "scheduler": address, "workers": count}

    def __exit__(self, *exc_info):
        if self.client is not None:
            self.client.close()
        if self.cluster is not None:
            self.cluster.close()


def _slice_on(client, engine: dict, paths: list[Path], tolerance: float, step: float,
              basis: FloatArray, band: float | None, relative_tolerance: float | None,
              fmt: str | None, columns: Sequence[int] | None,
              progress: Callable[[int, int], None] | None) -> SliceResult:
    t0 = time.perf_counter()
    names = [str(p) for p in paths]
    summaries = client.gather(client.map(tile_summary, names, basis=basis, fmt=fmt,
                                         columns=columns, pure=False))
    total = sum(s.count for s in summaries)
    if total < 3:
        raise DataError(f"{', '.join(names)}: {total} point(s); slicing needs 3 or more")
    low = min(s.low for s in summaries if s.count)
    high = max(s.high for s in summaries if s.count)
    bottoms, thick = uniform_layers(low, high, step)
    specs = layer_specs(bottoms, thick, tolerance, relative_tolerance, band)
    splits = client.map(tile_layers, names, basis=basis, bottoms=bottoms, fmt=fmt,
                        columns=columns, pure=False)
    layers = [client.submit(merge_layer, *[client.submit(operator.getitem, split, k)
                                           for split in splits]) for k in range(len(specs))]
    del splits  # the merged layers hold them until they are computed, and no longer
    timings = {"planning": time.perf_counter() - t0}
    t0 = time.perf_counter()
    done = [0]

    def run(tasks):
        futures = [client.submit(_fit_pieces, spec, *layers[first:stop], pure=False)
                   for spec, first, stop in tasks]
        return _gathered(client, futures, progress, done, len(specs))

    def errors_of(asks):  # each (layer, job) on the worker that holds the layer's slab
        return client.gather([client.submit(_error_of, job, layers[k], pure=False)
                              for k, job in asks])

    fits = held_over(fit_bands(specs, run), bottoms, bottoms + thick, errors_of, tolerance)
    timings["fitting"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    jobs = error_jobs(specs, [f.contours for f in fits], lambda k: None)
    errors = errors_of(list(enumerate(jobs)))
    again = farther_jobs(jobs, errors, bottoms, bottoms + thick, [f.contours for f in fits])
    for (k, _), err in zip(again, errors_of(again)):
        errors[k] = err
    counts = np.array(client.gather(client.map(len, layers, pure=False)))
    timings["model_error"] = time.perf_counter() - t0
    frame = SliceResult([], basis, tolerance, False, total, timings, engine=engine)
    return layer_model(bottoms, thick, fits, errors, counts, frame)


def _gathered(client, futures: list, progress, done: list[int], total: int) -> list:
    """The futures' results in order, calling ``progress`` as each one finishes."""
    from distributed import as_completed

    if progress:
        for _ in as_completed(futures):
            done[0] += 1
            progress(min(done[0], total), total)
    return client.gather(futures)


def _fit_pieces(spec, *layers: FloatArray):
    """`fit_layer_job` of a band given as its layers' points (the cluster's task)."""
    return fit_layer_job(LayerJob(spec, np.concatenate(layers)))


def _error_of(job: ErrorJob, slab: FloatArray) -> float:
    """`layer_error_job` with the slab's points sent apart from the contours."""
    return layer_error_job(replace(job, slab=slab))


def dask_available() -> bool:
    """True when the dask extra (dask.distributed) is installed."""
    import importlib.util

    return importlib.util.find_spec("distributed") is not None


def scheduler_from_environment() -> str | None:
    """The scheduler address of `SCHEDULER_VARIABLE`, if set and not empty."""
    return os.environ.get(SCHEDULER_VARIABLE) or None


__all__ = ["dask_available", "scheduler_from_environment", "slice_tiles"]
