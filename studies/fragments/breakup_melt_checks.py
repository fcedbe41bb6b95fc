"""The break-up and melt checks of issue 38, as validation/shield-mechanism-decision.md fixes them.

An Al 6061-T6 sphere (d = 0.3175 cm) at normal incidence on an Al 6061-T6 bumper of radius 1.5 d, the
state 3 µs after first contact, with the candidate's SPH options (fragmentation with flaws per unit
volume, Johnson–Cook flow stress, the Balsara viscosity switch):

* onset: the largest projectile piece (heaviest intact fragment made mostly of projectile particles,
  over the projectile's mass) at V_LV ± 0.5 km/s for t/D 0.1, 0.2, 0.4, then the onset speed (where it
  falls below ½) by bisection to 0.125 km/s;
* melt: the projectile's melted share on release (liquid and vapour, by mass) at 6 km/s for t/D 0.1,
  0.2, 0.4 and at 10 km/s for t/D 0.2, against CALE's (MMOD handbook Table 4-4).

(Candidate 3, the pair-wise damage coupling, made the onset earlier still; it ran with this script
and the ``damage_coupling`` option of commit af543fe, since removed.)

Every shot is appended to ``--out`` (JSON lines) as it finishes; a shot already there is read back, not
run again, so an interrupted check resumes.

    python studies/fragments/breakup_melt_checks.py --spacing 0.015875 --out breakup_melt_d20.jsonl
    python studies/fragments/breakup_melt_checks.py --spacing 0.0079375 --out breakup_melt_d40.jsonl --only melt
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import numpy as np

from impactdyn import shield
from impactdyn.materials import get_material

DIAMETER_CM = 0.3175
MATERIAL = "al6061-t6"
PLATE_RADIUS_D = 1.5
TIME_US = 3.0
RATIOS = (0.1, 0.2, 0.4)
CANDIDATE = dict(failure_model="fragmentation", flow_stress="johnson_cook", viscosity_switch="balsara")
#: CALE's melted fraction of the projectile (NASA/TM-2009-214785 Table 4-4): (V km/s, t/D) → fraction;
#: t/D 0.4 lies between the table's 0.3 and 0.5 rows, both 0.06 at 6 km/s.
CALE_MELTED = {(6.0, 0.1): 0.05, (6.0, 0.2): 0.06, (6.0, 0.4): 0.06, (10.0, 0.2): 0.75}
ONSET_RESOLUTION_KM_S = 0.125


def v_lv(ratio: float) -> float:
    """Reimerdes' onset of projectile fragmentation, km/s (NASA/TM-2009-214789 eq. 54)."""
    return 1.853 + 0.397 * ratio ** -0.565


def shot(speed_km_s: float, ratio: float, spacing_cm: float) -> dict:
    """One SPH run of the set-up and its measures."""
    problem = shield.sphere_on_plate(MATERIAL, MATERIAL, DIAMETER_CM, speed_km_s, 0.0, ratio * DIAMETER_CM,
                                     spacing_cm, plate_radius_cm=PLATE_RADIUS_D * DIAMETER_CM)
    projectile = problem.particles.velocity[:, 1] > 0
    start = time.perf_counter()
    state = shield.run(problem, TIME_US, options=shield.SPHOptions(**CANDIDATE)).state
    seconds = time.perf_counter() - start
    m_proj = get_material(MATERIAL).rho0 * math.pi * DIAMETER_CM ** 3 / 6
    fragments = shield.fragments_of(state, link_length_cm=1.5 * spacing_cm)
    both = np.concatenate([projectile, projectile])           # fragments_of adds the images after the particles
    largest = 0.0
    for f in range(len(fragments)):                          # heaviest first
        if np.mean(both[fragments.indices(f)]) > 0.5:
            largest = float(fragments.mass[f])
            break
    phase = shield.released_phase(state)
    mass = state.mass[projectile]
    return {"speed": speed_km_s, "ratio": ratio, "spacing": spacing_cm,
            "largest_projectile_piece": largest / m_proj,
            "melted_projectile": float(mass @ phase.melted[projectile] / mass.sum()),
            "vapour_projectile": float(mass @ phase.vapour[projectile] / mass.sum()),
            "failed_projectile": float(mass @ (state.damage[projectile] >= 1.0) / mass.sum()),
            "particles": len(state.mass), "seconds": round(seconds, 1)}


