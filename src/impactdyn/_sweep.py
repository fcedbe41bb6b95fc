"""Families of cases run as independent tasks: one helper for beam sweeps, Whipple campaigns and limits.

:func:`case_variants` validates every variant of a base case before any work, so a bad
value stops the sweep with a message naming it; :func:`run_all` runs the tasks through
:func:`impactdyn._parallel.run_tasks` and returns their results in task order.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from contextlib import closing
from typing import Any

from impactdyn._config import set_dotted, validate
from impactdyn._parallel import Scheduler, run_tasks


def case_variants(model, raw: dict, variants: Sequence[Mapping[str, Any]], source: str = "<case>") -> list:
    """``model`` validated from ``raw`` with each variant's dotted keys set (``{"a.b": 1.0}``)."""
    cases = []
    for variant in variants:
        data = raw
        for key, value in variant.items():
            data = set_dotted(data, key, value)
        label = ", ".join(f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v}" for k, v in variant.items())
        cases.append(validate(model, data, source=f"{source} [{label}]"))
    return cases


def run_all(fn: Callable[[Any], Any], tasks: Sequence[Any], *, scheduler: Scheduler = "processes",
            workers: int | None = None, address: str | None = None,
            on_result: Callable[[int, Any], None] | None = None) -> list:
    """``[fn(t) for t in tasks]``, run as :func:`run_tasks` schedules them; ``on_result(i, result)``
    is called as each finishes (write its files, advance a progress bar).  An exception, here or
    in ``on_result``, stops the tasks still running before it goes on."""
    results: list = [None] * len(tasks)
    if not tasks:  # a resumed family with nothing left: start no pool or cluster
        return results
    with closing(run_tasks(fn, tasks, scheduler=scheduler, workers=workers, address=address)) as finished:
        for i, result in finished:
            results[i] = result
            if on_result is not None:
                on_result(i, result)
    return results
