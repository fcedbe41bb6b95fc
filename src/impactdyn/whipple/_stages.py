"""The contract of the Whipple stages: their order, what each depends on, and their records.

The pipeline (:mod:`._pipeline`) runs the stages and the report (:mod:`._report`)
reads their records; both import this module and not each other.

Each stage writes ``<stage>/stage.json`` into the run folder: its numbers, its wall
time and :func:`settings`, the case tables its result depends on.  A restart from a
later stage reuses an earlier stage only if its recorded settings equal the case's.
"""

from __future__ import annotations

import fnmatch
import json
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

from impactdyn._errors import InputError
from impactdyn._runfolder import FolderWriter
from impactdyn.whipple._case import WhippleCase

STAGES = ("shield", "binning", "debris", "wall", "draws", "decks", "report")

#: Simulated verdicts that count as a failed rear wall (JSC test practice).
FAILED_VERDICTS = ("perforation", "detached spall")

#: Case tables each stage's result depends on (cumulative: a stage depends on the ones before it), or a
#: single key ``table.key`` of a table that an earlier stage reads, which that stage then does not depend on
#: (the draws' count changes no earlier stage: a run folder from before the key restarts from any stage).
#: ``compute`` is left out: where the particle chunks run does not change the result.
DEPENDS = {
    "shield": ("materials", "projectile", "bumper", "shield"),
    "binning": ("binning",),
    "debris": ("wall", "debris", "filter", "integrator", "legacy"),
    "wall": ("wall_solver",),
    "draws": ("shield.fragment_draws",),
    "decks": ("output",),
    "report": (),
}

#: How much of its output a run keeps (``--keep``): "lean" (default) what the report, ParaView and a
#: restart from any stage need; "all" every array besides (:mod:`._pipeline`).
KEEP = ("lean", "all")

#: ``progress(stage, done, total)``: the shield stage reports simulated µs, the debris
#: stage its sub-stages ``seed``, ``propagate`` and ``deposit``, the others 0 then 1 of 1.
Progress = Callable[[str, float, float], None]


def settings(case, stage: str) -> dict:
    """The case tables and keys ``stage``'s result depends on, as plain data (cumulative; :data:`DEPENDS`)."""
    upto = STAGES[:STAGES.index(stage) + 1]
    data = case.model_dump(mode="json")
    later = [name.split(".") for names in DEPENDS.values() for name in names if "." in name]

    def value(name: str):
        if "." in name:
            table, key = name.split(".")
            return data[table][key]
        if data[name] is None:
            return None
        return {k: v for k, v in data[name].items() if [name, k] not in later}

    # a case without its own materials records none, as the runs before a case could define them did
    return {name: value(name) for s in upto for name in DEPENDS[s] if data[name.split(".")[0]] is not None}


def read_stage(folder: Path, stage: str) -> dict:
    """The ``stage.json`` record of ``stage`` in a run folder."""
    path = Path(folder) / stage / "stage.json"
    if not path.is_file():
        raise InputError(f"{folder}: has no completed {stage} stage ({path} missing); run from an earlier stage")
    return json.loads(path.read_text())


@dataclass
class StageContext:
    """What a stage function gets: the case, the staging folder, the progress callback, how much
    to keep (:data:`KEEP`) and the further draws' ``(i, outcome)`` iterator, which the draws stage collects
    (:func:`impactdyn.whipple._pipeline.further_draws`; None where no draws stage follows)."""

    case: WhippleCase
    folder: FolderWriter
    progress: Progress | None
    keep: str = "lean"
    further_draws: Iterator[tuple[int, dict]] | None = None

    @property
    def lean(self) -> bool:
        return self.keep == "lean"

    def report(self, stage: str, done: float, total: float) -> None:
        if self.progress is not None:
            self.progress(stage, done, total)


#: Files a lean shot folder keeps (glob patterns relative to the run folder).
LEAN_KEEP = ("summary.json", "report.html", "case.toml", "plots/*", "*/stage.json", "*/summary.json",
             "*/plots/*", "debris/areal_density.csv", "debris/config.resolved.toml", "wall/*.json")


#: The case's ``[output]`` settings of a lean shot: no file that :data:`LEAN_KEEP` drops.
LEAN_OUTPUT = {"vtk": False, "lsdyna_deck": False, "dyna3d_deck": False}


def prune_run(folder: Path) -> None:
    """Delete every file of a run folder that :data:`LEAN_KEEP` does not name, and the emptied folders."""
    folder = Path(folder)
    for path in sorted(folder.rglob("*"), reverse=True):
        rel = path.relative_to(folder).as_posix()
        if path.is_file() and not any(fnmatch.fnmatchcase(rel, pattern) for pattern in LEAN_KEEP):
            path.unlink()
        elif path.is_dir() and not any(path.iterdir()):
            path.rmdir()
