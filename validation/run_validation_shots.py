"""Run the wall stage's validation shots (issue 11) and score the simulated verdicts against the tests.

The shots are those :mod:`select_validation_shots` picks by its rule, fixed before any was
run.  Each one's case is :func:`impactdyn.whipple.database_shot_case` of the shot on the
``table2_7a`` example (the run folder's ``case.toml`` is the case run): the shot's projectile,
bumper and wall put in, and nothing else changed but what the geometry forces, by the rules in
that function's module (wall extent with the stand-off, SPH spacing with the diameter, arrival
window with the stand-off), written before the runs.  (The window's rule was added after the
first run: with the example's 25 µs the 20.32-cm shot B31 deposited nothing — a set-up error,
not a choice.)

Each shot runs the full pipeline into ``OUT/<line>_<shot>`` (every file kept, so that
``--from-wall`` can rerun only the wall stage after a wall-solver change); the table, the
scores (accuracy, false-safe rate = perforated shots called safe / perforated shots, false
alarms) of the simulated verdicts beside the JSC equation's (the package default, on the same
shots), and ``scores.json`` go to OUT; each row keeps the wall's failed mass by the criterion
that failed it (``failed_mass_by_cause_g``).  No constant of the pipeline is calibrated on them.

    OMP_WAIT_POLICY=passive python validation/run_validation_shots.py -o OUT [--set N] [--only LINE ...]
        [--from-wall] [--score-only] [--wall-model MODEL] [--model-option KEY=VALUE ...]
        [--wall-option KEY=VALUE ...] [--wall-refinement R [--thickness-only]]

``--set``: the validation set of :func:`select_validation_shots.select` (1, the default, or 2, the
disjoint set that decides the default wall model).

``--wall-model``: score the finished shots with the wall stage rerun under another material
model (:func:`impactdyn.whipple.rerun_wall`; nothing is written but
``scores_MODEL.json``); with ``--wall-refinement R`` the rerun wall is refined R× through the
thickness and in the plane (the shots' cases use 1), into ``scores_MODEL_Rx.json``, or with
``--thickness-only`` through the thickness alone, into ``scores_MODEL_tRx.json``.
``--model-option KEY=VALUE`` (repeatable, as in ``verification/wall_convergence.py``) reruns the wall with that
change to its material model (the case's model unless ``--wall-model`` names another), into
``scores_[MODEL_]KEY-VALUE.json``; ``--wall-option KEY=VALUE`` the same with a change to the
wall solver's options (:class:`impactdyn.wall.WallOptions`, e.g. ``max_time_us=300``).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from select_validation_shots import select

from impactdyn._config import parse_assignment
from impactdyn.ble import read_database
from impactdyn.whipple import WhippleCase, database_shot, database_shot_case, rerun_wall, run_whipple

FAILED_VERDICTS = ("perforation", "detached spall")


def scores(rows: list[dict], key: str) -> dict:
    n_p = sum(r["perforated"] for r in rows)
    n_np = len(rows) - n_p
    called = [r[key] in FAILED_VERDICTS for r in rows]
    correct = sum(c == r["perforated"] for c, r in zip(called, rows))
    false_safe = sum((not c) and r["perforated"] for c, r in zip(called, rows))
    false_alarm = sum(c and not r["perforated"] for c, r in zip(called, rows))
    return {"n": len(rows), "accuracy": correct / len(rows), "false_safe": false_safe,
            "false_safe_rate": false_safe / n_p if n_p else None, "false_alarm": false_alarm,
            "false_alarm_rate": false_alarm / n_np if n_np else None}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--out", required=True, type=Path)
    ap.add_argument("--set", type=int, default=1, help="validation set (select_validation_shots.py)")
    ap.add_argument("--only", type=int, nargs="*", help="pyBLOSSUM line numbers to run (default: all 12)")
    ap.add_argument("--from-wall", action="store_true", help="rerun the wall stage on existing shot folders")
    ap.add_argument("--score-only", action="store_true", help="score the shot folders that exist")
    ap.add_argument("--wall-model", help="rescore with the wall stage rerun under this material model")
    ap.add_argument("--model-option", type=parse_assignment, action="append", default=[], metavar="KEY=VALUE",
                    help="rescore with the wall stage rerun with this change to its material model")
    ap.add_argument("--wall-option", type=parse_assignment, action="append", default=[], metavar="KEY=VALUE",
                    help="rescore with the wall stage rerun with this change to its solver options")
    ap.add_argument("--wall-refinement", type=int, default=1, help="with --wall-model: refine the rerun wall R times")
    ap.add_argument("--thickness-only", action="store_true", help="with --wall-refinement: refine the thickness alone")
    args = ap.parse_args()
    db = read_database()
    shots = select(args.set)
    args.out.mkdir(parents=True, exist_ok=True)
    # the wall stage rerun on the finished shots under these changes, or the shots' own results
    rerun = bool(args.wall_model or args.model_option or args.wall_option)
    changes = {"refinement_thickness": args.wall_refinement,
               "refinement_plane": 1 if args.thickness_only else args.wall_refinement,
               **({"material_model": args.wall_model} if args.wall_model else {}), **dict(args.wall_option)}
    rows = []
    for shot in shots:
        folder = args.out / f"{shot['line']}_{shot['shot_id']}"
        run = not (args.score_only or rerun) and (args.only is None or shot["line"] in args.only)
        if run:
            case = WhippleCase.model_validate(database_shot_case(database_shot(shot["line"], db)))
            tick = time.perf_counter()
            run_whipple(case, folder, start="wall" if args.from_wall else "shield", force=True)
            print(f"line {shot['line']} {shot['shot_id']}: {time.perf_counter() - tick:.0f} s", flush=True)
        summary_file = folder / "summary.json"
        if not summary_file.exists():
            continue
        s = json.loads(summary_file.read_text())
        if rerun:
            result = rerun_wall(folder, dict(args.model_option), **changes)
            wall = {"verdict": result.verdict, **result.measures}
        else:
            wall = s["wall"]
        rows.append({**{k: shot[k] for k in ("line", "source", "shot_id", "perforated", "diameter_cm",
                                             "velocity_km_s", "obliquity_deg", "bumper_thickness_cm",
                                             "wall_thickness_cm", "spacing_cm")},
                     "simulated": wall["verdict"], "jsc": s["ble"]["verdict"],
                     "jsc_threshold_cm": s["ble"]["threshold_cm"], "crater_depth_ratio": wall["crater_depth_ratio"],
                     "rear_bulge_cm": wall["rear_bulge_cm"], "failed_mass_g": wall["failed_mass_g"],
                     "eroded_mass_g": wall["eroded_mass_g"], "failed_mass_by_cause_g": wall.get("failed_mass_by_cause_g"),
                     "hourglass_to_internal": wall["hourglass_to_internal"],
                     "end_time_us": wall["end_time_us"], "ended_by": wall.get("ended_by"),
                     "peak_rear_bulge_cm": wall.get("peak_rear_bulge_cm"), "wall_time_s": s["wall_time_s"]})
    for r in rows:
        print(f"{r['line']:4d} {r['shot_id']:<10} {'P ' if r['perforated'] else 'NP'} d {r['diameter_cm']:.3f} "
              f"V {r['velocity_km_s']:.2f} θ {r['obliquity_deg']:>4g}  sim {r['simulated']:<15} "
              f"JSC {r['jsc']:<15} (d_c {r['jsc_threshold_cm']:.3f})  crater/t {r['crater_depth_ratio']:.3f} "
              f"bulge {r['rear_bulge_cm']:.3f}  hg/int {r['hourglass_to_internal']:.3f}"
              + "".join(f"  {k} {v:.3g} g" for k, v in (r["failed_mass_by_cause_g"] or {}).items() if v > 0))
    if rows:
        result = {"rows": rows, "simulated": scores(rows, "simulated"), "jsc": scores(rows, "jsc")}
        for key in ("simulated", "jsc"):
            print(key, json.dumps(result[key]))
        parts = ([args.wall_model] if args.wall_model else []) + [
            f"{k}-{json.dumps(v)}" for k, v in args.model_option + args.wall_option]
        if args.wall_refinement != 1:
            parts.append(f"{'t' if args.thickness_only else ''}{args.wall_refinement}x")
        name = "_".join(["scores", *parts]) + ".json"
        (args.out / name).write_text(json.dumps(result, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
