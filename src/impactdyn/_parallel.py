"""Independent tasks on local cores or on a Dask cluster: one mapper for every caller.

Beam sweeps, DC3D particle chunks and ballistic-limit campaigns are lists of
independent tasks.  :func:`run_tasks` runs them and yields ``(index, result)`` as
they finish, so callers can draw progress and keep results in order; :func:`tasks_started`
hands them to the pool at once and collects them later, so the caller can work beside them.

When the caller stops early (Ctrl-C, SIGTERM, a task's exception, or the caller leaving the
loop) the queued tasks are cancelled and the running ones stopped before the exception
goes on: the local pool's workers are terminated (a pool left to shut down normally would
first run every queued task), a Dask cluster's tasks are cancelled and a LocalCluster closed.
No worker process outlives the call (:mod:`impactdyn._interrupt`).
"""

from __future__ import annotations

import logging
import multiprocessing
import os
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, as_completed, wait
from typing import Any, Literal

from impactdyn._interrupt import ignore_interrupts, shielded

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
    with tasks_started(fn, tasks, scheduler=scheduler, workers=workers, address=address) as finished:
        yield from finished


@contextmanager
def tasks_started(fn: Callable[[Any], Any], tasks: Sequence[Any], *, scheduler: Scheduler = "processes",
                  workers: int | None = None, address: str | None = None,
                  caller_helps: bool = False) -> Iterator[Iterator[tuple[int, Any]]]:
    """:func:`run_tasks`'s tasks handed to the pool or cluster on entering the block, so that this process
    can work beside them; the block gets the ``(i, result)`` iterator that collects them (``serial`` tasks run
    as it is read).  With ``caller_helps``, reading it also runs here, last first, the local pool's tasks that
    no worker has taken yet, so that the caller, its own work done, takes a worker's share (the pool feeds its
    workers one task ahead, and those it keeps).  Leaving the block before the last result (an exception,
    Ctrl-C) stops the tasks."""
    if scheduler == "serial":
        yield ((i, fn(task)) for i, task in enumerate(tasks))
    elif scheduler == "processes":
        with _on_processes(fn, tasks, workers, caller_helps) as finished:
            yield finished
    elif scheduler == "dask":
        with _on_dask(fn, tasks, workers, address) as finished:
            yield finished
    else:
        raise ValueError(f"unknown scheduler {scheduler!r}")


def hold_threads(threads: int) -> None:
    """Let this process's numba kernels use ``threads`` threads (at least one, at most numba's pool)."""
    import numba

    numba.set_num_threads(max(1, min(threads, numba.config.NUMBA_NUM_THREADS)))


#: Seconds a terminated worker is given to end before it is killed.
STOP_GRACE_S = 5.0


@contextmanager
def _on_processes(fn, tasks, workers, caller_helps=False) -> Iterator[Iterator[tuple[int, Any]]]:
    # spawn, not fork: a process that has run numba's OpenMP kernels cannot fork safely
    pool = ProcessPoolExecutor(max_workers=workers or os.cpu_count(), initializer=ignore_interrupts,
                               mp_context=multiprocessing.get_context("spawn"))
    collected = []

    def finished(futures):
        for fut in as_completed(futures):
            yield futures[fut], fut.result()
        collected.append(True)

    def helped(futures):
        waiting = list(futures)
        while waiting:
            for fut in [f for f in waiting if f.done()]:
                waiting.remove(fut)
                yield futures[fut], fut.result()
            untaken = next((f for f in reversed(waiting) if f.cancel()), None)
            if untaken is not None:
                waiting.remove(untaken)
                yield futures[untaken], fn(tasks[futures[untaken]])
            elif waiting:
                wait(waiting, return_when=FIRST_COMPLETED)
        collected.append(True)

    try:
        futures = {pool.submit(fn, t): i for i, t in enumerate(tasks)}
        yield helped(futures) if caller_helps else finished(futures)
    finally:
        if collected:
            pool.shutdown(wait=True)
        else:
            with shielded():
                _stop_pool(pool)


def _stop_pool(pool: ProcessPoolExecutor) -> None:
    """Cancel the queued tasks and end the workers now.  The executor has no public way to end
    running tasks before Python 3.14 (``terminate_workers``), so its ``_processes`` are ended here.

    The pool's manager thread reaps the workers it sees die, racing with the joins here; it is
    joined last, so that on return every worker is reaped and known to be (``active_children``
    listed one as alive a moment after it had been reaped by that thread)."""
    processes = list((pool._processes or {}).values())
    manager = pool._executor_manager_thread
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        if process.is_alive():
            process.terminate()
    for process in processes:
        process.join(STOP_GRACE_S)
        if process.is_alive():
            process.kill()
            process.join()
    if manager is not None:
        manager.join(STOP_GRACE_S)


@contextmanager
def _on_dask(fn, tasks, workers, address) -> Iterator[Iterator[tuple[int, Any]]]:
    from dask.distributed import Client, LocalCluster
    from dask.distributed import as_completed as dask_completed

    cluster = None
    if address in (None, "local"):
        # the cluster is the command's private machinery: a failure that matters reaches the command as
        # an exception (a task's own, KilledWorker); its logs only add noise, above all when a stop tears
        # it down mid-task (cancelled tasks, heartbeats to a scheduler already gone)
        cluster = LocalCluster(n_workers=workers or os.cpu_count(), threads_per_worker=1, processes=True,
                               dashboard_address=None, silence_logs=logging.CRITICAL)
    try:
        with Client(cluster if cluster is not None else address) as client:
            if cluster is not None:  # our workers leave Ctrl-C to us, as the local pool's do
                client.run(ignore_interrupts)
            futures = {client.submit(fn, t, pure=False): i for i, t in enumerate(tasks)}
            collected = []

            def finished():
                for fut in dask_completed(futures):
                    yield futures[fut], fut.result()
                collected.append(True)

            try:
                yield finished()
            finally:
                if not collected:
                    # on a cluster that is not ours, cancelling is all we may do to its workers
                    with shielded():
                        client.cancel(list(futures), force=True)
    finally:
        if cluster is not None:
            with shielded():
                cluster.close()
