"""What decides where the shield stage breaks the projectile: measurements behind the break-up checks, not checks.

The set-up of ``breakup_melt_checks.py`` (an Al 6061-T6 sphere, d = 0.3175 cm, on an Al 6061-T6 bumper of
radius 1.5 d, 3 µs, the candidate's options: flaws per unit volume, Johnson–Cook flow stress, Balsara's
switch), at t/D 0.2 (V_LV 2.79 km/s) unless told otherwise:

* ``strength``: the largest projectile piece (the checks' measure) with the Weibull flaws calibrated to
  spall strengths scaled by a factor (×1.5, ×2), or to a steeper rate law (1.0 GPa at 10⁴ s⁻¹, 2.5 GPa at
  10⁶ s⁻¹: m ≈ 12 instead of 23);
* ``tension``: failure off, the largest principal stress σ₁ each projectile particle reaches (snapshots
  every 0.05 µs to 2 µs), by fifths of the sphere along the axis (0: rear, 4: impact face);
* ``ductile``: failure off, the Johnson–Cook ductile damage Σ Δεₚ/ε_f(σ*) accumulated from snapshots
  every 0.02 µs, split by the triaxiality σ* at which it accrued ([−⅓, ⅓), [⅓, 1.03), [1.03, 3), ≥ 3; 1.03
  is the largest triaxiality of the notched bars the 6061-T6 fit rests on);
* ``pieces``: the checks' measure beside a kinematic one: the largest piece of all solid particles
  (failed or not) that lie within the link length of one another, i.e. material that has not moved
  apart, whatever its damage.

    python studies/fragments/onset_diagnosis.py strength --factor 1.5 --speeds 1.84 2.34 2.84
    python studies/fragments/onset_diagnosis.py tension --speed 1.84 --per-d 20 --switch balsara
    python studies/fragments/onset_diagnosis.py ductile --speed 2.34
    python studies/fragments/onset_diagnosis.py pieces --speeds 1.84 2.34 2.84 3.34

The fourth measurement of the record, the projectile and bumper interacting by contact alone (no
tension and no shear across the two bodies' pairs), needs a patch of the pair loop and is described
in ``validation/shield-mechanism-decision.md`` rather than kept as code.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math

import numpy as np
from breakup_melt_checks import CANDIDATE, DIAMETER_CM, MATERIAL, PLATE_RADIUS_D, TIME_US, shot

from impactdyn import materials, shield
from impactdyn.materials import get_material, weibull_from_spall

GPA = 1.0e-2                     # Mbar per GPa
#: The library's calibration points ((σ GPa, ε̇ µs⁻¹) at 10⁴ and 10⁶ s⁻¹, ``materials.AL_WEIBULL``).
LIBRARY_SPALL = ((1.0, 1.0e-2), (1.7, 1.0))
STEEP_SPALL = ((1.0, 1.0e-2), (2.5, 1.0))
TRIAXIALITY_BANDS = (-1.0 / 3.0, 1.0 / 3.0, 1.026, 3.0)


def _problem(speed: float, ratio: float, per_d: float):
    spacing = DIAMETER_CM / per_d
    problem = shield.sphere_on_plate(MATERIAL, MATERIAL, DIAMETER_CM, speed, 0.0, ratio * DIAMETER_CM, spacing,
                                     plate_radius_cm=PLATE_RADIUS_D * DIAMETER_CM)
    return problem, problem.particles.velocity[:, 1] > 0, spacing


def _axial_fifths(problem, projectile: np.ndarray) -> np.ndarray:
    """0 (rear) … 4 (impact face): the projectile particles' initial axial position in fifths of d."""
    y = problem.particles.position[projectile, 1]
    z = (y - y.mean()) / (0.5 * DIAMETER_CM)
    return np.digitize(z, [-0.6, -0.2, 0.2, 0.6])


def strength(args) -> None:
    (s_lo, r_lo), (s_hi, r_hi) = STEEP_SPALL if args.steep else LIBRARY_SPALL
    flaws = weibull_from_spall(get_material(MATERIAL), (s_lo * args.factor * GPA, r_lo),
                               (s_hi * args.factor * GPA, r_hi))
    for name in ("al6061-t6", "al2024-t4", "al7075-t6"):   # the library's records, their flaws replaced
        materials.MATERIALS[name] = dataclasses.replace(materials.MATERIALS[name], weibull_flaws=flaws)
    for speed in args.speeds:
        row = shot(speed, args.ratio, DIAMETER_CM / args.per_d)
        print(json.dumps({"factor": args.factor, "steep": args.steep, "m": round(flaws.m, 2)} | row), flush=True)


def _largest_principal(particles, ids: np.ndarray) -> np.ndarray:
    s, p = particles.deviatoric_stress[ids], particles.pressure[ids]
    tensor = np.empty((len(ids), 3, 3))
    for a, b, c in ((0, 0, 0), (1, 1, 1), (2, 2, 2), (0, 1, 3), (1, 2, 4), (0, 2, 5)):
        tensor[:, a, b] = tensor[:, b, a] = s[:, c]
    tensor[:, [0, 1, 2], [0, 1, 2]] -= p[:, None]
    return np.linalg.eigvalsh(tensor)[:, -1]


