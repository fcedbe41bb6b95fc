"""The gate on the verdict (issue 50, item 1; the rule is ``validation/set-4-decision.md``, "The gate on
the verdict"): Table 2's shield with the fragments of failed material, 0.9 and 1.1 times the limit
measured at the example's spacing, at 4 and 7 km/s, over five partition seeds, at the example's
resolution, at half the SPH spacing (i) and at twice the wall mesh (ii).

    python studies/fragments/verdict_gate.py --resolution half_sph --out LEDGER.jsonl --work DIR
    python studies/fragments/verdict_gate.py --resolution example wall_2x --out LEDGER.jsonl --work DIR
    python studies/fragments/verdict_gate.py --out LEDGER.jsonl --table          # the counts, from the ledger

Per shot and resolution the SPH runs once (with seed 1's case: the SPH does not depend on the seed);
for every other seed the shield stage's folder is copied and only its fragments are drawn again from
the kept particles (:func:`impactdyn.shield.debris_fragments`, as the stage does), then the run
goes on from the binning (``run_whipple(..., start="binning")``).  Twice the wall mesh reruns the wall
stage of the example's run of the same seed (``start="wall"``): its SPH, fragments and deposition are
the example's.  Each draw appends one JSON line to the ledger; a draw already there is not run again.
Draws run in seed order, and a shot whose count is decided (3 of 5 on one side) stops unless
``--all-draws`` (the decision file's stopping rule).
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import time
from pathlib import Path

from impactdyn._config import load_toml
from impactdyn.whipple._case import WhippleCase

CASE = Path("examples/whipple/table2_7a_fragments.toml")
#: The limits measured with the candidate at the example's spacing (validation/results/limit_table2_7a_fragments).
LIMITS_CM = {4.0: 0.34582, 7.0: 0.50984}
FACTORS = (1.1, 0.9)
SEEDS = (1, 2, 3, 4, 5)
FAILED = ("perforation", "detached spall")
WALL_2X = {"wall_solver.refinement_thickness": 2, "wall_solver.refinement_plane": 2}


def commit() -> str:
    return subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()


def shot_case(speed: float, factor: float, seed: int, resolution: str) -> WhippleCase:
    """The example case made into the shot (as the limit search makes it), at ``resolution``."""
    from impactdyn._config import validate
    from impactdyn._sweep import case_variants
    from impactdyn.whipple._shots import shot_variant
    from impactdyn.whipple._stages import LEAN_OUTPUT

    raw = load_toml(CASE)
    base = validate(WhippleCase, raw, str(CASE))
    keys = shot_variant(base, speed, round(factor * LIMITS_CM[speed], 5))
    keys["shield.fragment_seed"] = seed
    if resolution == "half_sph":
        keys["shield.spacing_cm"] = 0.5 * keys["shield.spacing_cm"]
    if resolution == "wall_2x":
        keys |= WALL_2X
    keys |= {f"output.{k}": v for k, v in LEAN_OUTPUT.items()}
    return case_variants(WhippleCase, raw, [keys], str(CASE))[0]


def redraw_shield(source: Path, target: Path, case: WhippleCase) -> None:
    """``target``'s shield stage: ``source``'s particles, the fragments drawn with ``case``'s seed."""
    from impactdyn.shield import debris_fragments, fragment_rows, origin_masses, read_particles, write_fragments
    from impactdyn.units import km_s_to_cm_us
    from impactdyn.whipple._case import projectile_mass, shield_problem
    from impactdyn.whipple._cloud import debris_state, fragment_figures, projectile_particles
    from impactdyn.whipple._stages import settings
    from impactdyn._runfolder import FolderWriter

    shutil.copytree(source / "shield", target / "shield")
    out = target / "shield"
    problem, _ = shield_problem(case)
    particles, _ = read_particles(out / "particles.h5")
    fragments = debris_fragments(particles, problem, case.fragment_options, km_s_to_cm_us(case.projectile.velocity_km_s))
    write_fragments(out / "fragments.h5", fragments)
    from_projectile = origin_masses(fragments, particles.mass, projectile_particles(problem))
    FolderWriter(out).write_csv("fragments.csv", *fragment_rows(fragments, from_projectile_g=from_projectile))
    record = json.loads((out / "stage.json").read_text())
    record |= {"settings": settings(case, "shield"),
               "fragments": fragment_figures(fragments, from_projectile, projectile_mass(case)),
               "debris_state": debris_state(particles, projectile_particles(problem), fragments,
                                            case.bumper.thickness_cm, projectile_mass(case))}
    (out / "stage.json").write_text(json.dumps(record, indent=1))


