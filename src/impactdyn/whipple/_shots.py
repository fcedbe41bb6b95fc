"""One shot of a family (campaign or limit search): a full Whipple run, then a lean run folder.

A Table 2 run folder holds ~530 MB with ``--keep all`` (every debris particle's states, ParaView
files, the LS-DYNA deck's load curves) and ~50 MB as a lean ``whipple run`` (:mod:`._pipeline`);
a family of dozens of shots keeps by default even less, only what a user reads afterwards
(:data:`impactdyn.whipple._stages.LEAN_KEEP`): the summary and report, the stage records, the plots, the DCPOST table, the
wall's measures and pictures: a few MB per shot.  A lean shot does not
write what it would delete (:data:`LEAN_OUTPUT`: the decks and the ParaView files, a
quarter of a Table 2 shot's time), so it is faster as well as smaller.
``keep_all`` keeps everything and writes the case's own outputs.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from impactdyn.whipple._stages import LEAN_OUTPUT, prune_run

@dataclass(frozen=True)
class Shot:
    """One shot: its case, its run folder, the numba threads it may use and whether to keep every file."""

    case: object
    folder: Path
    threads: int
    keep_all: bool = False


def shot_name(velocity_km_s: float, diameter_cm: float) -> str:
    return f"V{velocity_km_s:g}_d{diameter_cm:g}"


def shot_variant(base, velocity_km_s: float, diameter_cm: float) -> dict:
    """The dotted keys of one shot of a family made from the case ``base``: its speed and
    diameter, and the settings that must follow them so that every shot is resolved and timed
    as the base case is:

    * the SPH spacing, scaled down with a smaller diameter (the projectile keeps at least the
      base case's particles across);
    * the hand-off time and the debris arrival window (``shield.handoff_us``,
      ``filter.t_cut_us``), stretched for a slower shot by V_base/V: the projectile's passage
      through the bumper and the cloud's flight to the wall take 1/V as long.  (Without it a
      4-km/s shot of the 7-km/s example kept its 25-µs window and nothing reached the wall.)

    The base case's ``[test_shot]``, if any, is dropped: a family's shot at another speed or diameter is
    not the test, and its report must not set the test's outcome beside its verdict.
    """
    slower = max(1.0, base.projectile.velocity_km_s / velocity_km_s)
    return {"projectile.velocity_km_s": float(velocity_km_s), "projectile.diameter_cm": float(diameter_cm),
            "shield.spacing_cm": float(base.shield.spacing_cm * min(1.0, diameter_cm / base.projectile.diameter_cm)),
            "shield.handoff_us": float(base.shield.handoff_us * slower),
            "filter.t_cut_us": float(base.filter.t_cut_us * slower), "test_shot": None}


def shot_workers(scheduler: str, workers: int | None, n_shots: int) -> int:
    """Shots run at once: one when serial, else ``workers`` (default: one per core), at most ``n_shots``."""
    if scheduler == "serial":
        return 1
    return max(1, min(workers or os.cpu_count() or 1, n_shots))


def threads_per_shot(n_workers: int) -> int:
    """The cores of this machine shared among ``n_workers`` concurrent shots (at least one each)."""
    return max(1, (os.cpu_count() or 1) // max(1, n_workers))


def shot_tasks(cases: list, folders: list[Path], scheduler: str, workers: int | None, keep_all: bool) -> list[Shot]:
    """The :class:`Shot` of each case into its folder, the cores shared among the shots run at once."""
    threads = threads_per_shot(shot_workers(scheduler, workers, len(cases)))
    return [Shot(case, folder, threads, keep_all) for case, folder in zip(cases, folders)]


def run_shot(shot: Shot) -> dict:
    """Run the shot's pipeline into its folder (lean unless ``keep_all``); returns its summary."""
    from impactdyn._parallel import hold_threads
    from impactdyn.whipple._pipeline import run_whipple

    hold_threads(shot.threads)
    case = shot.case
    if not shot.keep_all:
        case = case.model_copy(update={"output": case.output.model_copy(update=LEAN_OUTPUT)})
    summary = run_whipple(case, shot.folder, keep="all" if shot.keep_all else "lean")
    if not shot.keep_all:
        prune_run(shot.folder)
    return summary
