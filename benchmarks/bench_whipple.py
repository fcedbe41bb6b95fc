"""End-to-end Whipple runs: wall time per stage, and the resolution study of issue 4.

Runs a Whipple case (default: ``examples/whipple/table2_7a.toml``) end to end at its
own SPH particle spacing and at that spacing divided by ``--refine`` (1.26: twice the
particles), and prints, for each, the time of every stage and the three figures the
resolution study compares — the debris cloud's leading-edge velocity, its total
axial momentum (toward the wall) and the peak areal momentum on the wall — with
their relative change. The wall peak is also given on coarser elements (the
deposition remapped conservatively, :func:`impactdyn.debris.remap_impulse`), to show
how much of its change is element-scale noise. ``--binning`` overrides the case's
hand-off assignment (kernel or cloud-in-cell); ``--shield KEY=VALUE`` sets a key of the case's
``[shield]`` table (repeatable: the fragments of failed material are ``--shield
failure_model=fragmentation --shield failed_fragments=grady``).

    python benchmarks/bench_whipple.py [--case examples/whipple/table2_7a.toml] [--refine 1.26]
                                       [--binning kernel|cic] [--shield KEY=VALUE ...]
                                       [--out runs/bench_whipple] [--coarse-only]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from pathlib import Path

import numpy as np

from impactdyn._config import parse_assignment
from impactdyn.debris import WallGrid, areal_density, remap_impulse
from impactdyn.debris import read_deposition
from impactdyn.whipple import load_whipple_case, run_whipple

FIGURES = (("cloud", "leading_edge_velocity_km_s", "leading-edge velocity (km/s)"),
           ("cloud", "axial_momentum_g_cm_us", "axial momentum, half model (g cm/us)"),
           ("deposition", "peak_areal_momentum_N_s_cm2", "peak areal momentum (N s/cm2)"))
#: Element edges (cm) of the coarser wall grids the deposition is remapped onto.
REMAP_CM = (0.32, 0.5, 0.8)


def remapped_peaks(folder: Path) -> dict[float, float]:
    """Peak areal momentum (N·s/cm²) with the wall's impulse remapped onto square elements of each REMAP_CM edge."""
    wall, _, impulse = read_deposition(folder / "debris" / "debris.h5")
    peaks = {}
    for edge in REMAP_CM:
        n = [max(1, round((a[-1] - a[0]) / edge)) + 1 for a in (wall.x, wall.z)]
        coarse = WallGrid(x=np.linspace(wall.x[0], wall.x[-1], n[0]), y=wall.y[:2],
                          z=np.linspace(wall.z[0], wall.z[-1], n[1]))
        peaks[edge] = 10.0 * float(areal_density(remap_impulse(impulse, wall, coarse), coarse).max())
    return peaks


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--case", default="examples/whipple/table2_7a.toml")
    ap.add_argument("--refine", type=float, default=1.26, help="spacing ratio of the finer run")
    ap.add_argument("--out", default="runs/bench_whipple", help="folder for the run folders (replaced)")
    ap.add_argument("--coarse-only", action="store_true", help="only the case's own resolution (timing)")
    ap.add_argument("--binning", choices=("kernel", "cic"), help="hand-off assignment (default: the case's)")
    ap.add_argument("--shield", action="append", default=[], metavar="KEY=VALUE",
                    help="set a key of the case's [shield] table (repeatable)")
    args = ap.parse_args()

    case = load_whipple_case(args.case)
    if args.shield:
        keys = dict(parse_assignment(a) for a in args.shield)
        case = case.model_copy(update={"shield": type(case.shield).model_validate(case.shield.model_dump() | keys)})
    if args.binning:
        case = case.model_copy(update={"binning": case.binning.model_copy(update={"method": args.binning})})
    print(f"machine: {platform.platform()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    runs = [("default", case)]
    if not args.coarse_only:
        fine = case.model_copy(update={"shield": case.shield.model_copy(
            update={"spacing_cm": case.shield.spacing_cm / args.refine})})
        runs.append((f"{args.refine:g}x finer", fine))
    results = {}
    for label, c in runs:
        tick = time.perf_counter()
        folder = Path(args.out) / label.replace(" ", "_")
        s = run_whipple(c, folder, force=True)
        total = time.perf_counter() - tick
        st = s["stages"]
        s["remapped_peaks"] = remapped_peaks(folder)
        print(f"\n{label}: SPH spacing {c.shield.spacing_cm:.5g} cm, {st['shield']['n_particles']} SPH particles "
              f"({st['shield']['steps']} steps), {st['binning']['method']} binning of "
              f"{st['binning']['n_particles_binned']} into {st['binning']['n_cells_with_mass']} cells, "
              f"{st['debris']['n_particles']} debris particles ({st['debris']['n_arrived']} arrived)")
        print("  stage times (s): " + ", ".join(f"{k} {v:.1f}" for k, v in s["timings_s"].items())
              + f", report {total - s['wall_time_s']:.1f}; end to end {total:.1f}")
        print(f"  conservation: momentum {st['shield']['momentum_error_rel']:.2e}, "
              f"energy {st['shield']['energy_error_rel']:.2e}")
        for group, key, name in FIGURES:
            print(f"  {name}: {s[group][key]:.6g}")
        print("  the same on " + " / ".join(f"{e:g}" for e in REMAP_CM) + "-cm elements: "
              + " / ".join(f"{v:.4g}" for v in s["remapped_peaks"].values()))
        results[label] = s
    if len(runs) == 2:
        (a, sa), (b, sb) = results.items()
        print(f"\nchange {a} → {b}:")
        for group, key, name in FIGURES:
            x, y = sa[group][key], sb[group][key]
            print(f"  {name}: {100 * (y - x) / x:+.2f} %")
        print("  the same on " + " / ".join(f"{e:g}" for e in REMAP_CM) + "-cm elements: " + " / ".join(
            f"{100 * (sb['remapped_peaks'][e] / sa['remapped_peaks'][e] - 1):+.2f}" for e in REMAP_CM) + " %")
    print(json.dumps({k: {"timings_s": v["timings_s"], "remapped_peaks": v["remapped_peaks"],
                          **{key: v[g][key] for g, key, _ in FIGURES}} for k, v in results.items()}))


if __name__ == "__main__":
    main()