def run_draw(work: Path, speed: float, factor: float, seed: int, resolution: str) -> dict:
    from impactdyn.whipple._pipeline import run_whipple

    case = shot_case(speed, factor, seed, resolution)
    sph = "half_sph" if resolution == "half_sph" else "example"
    folder = work / f"{sph}_V{speed:g}_x{factor:g}_seed{seed}" if resolution != "wall_2x" else \
        work / f"wall_2x_V{speed:g}_x{factor:g}_seed{seed}"
    tick = time.perf_counter()
    if folder.exists():
        shutil.rmtree(folder)
    if resolution == "wall_2x":
        example = work / f"example_V{speed:g}_x{factor:g}_seed{seed}"   # main ran it first
        shutil.copytree(example, folder)
        summary = run_whipple(case, folder, start="wall", force=True)
    elif seed == SEEDS[0]:
        summary = run_whipple(case, folder)
    else:
        first = work / f"{sph}_V{speed:g}_x{factor:g}_seed{SEEDS[0]}"
        if not (first / "summary.json").is_file():
            run_whipple(shot_case(speed, factor, SEEDS[0], resolution), first)
        folder.mkdir(parents=True)
        redraw_shield(first, folder, case)
        summary = run_whipple(case, folder, start="binning", force=True)
    wall = summary["wall"]
    fragments = summary["stages"]["shield"]["fragments"]
    return {"speed_km_s": speed, "factor": factor, "diameter_cm": case.projectile.diameter_cm,
            "resolution": resolution, "seed": seed, "sph_spacing_cm": case.shield.spacing_cm,
            "verdict": wall["verdict"], "perforated": wall["verdict"] in FAILED,
            "jsc_verdict": summary["ble"]["verdict"], "ended_by": summary["stages"]["wall"]["evidence"].get("ended_by"),
            "n_elements": summary["stages"]["wall"]["mesh"].get("n_elements"),
            "compact_mass_g": summary["stages"]["debris"]["compact_fragments"]["mass_g"],
            "n_fragments": fragments["n_fragments"], "largest_over_projectile": fragments.get("largest_over_projectile"),
            "timings_s": summary["timings_s"], "seconds": time.perf_counter() - tick, "commit": commit(),
            "folder": folder.name}


def read_ledger(path: Path) -> list[dict]:
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()] if path.is_file() else []


def decided(rows: list[dict], speed: float, factor: float, resolution: str) -> bool:
    """3 of the shot's draws on one side: its count against the rule cannot change."""
    outcomes = [r["perforated"] for r in rows if (r["speed_km_s"], r["factor"], r["resolution"]) ==
                (speed, factor, resolution)]
    return max(sum(outcomes), len(outcomes) - sum(outcomes)) >= 3


def table(rows: list[dict]) -> str:
    lines = ["| resolution | V (km/s) | d/d_lim | d (cm) | draws run | perforated | held | right side | decided |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for resolution in ("example", "half_sph", "wall_2x"):
        for speed in LIMITS_CM:
            for factor in sorted(FACTORS):
                mine = [r for r in rows if (r["speed_km_s"], r["factor"], r["resolution"]) == (speed, factor, resolution)]
                if not mine:
                    continue
                k = sum(r["perforated"] for r in mine)
                right = k if factor > 1 else len(mine) - k
                verdict = "holds" if right >= 3 else "fails" if len(mine) - right >= 3 else "undecided"
                lines.append(f"| {resolution} | {speed:g} | {factor:g} | {mine[0]['diameter_cm']:.4f} | {len(mine)} | "
                             f"{k} | {len(mine) - k} | {right} of {len(mine)} | {verdict} |")
    return "\n".join(lines)


def ledger(path: Path, row: dict) -> None:
    with path.open("a") as f:
        f.write(json.dumps(row) + "\n")
    print(json.dumps({k: row[k] for k in ("resolution", "speed_km_s", "factor", "seed", "verdict", "seconds")}),
          flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--resolution", nargs="+", default=["example", "half_sph", "wall_2x"],
                    choices=["example", "half_sph", "wall_2x"])
    ap.add_argument("--speeds", nargs="+", type=float, default=[4.0, 7.0])
    ap.add_argument("--factors", nargs="+", type=float, default=list(FACTORS))
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--work", type=Path, default=Path("runs/verdict_gate"))
    ap.add_argument("--all-draws", action="store_true", help="run all five draws even when a count is decided")
    ap.add_argument("--table", action="store_true", help="print the counts from the ledger and stop")
    args = ap.parse_args()
    if args.table:
        print(table(read_ledger(args.out)))
        return
    args.work.mkdir(parents=True, exist_ok=True)
    for seed in SEEDS:  # seed order across the shots: each shot's first three draws come first
        for resolution in args.resolution:
            for speed in args.speeds:
                for factor in args.factors:
                    rows = read_ledger(args.out)
                    key = (speed, factor, resolution)
                    if any((r["speed_km_s"], r["factor"], r["resolution"], r["seed"]) == key + (seed,) for r in rows):
                        continue
                    if not args.all_draws and decided(rows, *key):
                        continue
                    if resolution == "wall_2x" and not any(
                            (r["speed_km_s"], r["factor"], r["resolution"], r["seed"]) == (speed, factor, "example", seed)
                            for r in rows):
                        ledger(args.out, run_draw(args.work, speed, factor, seed, "example"))  # (ii) reruns its wall
                    ledger(args.out, run_draw(args.work, speed, factor, seed, resolution))
    print(table(read_ledger(args.out)))


if __name__ == "__main__":
    main()
