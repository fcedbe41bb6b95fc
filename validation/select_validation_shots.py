"""The validation shots of the wall stage, chosen from the test database by a rule fixed before any is run.

The rules are data now: ``src/impactdyn/whipple/rules/set-N.toml``, selected by
:func:`impactdyn.whipple.select_shots` (``impactdyn whipple validate --select set-N`` runs and scores them);
this script lists a set.  The history of the rules and of the decisions they served:

Rule (written down 2026-11-24, before a single database shot was simulated; issue 11):

1. Eligible: the pipeline can model the shot with library materials and its case validates:
   - projectile AA2017-T4 (modelled as Al 2024-T4, the same Al–Cu family; ρ 2.79 vs 2.785),
     AA2024-* (as Al 2024-T4) or AA6061-T6; bumper and wall AA6061-T6 (as Al 6061-T6) or
     AA2024-T3 (as Al 2024-T4).  Pure and annealed aluminium (AA1100-O, 99.9 %) has no library
     entry and is left out;
   - 3 ≤ V ≤ 8 km/s; 0.2 ≤ d ≤ 1.0 cm (the default SPH spacing puts ≥ 8 particles across);
   - stand-off S ≥ 4 cm (the hand-off grid must fit between bumper and wall at 8 km/s);
   - wall thickness ≥ 0.1 cm.
2. Distance to the report's Table 2 shield (t_b 0.127, t_w 0.3175, S 10.16 cm):
   D = |ln(t_b/0.127)| + |ln(t_w/0.3175)| + |ln(S/10.16)|.
3. Take the 6 perforated (P) and the 6 not perforated (NP) eligible shots of smallest D (ties:
   file line).  If fewer than 3 of the 12 are oblique (θ > 0), replace, alternating P and NP,
   the normal-incidence shot of largest D in that outcome by the nearest oblique one of the
   same outcome not yet taken, until 3 are.

The simulated verdicts of these shots are compared with the test outcome and with the JSC
equation's on the same shots (accuracy and false-safe rate, BENCHMARKS.md).  No constant of
the pipeline is calibrated on them.

Set 2 (rule written down 2026-11-26, before any shot of it was simulated): the same rule, 1–3,
applied to the eligible shots that are not in set 1 — a disjoint set, the next nearest to the
Table 2 shield.  Set n in general: the rule applied to the eligible shots not in sets 1 … n−1.
Set 2 exists to choose the wall stage's default material model on shots neither model has been
scored on; the decision rule, also written before the runs: the default becomes
``johnson_cook`` if on set 2 it has more verdicts right than the type-13 card AND no more
false-safe verdicts (perforated shots called safe); otherwise the type-13 card stays.

Set 3 (reserved 2026-11-27, before any of its shots was simulated): it judges the next change to
the wall's load or failure model.  Sets 1 and 2 were looked at when the wall resolved through
its thickness turned out to call 11 of their 12 perforations safe (BENCHMARKS.md), so a model
proposed in answer to that can no longer be judged on them.

Set 3's decision rule (written down 2026-11-27, before any shot of set 3 was simulated): how the
Johnson–Cook wall fails in triaxial tension beyond its damage fit's range — (a) as now, damage
accumulates where the fit's fracture strain is at its floor, against (b)
``damage_at_floor=False``, damage only where the fit gives a fracture strain (BENCHMARKS.md,
"what fails the 7a wall").  Each shot runs end to end once with the defaults, (a); its wall stage
is rerun under (b) on the same deposition (``run_validation_shots.py --set 3 --model-option
damage_at_floor=false``).  (b) becomes the default if on set 3 it has at least as many verdicts
right as (a) AND no more false-safe verdicts (perforated shots called safe); otherwise (a) stays.
A tie on both goes to (b), the option whose 7a verdict converges with the mesh.  The JSC
equation's scores on the same shots are reported beside them and take no part in the rule.
Outcome (BENCHMARKS.md, "validation set 3"): (a) 7 right, 5 false-safe; (b) 6 right, 6
false-safe: (a) stays.  Set 3 is spent; the next change is judged on set 4.

Library data, not a model choice (2026-11-27, session 16, written before any run with them): the
Johnson–Cook damage constants of 2024-T351 (the library's ``al2024-t4``) and OFHC copper were
missing, so a 2024 wall could fail by spall alone (9 walls of sets 1–3).  They are published
material data and are adopted whatever the scores say; no constant is chosen by a shot.  Their
effect is reported on those 9 walls of the spent sets 1–3 (wall stage rerun on the same
depositions, with and without them), not judged; set 4 stays reserved for the next change to the
wall's load or failure model.

    python validation/select_validation_shots.py [--set N] [--json]
"""

from __future__ import annotations

import json
import sys

import numpy as np

from impactdyn.ble import read_database
from impactdyn.whipple import ALLOYS, load_rule, select_shots


def select(set_number: int = 1) -> list[dict]:
    """The shots of validation set ``set_number`` (the shipped rule ``set-N``), sorted by file line."""
    db = read_database()
    rule = load_rule(f"set-{set_number}")
    reference = rule.distance.model_dump()
    rows = []
    for i in select_shots(rule, db):
        rows.append({"line": int(db.line[i]), "source": str(db.source[i]), "shot_id": str(db.shot_id[i]),
                     "projectile": ALLOYS[db.projectile_material[i]], "bumper": ALLOYS[db.bumper_material[i]],
                     "wall": ALLOYS[db.wall_material[i]], "diameter_cm": float(db.diameter_cm[i]),
                     "velocity_km_s": float(db.velocity_km_s[i]), "obliquity_deg": float(db.obliquity_deg[i]),
                     "bumper_thickness_cm": float(db.bumper_thickness_cm[i]),
                     "wall_thickness_cm": float(db.wall_thickness_cm[i]), "spacing_cm": float(db.spacing_cm[i]),
                     "wall_yield_ksi": float(db.wall_yield_ksi[i]), "perforated": bool(db.perforated[i]),
                     "distance": float(sum(abs(np.log(getattr(db, k)[i] / ref)) for k, ref in reference.items()))})
    return rows


def main() -> None:
    set_number = int(sys.argv[sys.argv.index("--set") + 1]) if "--set" in sys.argv else 1
    shots = select(set_number)
    if "--json" in sys.argv:
        print(json.dumps(shots, indent=2))
        return
    for r in shots:
        print(f"line {r['line']:4d} {r['source']:<22} {r['shot_id']:<12} {'P ' if r['perforated'] else 'NP'} "
              f"d {r['diameter_cm']:.3f} V {r['velocity_km_s']:.2f} θ {r['obliquity_deg']:g} "
              f"t_b {r['bumper_thickness_cm']:.4g} t_w {r['wall_thickness_cm']:.4g} S {r['spacing_cm']:.4g} "
              f"{r['projectile']}/{r['bumper']}/{r['wall']} D {r['distance']:.3f}")


if __name__ == "__main__":
    main()
