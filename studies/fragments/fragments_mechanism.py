"""Fragmentation mechanism of the shield stage on the physics alone (no test outcome): issue 31, item 4.

For one Al 6061-T6 sphere (d = 0.3175 cm) on Al 6061-T6 bumpers, SPH with the fragmentation
failure model (``failure_model = "fragmentation"``), the fragments at ``--time`` µs
(:func:`impactdyn.shield.fragments_of`, link length 1.5 Δ): per bumper t/D, impact speed and particle
spacing, the largest debris fragments (centre-of-mass velocity toward the wall > 5 % of the impact
speed, so the bumper's remnant is left out) as fractions of the projectile's mass, the intact
and the melted share of the projectile.

    python studies/fragments/fragments_mechanism.py                         # t/D 0.1–0.4 at 6 km/s, Δ = d/10
    python studies/fragments/fragments_mechanism.py --speeds 2 3 4 6 --ratios 0.2
    python studies/fragments/fragments_mechanism.py --spacings 0.0318 0.0159 --model threshold
    python studies/fragments/fragments_mechanism.py --failed grady      # with the fragments of failed material
    python studies/fragments/fragments_mechanism.py --failed grady --speeds 4 6 7 --spacings 0.015875 0.0079375 \
        --json gate.jsonl                                                 # the set-4 gate (validation/set-4-decision.md)

``--failed grady`` adds the fragments of the failed solid material (:func:`impactdyn.shield.grady_fragments`,
sized at the rate ``--rate``: read across each fragment's own size, the default, or the kernel's at
failure) to the intact ones; the table then also gives the debris fragments the wall resolves
(diameter ≥ 0.06 cm), their mass, and the projectile's mass in them.  ``--json FILE`` appends each row
to FILE (JSON lines) as it finishes; a row already there is read back, not run again.

What the checks ask: the largest surviving fragment grows as the bumper thins; fragmentation
begins near the published onset speeds for Al on Al; the statistics converge with the spacing.
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
RESOLVED_CM = 0.06   # the fragment the wall's mesh rule is built to crater (impactdyn.wall.FRAGMENT_DIAMETER_CM)


def largest_of(fragments, debris, projectile) -> float:
    """The mass of the largest debris fragment made mostly (by mass: equal particle masses) of projectile
    particles (``projectile`` over the half model and its images), g; 0 if none."""
    for f in np.flatnonzero(debris):
        if np.mean(projectile[fragments.indices(f)]) > 0.5:
            return float(fragments.mass[f])
    return 0.0


def sph_state(speed_km_s: float, ratio: float, spacing_cm: float, model: str, time_us: float,
              keep: Path | None) -> tuple:
    """The SPH states at t = 0 and at ``time_us`` and the seconds the run took (None when read back from
    ``keep``, where a run's states are written for later partitions: they do not depend on it)."""
    stem = None if keep is None else keep / f"{model}_{speed_km_s:g}_{ratio:g}_{spacing_cm:g}_t{time_us:g}"
    if stem is not None and Path(f"{stem}_end.h5").is_file():
        return shield.read_particles(f"{stem}_init.h5")[0], shield.read_particles(f"{stem}_end.h5")[0], None
    problem = shield.sphere_on_plate(MATERIAL, MATERIAL, DIAMETER_CM, speed_km_s, 0.0, ratio * DIAMETER_CM,
                                     spacing_cm)
    start = time.perf_counter()
    state = shield.run(problem, time_us, options=shield.SPHOptions(failure_model=model)).state
    seconds = time.perf_counter() - start
    if stem is not None:
        shield.write_particles(f"{stem}_init.h5", problem.particles)
        shield.write_particles(f"{stem}_end.h5", state)
    return problem.particles, state, seconds


def survey(speed_km_s: float, ratio: float, spacing_cm: float, model: str, time_us: float, failed: str,
           rate: str, keep: Path | None = None, seed: int = 1) -> dict:
    initial, state, seconds = sph_state(speed_km_s, ratio, spacing_cm, model, time_us, keep)
    projectile = initial.velocity[:, 1] > 0
    fragments = shield.fragments_of(state, link_length_cm=1.5 * spacing_cm)
    if failed == "grady":
        fragments = shield.join_fragments(fragments, shield.grady_fragments(
            state, link_length_cm=1.5 * spacing_cm, seed=seed, initial=initial if rate == "own_size" else None))
    debris = fragments.velocity[:, 1] > 0.05 * speed_km_s * 0.1        # cm/µs
    mat = get_material(MATERIAL)
    m_proj = mat.rho0 * math.pi * DIAMETER_CM ** 3 / 6
    intact = (state.damage < 1.0) & (state.temperature < mat.johnson_cook.t_melt)
    both = np.concatenate([projectile, projectile])          # the fragments' members: particles, then images
    resolved = np.flatnonzero(debris & (fragments.diameter_cm >= RESOLVED_CM))
    projectile_resolved = float(shield.origin_masses(fragments, state.mass, projectile)[resolved].sum())
    return {"speed": speed_km_s, "ratio": ratio, "spacing": spacing_cm, "model": model, "failed": failed,
            "rate": rate if failed == "grady" else None, "seed": seed if failed == "grady" else None,
            "largest": (fragments.mass[debris][:3] / m_proj).tolist(), "count": fragments.count[debris][:3].tolist(),
            "n_debris_fragments": int(np.sum(debris & (fragments.count >= 4))),
            "resolved": int(resolved.size),
            "resolved_mass": float(fragments.mass[resolved].sum() / m_proj),
            "projectile_resolved_mass": projectile_resolved / m_proj,
            "largest_cm": float(fragments.diameter_cm[debris][0]) if np.any(debris) else 0.0,
            "largest_projectile": largest_of(fragments, debris, both) / m_proj,
            "intact_projectile": float(np.mean(intact[projectile])),
            "melted_projectile": float(np.mean(state.temperature[projectile] >= mat.johnson_cook.t_melt)),
            "particles": len(state.mass), "seconds": seconds}


def _seconds(seconds: float | None) -> str:
    return "read back" if seconds is None else f"{seconds:.0f}"


def _ledger(path: Path | None) -> dict:
    """The rows already in ``path``, by (model, failed, rate, seed, speed, ratio, spacing)."""
    if path is None or not path.is_file():
        return {}
    rows = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    return {_key(r): r for r in rows}


def _key(row: dict) -> tuple:
    seed = 1 if row.get("seed") is None else row["seed"]        # rows before the seed was recorded: 1
    return row["model"], row["failed"], row["rate"], seed, row["speed"], row["ratio"], row["spacing"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speeds", type=float, nargs="+", default=[6.0])
    parser.add_argument("--ratios", type=float, nargs="+", default=[0.1, 0.2, 0.3, 0.4])
    parser.add_argument("--spacings", type=float, nargs="+", default=[DIAMETER_CM / 10])
    parser.add_argument("--model", default="fragmentation", choices=shield.FAILURE_MODELS)
    parser.add_argument("--time", type=float, default=3.0, help="µs after first contact (default 3)")
    parser.add_argument("--failed", default="spray", choices=("spray", "grady"),
                        help="the failed solid material: spray (default) or Grady fragments")
    parser.add_argument("--rate", default="own_size", choices=("own_size", "at_failure"),
                        help="the rate that sizes Grady's fragments (with --failed grady)")
    parser.add_argument("--json", type=Path, help="append each row to this JSON-lines file; rows there are reused")
    parser.add_argument("--seed", type=int, default=1, help="the seed of Grady's partition (with --failed grady)")
    parser.add_argument("--keep-states", type=Path, help="write each SPH run's states (t = 0 and --time) to this "
                        "folder, and read back those there")
    args = parser.parse_args()
    done = _ledger(args.json)
    print("| model | V km/s | t/D | Δ cm | particles | largest debris fragments / m_proj (particles) | largest cm "
          "| largest of projectile / m_proj | fragments ≥ 4 particles | ≥ 0.06 cm (mass / m_proj; of projectile) | projectile intact | projectile melted | SPH s |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for spacing in args.spacings:
        for speed in args.speeds:
            for ratio in args.ratios:
                grady = args.failed == "grady"
                key = (args.model, args.failed, args.rate if grady else None, args.seed if grady else 1, speed, ratio,
                       spacing)
                r = done.get(key)
                if r is None:
                    r = survey(speed, ratio, spacing, args.model, args.time, args.failed, args.rate, args.keep_states, args.seed)
                    if args.json is not None:
                        with args.json.open("a") as ledger:
                            ledger.write(json.dumps(r) + "\n")
                largest = ", ".join(f"{f:.4f} ({c})" for f, c in zip(r["largest"], r["count"])) or "none"
                print(f"| {r['model']}{' + grady' if args.failed == 'grady' else ''} | {speed:g} | {ratio:g} "
                      f"| {spacing:g} | {r['particles']} | {largest} | {r['largest_cm']:.3f} | {r['largest_projectile']:.4f} "
                      f"| {r['n_debris_fragments']} | {r['resolved']} ({r['resolved_mass']:.3f}; projectile {r['projectile_resolved_mass']:.3f}) "
                      f"| {r['intact_projectile']:.2f} | {r['melted_projectile']:.2f} "
                      f"| {_seconds(r['seconds'])} |", flush=True)


if __name__ == "__main__":
    main()
