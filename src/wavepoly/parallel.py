"""How independent work runs: in this process, or in a local process pool.

A job is a picklable record and the work a module-level pure function, so the same jobs can go
to another engine (a cluster) without changing the stages.
"""

from __future__ import annotations

import os
import signal
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import ProcessPoolExecutor
from typing import TypeVar

from .errors import ParameterError

Job = TypeVar("Job")
Result = TypeVar("Result")


def resolve_workers(workers: int | None) -> int:
    """The number of processes to use: all cores when None; at least 1."""
    count = (os.cpu_count() or 1) if workers is None else int(workers)
    if count < 1:
        raise ParameterError(f"workers must be 1 or more, not {workers}")
    return count


def run_jobs(work: Callable[[Job], Result], jobs: Sequence[Job], workers: int | None = None,
             progress: Callable[[int, int], None] | None = None) -> list[Result]:
    """``[work(job) for job in jobs]``, in order, on ``workers`` processes (1: this process).

    ``progress(done, total)`` is called after each job, in order.
    """
    count = resolve_workers(workers)
    if count == 1 or len(jobs) <= 1:
        return _collect(map(work, jobs), len(jobs), progress)
    pool = ProcessPoolExecutor(max_workers=min(count, len(jobs)), initializer=_ignore_interrupts)
    try:
        out = _collect(pool.map(work, jobs, chunksize=1), len(jobs), progress)
    except BaseException:  # an error, Ctrl-C or SIGTERM: no worker may outlive the caller
        _stop(pool)
        raise
    pool.shutdown()
    return out


def _ignore_interrupts() -> None:
    """Workers leave Ctrl-C (sent to the whole process group) to the caller, which stops them,
    and end quietly on SIGTERM (not with a handler inherited from the caller)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


def _stop(pool: ProcessPoolExecutor) -> None:
    """Terminate the pool's workers now, whatever they are doing, and drop pending work."""
    for process in list(getattr(pool, "_processes", {}).values()):
        process.terminate()
    pool.shutdown(wait=True, cancel_futures=True)


def _collect(results: Iterable[Result], total: int,
             progress: Callable[[int, int], None] | None) -> list[Result]:
    out = []
    for k, res in enumerate(results):
        out.append(res)
        if progress:
            progress(k + 1, total)
    return out