def tension(args) -> None:
    problem, projectile, _ = _problem(args.speed, args.ratio, args.per_d)
    options = shield.SPHOptions(**(CANDIDATE | {"failure": False, "viscosity_switch": args.switch}))
    run = shield.run(problem, 2.0, options=options, snapshot_times_us=np.arange(0.05, 2.0001, 0.05))
    ids = np.flatnonzero(projectile)
    peak, when = np.full(ids.size, -np.inf), np.zeros(ids.size)
    for snap in run.snapshots:
        s1 = _largest_principal(snap, ids) / GPA
        up = s1 > peak
        peak[up], when[up] = s1[up], snap.time
    fifth = _axial_fifths(problem, projectile)
    print(json.dumps({"speed": args.speed, "ratio": args.ratio, "per_d": args.per_d, "switch": args.switch,
                      "median_peak_sigma1_gpa": round(float(np.median(peak)), 2),
                      "by_fifth_rear_to_face": [{"median_gpa": round(float(np.median(peak[fifth == k])), 2),
                                                 "median_time_us": round(float(np.median(when[fifth == k])), 2),
                                                 "above_1.5_gpa": round(float(np.mean(peak[fifth == k] > 1.5)), 2)}
                                                for k in range(5)]}))


def ductile(args) -> None:
    problem, projectile, _ = _problem(args.speed, args.ratio, args.per_d)
    fit = get_material(MATERIAL).johnson_cook_damage
    options = shield.SPHOptions(**(CANDIDATE | {"failure": False}))
    run = shield.run(problem, TIME_US, options=options, snapshot_times_us=np.arange(0.02, TIME_US + 1e-4, 0.02))
    ids = np.flatnonzero(projectile)
    strain, damage = np.zeros(ids.size), np.zeros((ids.size, len(TRIAXIALITY_BANDS)))
    for snap in run.snapshots:
        s = snap.deviatoric_stress[ids]
        mises = np.sqrt(1.5 * (s[:, :3] ** 2).sum(1) + 3.0 * (s[:, 3:] ** 2).sum(1))
        triax = np.where(mises > 0, -snap.pressure[ids] / np.maximum(mises, 1e-300), 0.0)
        step = snap.plastic_strain[ids] - strain
        strain = snap.plastic_strain[ids].copy()
        eps_f = np.maximum(fit.D1 + fit.D2 * np.exp(fit.D3 * np.maximum(triax, TRIAXIALITY_BANDS[0])), fit.efmin)
        band = np.digitize(triax, TRIAXIALITY_BANDS) - 1          # −1: below the cut-off, no damage
        for k in range(len(TRIAXIALITY_BANDS)):
            damage[:, k] += np.where(band == k, step / eps_f, 0.0)
    total = damage.sum(1)
    print(json.dumps({"speed": args.speed, "ratio": args.ratio, "per_d": args.per_d,
                      "plastic_strain_median": round(float(np.median(strain)), 2),
                      "failed_share": round(float(np.mean(total >= 1.0)), 3),
                      "damage_share_by_triaxiality": [round(float(x), 3) for x in damage.sum(0) / total.sum()]}))


def pieces(args) -> None:
    material = get_material(MATERIAL)
    m_proj = material.rho0 * math.pi * DIAMETER_CM ** 3 / 6
    for speed in args.speeds:
        problem, projectile, spacing = _problem(speed, args.ratio, args.per_d)
        state = shield.run(problem, TIME_US, options=shield.SPHOptions(**CANDIDATE)).state
        solid = shield.solid_particles(state)
        both = np.concatenate([projectile, projectile])
        row = {"speed": speed, "ratio": args.ratio, "per_d": args.per_d,
               "failed_projectile": round(float(np.mean(state.damage[projectile] >= 1.0)), 3)}
        for name, member in (("intact_pieces", solid & (state.damage < 1.0)), ("kinematic_pieces", solid)):
            image = np.array([-1.0, 1.0, 1.0])
            mass = np.concatenate([state.mass, state.mass])
            found = shield.find_fragments(np.concatenate([state.position, state.position * image]),
                                          np.concatenate([state.velocity, state.velocity * image]), mass,
                                          mass / material.rho0, np.concatenate([member, member]),
                                          link_length_cm=1.5 * spacing)
            best = 0.0
            for f in range(len(found)):
                idx = found.indices(f)
                if both[idx].mean() > 0.5:
                    best = max(best, float(mass[idx][both[idx]].sum() / m_proj))
            row[name] = round(best, 3)
        print(json.dumps(row), flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="what", required=True)
    for name, func in (("strength", strength), ("tension", tension), ("ductile", ductile), ("pieces", pieces)):
        p = sub.add_parser(name)
        p.set_defaults(func=func)
        p.add_argument("--ratio", type=float, default=0.2, help="bumper thickness over projectile diameter")
        p.add_argument("--per-d", type=float, default=20.0, help="particles across the diameter (spacing d/N)")
        if name in ("strength", "pieces"):
            p.add_argument("--speeds", type=float, nargs="+", default=[1.84, 2.34, 2.84])
        else:
            p.add_argument("--speed", type=float, default=1.84)
    sub.choices["strength"].add_argument("--factor", type=float, default=1.0, help="spall strengths scaled by")
    sub.choices["strength"].add_argument("--steep", action="store_true", help="the steeper rate law")
    sub.choices["tension"].add_argument("--switch", choices=("none", "balsara"), default="balsara")
    args = parser.parse_args()
    args.func(args)


if __name__ == "__main__":
    main()
