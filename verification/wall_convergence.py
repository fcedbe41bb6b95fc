"""The wall stage's mesh and load-spread study on a finished Whipple run (issue 11 acceptance).

Reruns only the wall solver on the run's deposition (``debris/debris.h5``) with the case's
wall settings, then with each variant: 2× refinement through the thickness and in the plane,
and each other load spread (:data:`impactdyn.wall.SPREADS`); ``--split`` adds the refinement
through the thickness alone and in the plane alone, ``--thickness-series N`` the refinements
2 … N through the thickness alone, and ``--deposition-depth D`` sets the case's
``deposition_depth_cm`` on every row (the impulses as a body force over D cm, :mod:`impactdyn.wall._load`).  Prints, for every variant, the verdict,
crater depth / wall thickness, rear bulge, failed and eroded mass, hourglass / internal energy,
the work of the load and the plastic work, the failed mass by the criterion that failed it, and
the change of bulge, crater depth and load work against the case's own settings; ``--json FILE``
keeps them.  ``--failure-switches`` (Johnson–Cook walls) adds, for the case's mesh and the
refined one, the rows with the JC ductile damage off, the spall criterion off, both off, and the
damage increments at the fracture-strain floor off (``damage_at_floor=False``): which failure
criterion makes a verdict, and whether the response without it converges.  ``--model-option
KEY=VALUE`` (repeatable; VALUE read as JSON, e.g. ``damage_at_floor=false``) changes the material
model of every row (:func:`impactdyn.wall.wall_model` keywords).  The acceptance: the same verdict
on every row, and bulge and crater depth within 10 % at 2× refinement; a crater less than one
element layer deep on both meshes (``crater_resolved`` false on both) is "not resolved, the same",
since neither mesh can show its depth, and the 10 % holds where it is resolved on either.

The work of the load is the energy the impulses bring, Σ I·½(v⁻ + v⁺): for an impulse on a node
at rest |I|²/2m, so it grows as the nodes under the load get lighter — the reason the crater
depth of an impulsively loaded wall is not a mesh-converged measure (BENCHMARKS.md).

    OMP_WAIT_POLICY=passive python verification/wall_convergence.py RUN_FOLDER [--json FILE]
        [--refinement 2] [--no-spreads] [--split] [--thickness-series N] [--deposition-depth D]
        [--failure-switches] [--model-option KEY=VALUE ...]
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from impactdyn._config import parse_assignment
from impactdyn.wall import SPREADS
from impactdyn.whipple import load_whipple_case, rerun_wall

KEYS = ("crater_depth_ratio", "crater_resolved", "rear_bulge_cm", "peak_rear_bulge_cm", "failed_mass_g", "eroded_mass_g",
        "failed_mass_by_cause_g", "hourglass_to_internal", "end_time_us", "ended_by", "steps")

#: The rows of ``--failure-switches``: Johnson–Cook model keywords.
FAILURE_SWITCHES = {"no JC damage": {"damage": None}, "no spall": {"spall": False},
                    "no damage, no spall": {"damage": None, "spall": False},
                    "no JC damage at the floor": {"damage_at_floor": False}}


#: The largest change of a resolved crater depth or of the bulge at 2× refinement (the acceptance).
CONVERGED_CHANGE = 0.10


def _crater_agreement(row: dict, reference: dict, change: float) -> str:
    """The crater depth of ``row`` against ``reference``'s: "not resolved, the same" when neither mesh
    resolves it (less than one element layer deep on both), else its change and whether it is within
    :data:`CONVERGED_CHANGE`."""
    if not (row["crater_resolved"] or reference["crater_resolved"]):
        return "not resolved on either mesh, the same"
    return f"{change:+.1%}, {'within' if abs(change) <= CONVERGED_CHANGE else 'beyond'} {CONVERGED_CHANGE:.0%}"


def wall_row(run: Path, model_changes: dict | None = None, **changes) -> dict:
    """A row of the study: :func:`impactdyn.whipple.rerun_wall`'s verdict, :data:`KEYS` of its
    measures, the work of the load, the plastic work and the rerun's wall time."""
    tick = time.perf_counter()
    result = rerun_wall(run, model_changes, **changes)
    energy = result.measures["energy"]
    return {"verdict": result.verdict, **{k: result.measures[k] for k in KEYS},
            "load_work": energy["load_work"], "plastic_work": energy["plastic"],
            "wall_time_s": time.perf_counter() - tick}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run", type=Path)
    ap.add_argument("--refinement", type=int, default=2)
    ap.add_argument("--no-spreads", action="store_true")
    ap.add_argument("--split", action="store_true",
                    help="also refine through the thickness alone and in the plane alone")
    ap.add_argument("--thickness-series", type=int, default=0, metavar="N",
                    help="also refine through the thickness alone 2, 3, ..., N times")
    ap.add_argument("--deposition-depth", type=float, default=None, metavar="D",
                    help="deposition_depth_cm on every row (default: the case's)")
    ap.add_argument("--failure-switches", action="store_true",
                    help="also the case's and the refined mesh with JC damage, spall or both off")
    ap.add_argument("--model-option", type=parse_assignment, action="append", default=[], metavar="KEY=VALUE",
                    help="a material-model keyword for every row (VALUE as JSON: false, null, 0.5)")
    ap.add_argument("--json", type=Path)
    args = ap.parse_args()
    case = load_whipple_case(args.run / "case.toml")
    base = case.wall_options
    if args.deposition_depth is not None:
        base = base.replaced(deposition_depth_cm=args.deposition_depth)
    r = args.refinement
    variants = {"case settings": {},
                f"{r}x refinement": {"refinement_thickness": base.refinement_thickness * r,
                                     "refinement_plane": base.refinement_plane * r}}
    if args.split:
        variants |= {f"{r}x thickness": {"refinement_thickness": base.refinement_thickness * r},
                     f"{r}x plane": {"refinement_plane": base.refinement_plane * r}}
    variants |= {f"{n}x thickness": {"refinement_thickness": base.refinement_thickness * n}
                 for n in range(2, args.thickness_series + 1)}
    if not args.no_spreads:
        variants |= {f"spread {s}": {"spread": s} for s in SPREADS if s != base.spread}
    model = dict(args.model_option)
    # (row, wall-option changes, material-model keywords, the row its change is taken against)
    specs = [(name, changes, model, "case settings") for name, changes in variants.items()]
    if args.failure_switches:
        specs += [(f"{mesh}, {switch}", variants[mesh], model | kw, f"case settings, {switch}")
                  for mesh in ("case settings", f"{r}x refinement") for switch, kw in FAILURE_SWITCHES.items()]
    rows = {}
    for name, changes, model_changes, reference in specs:
        rows[name] = row = wall_row(args.run, model_changes or None, deposition_depth_cm=base.deposition_depth_cm,
                                    **changes)
        ref = rows[reference]
        change = {k: (row[k] / ref[k] - 1.0) if ref[k] else float("nan")
                  for k in ("crater_depth_ratio", "rear_bulge_cm", "load_work", "plastic_work")}
        row["change"] = change
        row["crater"] = _crater_agreement(row, ref, change["crater_depth_ratio"])
        print(f"{name:<40} {row['verdict']:<15} crater/t {row['crater_depth_ratio']:.4f} ({row['crater']}) "
              f"bulge {row['rear_bulge_cm']:.4f} cm ({change['rear_bulge_cm']:+.1%}) failed {row['failed_mass_g']:.4g} g "
              f"eroded {row['eroded_mass_g']:.4g} g hg/int {row['hourglass_to_internal']:.3f} "
              f"load work {row['load_work']:.4g} ({change['load_work']:+.1%}) "
              f"plastic {row['plastic_work']:.4g} ({change['plastic_work']:+.1%}) "
              f"t_end {row['end_time_us']:.1f} us ({row['ended_by']}) steps {row['steps']} ({row['wall_time_s']:.0f} s); "
              f"failed by "
              + ", ".join(f"{k} {v:.4g} g" for k, v in row["failed_mass_by_cause_g"].items() if v > 0), flush=True)
    same = len({rows[name]["verdict"] for name in variants}) == 1
    print("same verdict on every row of the case's model" + (f" with {model}" if model else "") + ":", same)
    if args.failure_switches:
        for switch in FAILURE_SWITCHES:
            pair = {rows[f"{mesh}, {switch}"]["verdict"] for mesh in ("case settings", f"{r}x refinement")}
            print(f"{switch}: same verdict at both meshes: {len(pair) == 1}")
    if args.json:
        args.json.write_text(json.dumps({"run": str(args.run), "options": repr(base), "rows": rows}, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
