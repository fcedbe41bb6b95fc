"""When does an unholed wall stop changing its verdict?  The run's own wall of a finished run, run again
to the ceiling and sampled every microsecond: what an earlier end would save, and what it would change.

A wall that is not holed runs to ``max_time_us`` (100 µs): after the last arrival it rings elastically,
at a step shortened by its distorted elements, intact and failed.  For each RUN (a finished
``impactdyn whipple run`` folder, lean is enough: its ``debris/debris.h5``) this reruns the wall stage
exactly as the pipeline does (the case's wall options and material) and, every ``--every`` µs, records
the steps taken, the damaged elements (failed or eroded), the plastic work, the summed ductile damage and
the rear bulge.  Printed per run, as JSON lines (and to ``--out``):

* ``t_last_arrival``: the last deposition record (the load's last arrival); ``t_impulse_99``,
  ``t_impulse_999``: when 99 % and 99.9 % of the load's impulse magnitude has arrived;
* ``t_last_new_damaged``: the last sample at which the damaged count grew;
* ``t_plastic_999``: the first sample with 99.9 % of the final plastic work;
* ``t_damage_999``, ``t_spall_damage_999``: the first sample with 99.9 % of the final summed ductile
  (Johnson–Cook) and spall (Tuler–Butcher) damage;
* ``initial_step_us``, ``steps_at_initial_step``: the run's first step (the Courant factor times the
  smallest element's stable step) and the steps the run would take at it throughout;
* ``steps_intact_step``: the steps the run would take had its step been set by the intact elements
  alone (failed rubble out of the step), an estimate from the smallest intact element's step sampled;
* ``t_end_tau``: for each hold τ in ``--holds``, the first sample t ≥ last arrival + τ over whose
  preceding τ µs no element became damaged and the plastic work grew by less than 0.1 % (a candidate
  rule, deciding nothing), with the fraction of the run's steps taken by then and the damaged count
  and bulge there, beside the ceiling's.

    python studies/wall-end/unholed_wall_end.py RUN [RUN ...] [--every 1] [--holds 5 10 20] [--ceiling US]
        [--out FILE]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from impactdyn.debris import read_deposition
from impactdyn.wall import wall_solver
from impactdyn.wall._state import DAMAGE, DT_E, SPALL_DAMAGE
from impactdyn.whipple import load_whipple_case


def sampled_wall(run: Path, every: float, ceiling: float | None = None) -> dict[str, np.ndarray | float]:
    """The run's wall stage again, sampled every ``every`` µs to the ceiling (the pipeline's solver,
    :func:`impactdyn.wall.wall_solver`; ``ceiling``: another ``max_time_us``)."""
    case = load_whipple_case(run / "case.toml")
    wall, deposition, _ = read_deposition(run / "debris" / "debris.h5")
    options = case.wall_options
    if ceiling is not None:
        options = options.model_copy(update={"max_time_us": ceiling})
    solver = wall_solver(wall, deposition, case.wall.material, options)
    load = solver.load
    rows = []
    t = solver.time
    while True:
        solver.update_categories()
        es = solver.es
        intact = ~(solver.failed | solver.eroded)
        rows.append((solver.time, solver.steps, np.count_nonzero(~intact),
                     solver.energies()["plastic"], float(es[:, DAMAGE].sum()), solver.surface()[0],
                     float(es[:, SPALL_DAMAGE].sum()), float(es[intact, DT_E].min())))
        if t >= options.max_time_us or solver.through_since is not None:
            break
        t = min(t + every, options.max_time_us)
        solver.advance(t)
    cols = np.array(rows).T
    arrived = np.cumsum(np.linalg.norm(load.impulse, axis=1))     # the records are in arrival order
    arrived /= arrived[-1]
    return {"t_impulse_99": float(load.time[np.argmax(arrived >= 0.99)]),
            "t_impulse_999": float(load.time[np.argmax(arrived >= 0.999)]),
            "time": cols[0], "steps": cols[1], "damaged": cols[2], "plastic": cols[3], "damage": cols[4],
            "bulge": cols[5], "spall_damage": cols[6], "dt_intact": cols[7], "courant": options.courant,
            "initial_step": options.courant * solver.dt_element0, "t_start": float(load.time[0]),
            "t_last_arrival": float(load.time.max()),
            "holed": solver.through_since is not None, "n_elements": solver.mesh.n_elements}


def first_at(t: np.ndarray, reached: np.ndarray) -> float | None:
    return float(t[np.argmax(reached)]) if reached.any() else None


def steps_at_intact_step(s: dict) -> int:
    """The steps the run would have taken had its step been set by the intact elements alone (failed ones
    out of the step, as mass scaling of the rubble would leave it), each sampling interval at the smallest
    intact element's step at its start: an estimate."""
    t, dt = s["time"], s["courant"] * s["dt_intact"]
    return int(round(np.sum(np.diff(t) / dt[:-1]))) + 1


def summary(name: str, s: dict, holds: list[float]) -> dict:
    t, steps, damaged, plastic, damage, bulge = (s[k] for k in ("time", "steps", "damaged", "plastic", "damage",
                                                                "bulge"))
    grew = np.flatnonzero(np.diff(damaged) > 0)
    out = {"run": name, "n_elements": s["n_elements"], "holed": s["holed"], "t_end": float(t[-1]),
           "steps": int(steps[-1]), "damaged_end": int(damaged[-1]), "bulge_end_cm": float(bulge[-1]),
           "initial_step_us": s["initial_step"],
           "steps_at_initial_step": int(round((t[-1] - s["t_start"]) / s["initial_step"])),
           "steps_intact_step": steps_at_intact_step(s),
           "t_last_arrival": s["t_last_arrival"], "t_impulse_99": s["t_impulse_99"],
           "t_impulse_999": s["t_impulse_999"],
           "t_last_new_damaged": float(t[grew[-1] + 1]) if grew.size else None,
           "t_plastic_999": first_at(t, plastic >= 0.999 * plastic[-1]),
           "t_damage_999": first_at(t, damage >= 0.999 * damage[-1]) if damage[-1] > 0 else None,
           "t_spall_damage_999": (first_at(t, s["spall_damage"] >= 0.999 * s["spall_damage"][-1])
                                  if s["spall_damage"][-1] > 0 else None)}
    for tau in holds:
        end = None
        for i, ti in enumerate(t):
            if ti < s["t_last_arrival"] + tau:
                continue
            j = int(np.searchsorted(t, ti - tau))
            if damaged[i] == damaged[j] and plastic[i] - plastic[j] <= 1e-3 * plastic[i]:
                end = i
                break
        out[f"hold_{tau:g}"] = None if end is None else {
            "t_end": float(t[end]), "step_fraction": float(steps[end] / steps[-1]),
            "damaged": int(damaged[end]), "bulge_cm": float(bulge[end]),
            "plastic_fraction": float(plastic[end] / plastic[-1]) if plastic[-1] > 0 else None}
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", nargs="+", type=Path)
    ap.add_argument("--every", type=float, default=1.0)
    ap.add_argument("--holds", type=float, nargs="+", default=[5.0, 10.0, 20.0])
    ap.add_argument("--ceiling", type=float, help="another max_time_us than the case's (µs)")
    ap.add_argument("--out", type=Path)
    args = ap.parse_args()
    for run in args.runs:
        line = json.dumps(summary(run.name, sampled_wall(run, args.every, args.ceiling), args.holds))
        print(line, flush=True)
        if args.out:
            with args.out.open("a") as f:
                f.write(line + "\n")


if __name__ == "__main__":
    main()
