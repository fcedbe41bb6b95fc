"""End-to-end Whipple runs: wall time per stage, and the resolution study of issue 4.

Runs a Whipple case (default: ``examples/whipple/table2_7a.toml``) end to end at its
own SPH particle spacing and at that spacing divided by ``--refine`` (1.26: twice the
particles), and prints, for each, the time of every stage and the three figures the
resolution study compares — the debris cloud's leading-edge velocity, its total
axial momentum (toward the wall) and the peak areal momentum on the wall — with
their relative change.

    python benchmarks/bench_whipple.py [--case examples/whipple/table2_7a.toml] [--refine 1.26]
                                       [--out runs/bench_whipple] [--coarse-only]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from pathlib import Path

from impactdyn.whipple import load_whipple_case, run_whipple

FIGURES = (("cloud", "leading_edge_velocity_km_s", "leading-edge velocity (km/s)"),
           ("cloud", "axial_momentum_g_cm_us", "axial momentum, half model (g cm/us)"),
           ("deposition", "peak_areal_momentum_N_s_cm2", "peak areal momentum (N s/cm2)"))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--case", default="examples/whipple/table2_7a.toml")
    ap.add_argument("--refine", type=float, default=1.26, help="spacing ratio of the finer run")
    ap.add_argument("--out", default="runs/bench_whipple", help="folder for the run folders (replaced)")
    ap.add_argument("--coarse-only", action="store_true", help="only the case's own resolution (timing)")
    args = ap.parse_args()

    case = load_whipple_case(args.case)
    print(f"machine: {platform.platform()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    runs = [("default", case)]
    if not args.coarse_only:
        fine = case.model_copy(update={"shield": case.shield.model_copy(
            update={"spacing_cm": case.shield.spacing_cm / args.refine})})
        runs.append((f"{args.refine:g}x finer", fine))
    results = {}
    for label, c in runs:
        tick = time.perf_counter()
        s = run_whipple(c, Path(args.out) / label.replace(" ", "_"), force=True)
        total = time.perf_counter() - tick
        st = s["stages"]
        print(f"\n{label}: SPH spacing {c.shield.spacing_cm:.5g} cm, {st['shield']['n_particles']} SPH particles "
              f"({st['shield']['steps']} steps), {st['debris']['n_particles']} debris particles "
              f"({st['debris']['n_arrived']} arrived)")
        print("  stage times (s): " + ", ".join(f"{k} {v:.1f}" for k, v in s["timings_s"].items())
              + f", report {total - s['wall_time_s']:.1f}; end to end {total:.1f}")
        print(f"  conservation: momentum {st['shield']['momentum_error_rel']:.2e}, "
              f"energy {st['shield']['energy_error_rel']:.2e}")
        for group, key, name in FIGURES:
            print(f"  {name}: {s[group][key]:.6g}")
        results[label] = s
    if len(runs) == 2:
        (a, sa), (b, sb) = results.items()
        print(f"\nchange {a} → {b}:")
        for group, key, name in FIGURES:
            x, y = sa[group][key], sb[group][key]
            print(f"  {name}: {100 * (y - x) / x:+.2f} %")
    print(json.dumps({k: {"timings_s": v["timings_s"], **{key: v[g][key] for g, key, _ in FIGURES}}
                      for k, v in results.items()}))


if __name__ == "__main__":
    main()