class Ledger:
    """The shots of one spacing, kept in a JSON-lines file."""

    def __init__(self, path: Path, spacing_cm: float):
        self.path, self.spacing = path, spacing_cm
        self.rows = [json.loads(line) for line in path.read_text().splitlines()] if path.exists() else []

    def get(self, speed: float, ratio: float) -> dict:
        for row in self.rows:
            if row["speed"] == speed and row["ratio"] == ratio and row["spacing"] == self.spacing:
                return row
        row = shot(speed, ratio, self.spacing)
        self.rows.append(row)
        with self.path.open("a") as f:
            f.write(json.dumps(row) + "\n")
        print(json.dumps(row), flush=True)
        return row


def onset(ledger: Ledger, ratio: float, bracket_only: bool = False) -> dict:
    """The bracket check at V_LV ± 0.5 and the onset speed (decision file, check 1); ``bracket_only``:
    the two bracket shots alone (the onset speed left unsearched)."""
    centre = round(v_lv(ratio), 3)
    low, high = round(centre - 0.5, 3), round(centre + 0.5, 3)
    whole = lambda v: ledger.get(v, ratio)["largest_projectile_piece"] >= 0.5     # noqa: E731
    holds = whole(low) and not whole(high)
    if bracket_only:
        return {"ratio": ratio, "v_lv": centre, "bracket_holds": holds, "onset": None}
    if not holds and whole(high):                   # the onset lies above: step up within 7 km/s
        while whole(high) and high + 0.5 <= 7.0:
            low, high = high, round(high + 0.5, 3)
    elif not holds:                                 # the onset lies below: step down within 1 km/s
        while not whole(low) and low - 0.5 >= 1.0:
            low, high = round(low - 0.5, 3), low
    if whole(low) and not whole(high):
        while high - low > ONSET_RESOLUTION_KM_S + 1e-9:
            mid = round(0.5 * (low + high), 4)
            low, high = (mid, high) if whole(mid) else (low, mid)
        speed = 0.5 * (low + high)
    else:
        speed = None
    return {"ratio": ratio, "v_lv": centre, "bracket_holds": holds, "onset": speed}


def melt(ledger: Ledger) -> list[dict]:
    out = []
    for (speed, ratio), cale in CALE_MELTED.items():
        got = ledger.get(speed, ratio)["melted_projectile"]
        band = (0.5 * cale, 2.0 * cale) if speed == 6.0 else (0.5 * cale, min(1.5 * cale, 1.0))
        out.append({"speed": speed, "ratio": ratio, "cale": cale, "melted": got, "band": band,
                    "holds": band[0] <= got <= band[1]})
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--spacing", type=float, help="particle spacing, cm (d/20 = 0.015875, d/40 = 0.0079375)")
    parser.add_argument("--out", type=Path, help="the JSON-lines ledger of this spacing's shots")
    parser.add_argument("--only", choices=("onset", "melt"), help="run one of the two checks")
    parser.add_argument("--ratios", type=float, nargs="+", default=list(RATIOS))
    parser.add_argument("--bracket-only", action="store_true", help="onset: the V_LV ± 0.5 shots alone")
    args = parser.parse_args()
    ledger = Ledger(args.out, args.spacing)
    if args.only != "melt":
        for ratio in args.ratios:
            print("ONSET", json.dumps(onset(ledger, ratio, args.bracket_only)), flush=True)
    if args.only != "onset":
        for row in melt(ledger):
            print("MELT", json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
