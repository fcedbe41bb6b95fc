"""Rich progress bars fed by a ``progress(stage, done, total)`` callback (one bar per stage)."""

from __future__ import annotations


def progress_bars(counts: bool = True):
    """A rich progress display and the ``progress(stage, done, total)`` callback feeding it.

    ``counts``: show "done/total" (whole numbers: particles); otherwise a percentage
    (stages that report simulated time).
    """
    from rich.progress import (BarColumn, MofNCompleteColumn, Progress, TaskProgressColumn, TextColumn,
                               TimeElapsedColumn)

    done_column = MofNCompleteColumn() if counts else TaskProgressColumn()
    bar = Progress(TextColumn("{task.description:<10}"), BarColumn(), done_column, TimeElapsedColumn(),
                   transient=False)
    tasks: dict[str, int] = {}

    def update(stage: str, done: float, total: float) -> None:
        if stage not in tasks:
            tasks[stage] = bar.add_task(stage, total=max(total, 1))
        bar.update(tasks[stage], completed=done if total else 1, total=max(total, 1))

    return bar, update
