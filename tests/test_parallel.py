"""The local workers share the cores among their compiled kernels' threads (``impactdyn._parallel``)."""

import os

import numba
import pytest

from impactdyn._parallel import kernel_threads, run_tasks


def _kernel_threads_here(_task) -> int:
    return numba.get_num_threads()


@pytest.mark.parametrize("workers, cores, threads", [(1, 2, 2), (2, 2, 1), (3, 2, 1), (2, 16, 8), (3, 16, 5)])
def test_each_worker_takes_its_share_of_the_cores(monkeypatch, workers, cores, threads):
    monkeypatch.setattr(os, "cpu_count", lambda: cores)
    assert kernel_threads(workers) == threads


@pytest.mark.parametrize("scheduler", ["processes", "dask"])
def test_workers_kernels_run_on_their_share_of_the_cores(scheduler):
    """Two workers: each one's kernels run on half the cores (numba's default would give each all of
    them, twice as many threads as cores)."""
    found = dict(run_tasks(_kernel_threads_here, [0, 1, 2, 3], scheduler=scheduler, workers=2))
    assert set(found.values()) == {min(kernel_threads(2), numba.config.NUMBA_NUM_THREADS)}
