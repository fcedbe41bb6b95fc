"""Independent tasks on local cores or on a Dask cluster: one mapper for every caller.

Beam sweeps, DC3D particle chunks and ballistic-limit campaigns are lists of
independent tasks.  :func:`run_tasks` runs them and yields ``(index, result)`` as
they finish, so callers can draw progress and keep results in order.
"""

from __future__ import annotations

import multiprocessing
import os
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from typing import Any, Literal

Scheduler = Literal["serial", "processes", "dask"]


def run_tasks(fn: Callable[[Any], Any], tasks: Sequence[Any], *, scheduler: Scheduler = "processes",
              workers: int | None = None, address: str | None = None) -> Iterator[tuple[int, Any]]:
    """Yield ``(i, fn(tasks[i]))`` for every task, in completion order.

    ``serial``: in this process, in order (for work that is already parallel
    inside, such as the numba particle kernels).  ``processes``: a local process
    pool of ``workers`` (default: all cores).  ``dask``: ``address`` of an existing
    scheduler, or None / ``"local"`` for a LocalCluster of ``workers`` processes.
    ``fn`` must be importable by name (a module-level function) for the pools.
    """
    if scheduler == "serial":
        for i, task in enumerate(tasks):
            yield i, fn(task)
    elif scheduler == "processes":
        # spawn, not fork: a process that has run numba's OpenMP kernels cannot fork safely
        with ProcessPoolExecutor(max_workers=workers or os.cpu_count(),
                                 mp_context=multiprocessing.get_context("spawn")) as pool:
            futures = {pool.submit(fn, t): i for i, t in enumerate(tasks)}
            for fut in as_completed(futures):
                yield futures[fut], fut.result()
    elif scheduler == "dask":
        yield from _on_dask(fn, tasks, workers, address)
    else:
        raise ValueError(f"unknown scheduler {scheduler!r}")


def _on_dask(fn, tasks, workers, address) -> Iterator[tuple[int, Any]]:
    from dask.distributed import Client, LocalCluster
    from dask.distributed import as_completed as dask_completed

    cluster = None
    if address in (None, "local"):
        cluster = LocalCluster(n_workers=workers or os.cpu_count(), threads_per_worker=1, processes=True,
                               dashboard_address=None)
    try:
        with Client(cluster if cluster is not None else address) as client:
            futures = {client.submit(fn, t, pure=False): i for i, t in enumerate(tasks)}
            for fut in dask_completed(futures):
                yield futures[fut], fut.result()
    finally:
        if cluster is not None:
            cluster.close()
