"""The onset as the radiographs see it (issue 50, item 3; the rule is ``validation/shield-mechanism-decision.md``,
"The onset as the radiographs see it"): Piekutowski's spall shell, intact or ruptured, read off the SPH.

    python studies/fragments/spall_shell.py --spacing 0.04765 --out d20.jsonl      # d/20
    python studies/fragments/spall_shell.py --spacing 0.023825 --out d40.jsonl     # d/40
    python studies/fragments/spall_shell.py --out d20.jsonl --out d40.jsonl --table

A 0.953-cm al2024-t4 sphere on an al6061-t6 bumper at normal incidence (half model), the SPH with the
fragments example's ``[shield]`` keys, read at the pipeline's hand-off time 4 × 7/V µs.  The rear cap (the
projectile's particles more than d/4 behind its centre at t = 0) is linked friends-of-friends at 1.5 Δ on
its current positions, whatever the damage; the shell is intact when its largest piece holds ≥ 80 % of
the cap's mass.  Beside it, the largest projectile fragment the chain sends to the wall
(:func:`impactdyn.shield.debris_fragments`), over the projectile's mass.  Each point appends a JSON line to
``--out``; a point already there is not run again.
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import time
from pathlib import Path

import numpy as np

from impactdyn import shield
from impactdyn.materials import get_material
from impactdyn.units import km_s_to_cm_us
from impactdyn.whipple import load_whipple_case

EXAMPLE = Path("examples/whipple/table2_7a_fragments.toml")
DIAMETER_CM = 0.953
PROJECTILE, BUMPER = "al2024-t4", "al6061-t6"
#: Piekutowski's points the spacing resolves (t/D, km/s, shell intact in the radiograph), Reimerdes et al.
#: (2006) Fig. 4 and NASA/TM-2009-214789 Fig. 12, with their test numbers.
POINTS = [("4-1632", 0.085, 3.4, False), ("4-1719", 0.24, 2.8, False), ("4-1722", 0.135, 2.5, True),
          ("4-1718", 0.23, 2.0, True), ("4-1720", 0.23, 2.4, True), ("4-1721", 0.50, 2.2, True)]
CAP_DEPTH = 0.25          # the rear cap: more than d/4 behind the centre
INTACT_SHARE = 0.8        # the largest linked piece of the cap, over the cap's mass
LINK_SPACINGS = 1.5


def handoff_us(speed_km_s: float) -> float:
    """The pipeline's hand-off time at this speed (the example's 4 µs at 7 km/s, stretched by 7/V)."""
    return 4.0 * max(1.0, 7.0 / speed_km_s)


def spall_shell(initial, state, spacing_cm: float) -> tuple[float, float]:
    """(the largest linked piece of the rear cap over the cap's mass, the cap's mass over the projectile's)."""
    projectile = initial.velocity[:, 1] > 0
    centre_y = np.average(initial.position[projectile, 1], weights=initial.mass[projectile])
    cap = projectile & (initial.position[:, 1] < centre_y - CAP_DEPTH * DIAMETER_CM)
    mirror = np.array([-1.0, 1.0, 1.0])    # the half model's images across x = 0
    position, velocity = (np.concatenate([a[cap], a[cap] * mirror]) for a in (state.position, state.velocity))
    mass = np.concatenate([state.mass[cap]] * 2)
    pieces = shield.find_fragments(position, velocity, mass, mass / get_material(PROJECTILE).rho0,
                                   np.ones(len(mass), dtype=bool), link_length_cm=LINK_SPACINGS * spacing_cm)
    return float(pieces.mass[0] / mass.sum()), float(state.mass[cap].sum() / state.mass[projectile].sum())


def largest_to_wall(initial, state, problem, speed_km_s: float, options) -> float:
    """The heaviest debris fragment the chain finds (``options``: the example's fragment options), more than
    half projectile by mass, over the projectile's (full) mass; 0 if none."""
    fragments = shield.debris_fragments(state, problem, options, km_s_to_cm_us(speed_km_s))
    projectile = initial.velocity[:, 1] > 0
    from_projectile = shield.origin_masses(fragments, state.mass, projectile)
    mostly = from_projectile > 0.5 * fragments.mass
    m_p = get_material(PROJECTILE).rho0 * math.pi * DIAMETER_CM ** 3 / 6.0
    return float(fragments.mass[mostly][0] / m_p) if mostly.any() else 0.0


def run_point(test: str, ratio: float, speed: float, intact: bool, spacing: float) -> dict:
    problem = shield.sphere_on_plate(PROJECTILE, BUMPER, DIAMETER_CM, speed, 0.0, ratio * DIAMETER_CM, spacing)
    example = load_whipple_case(EXAMPLE)
    tick = time.perf_counter()
    state = shield.run(problem, handoff_us(speed), options=example.shield.sph_options()).state
    seconds = time.perf_counter() - tick
    piece, cap = spall_shell(problem.particles, state, spacing)
    return {"test": test, "t_over_d": ratio, "speed_km_s": speed, "radiograph_intact": intact,
            "spacing_cm": spacing, "time_us": handoff_us(speed), "n_particles": len(state),
            "largest_cap_piece": piece, "cap_mass_share": cap, "simulated_intact": piece >= INTACT_SHARE,
            "agrees": (piece >= INTACT_SHARE) == intact,
            "largest_projectile_fragment_to_wall": largest_to_wall(problem.particles, state, problem, speed,
                                                                    example.fragment_options),
            "sph_seconds": seconds,
            "commit": subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True
                                     ).stdout.strip()}


def table(rows: list[dict]) -> str:
    lines = ["| test | t/D | V (km/s) | radiograph | Δ (cm) | largest cap piece | simulated | agrees | "
             "largest projectile fragment to the wall |", "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for r in sorted(rows, key=lambda r: (r["spacing_cm"], r["t_over_d"], r["speed_km_s"]), reverse=True):
        lines.append(f"| {r['test']} | {r['t_over_d']:g} | {r['speed_km_s']:g} | "
                     f"{'intact' if r['radiograph_intact'] else 'ruptured'} | {r['spacing_cm']:g} | "
                     f"{r['largest_cap_piece']:.3f} | {'intact' if r['simulated_intact'] else 'ruptured'} | "
                     f"{'yes' if r['agrees'] else 'no'} | {r['largest_projectile_fragment_to_wall']:.3f} |")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--spacing", type=float, default=DIAMETER_CM / 20)
    ap.add_argument("--out", type=Path, action="append", required=True)
    ap.add_argument("--table", action="store_true", help="print the rows of every --out and stop")
    args = ap.parse_args()
    rows = [json.loads(line) for path in args.out if path.is_file() for line in path.read_text().splitlines()]
    if not args.table:
        for test, ratio, speed, intact in POINTS:
            if any(r["test"] == test and math.isclose(r["spacing_cm"], args.spacing) for r in rows):
                continue
            row = run_point(test, ratio, speed, intact, args.spacing)
            with args.out[0].open("a") as f:
                f.write(json.dumps(row) + "\n")
            rows.append(row)
            print(json.dumps({k: row[k] for k in ("test", "largest_cap_piece", "agrees", "sph_seconds")}), flush=True)
    print(table(rows))


if __name__ == "__main__":
    main()
