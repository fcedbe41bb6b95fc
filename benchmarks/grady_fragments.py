"""How large would the projectile's fragments be? Grady's energy estimate from the SPH hand-off (issue 11).

A diagnosis for the fragment model proposed on issue 11, not a model of the pipeline: for each
finished Whipple run it takes the projectile material at the shield stage's hand-off and

* its velocity spread σ_v (mass-weighted standard deviation, per axis: y along the shot line, z
  across it; x is the half model's symmetry axis and is left out), which stays as it was when
  the projectile broke up, since the debris flies ballistically after that;
* the strain rate of the break-up, ε̇ = σ_v / σ_X, with σ_X = R/√5 the spread of the intact
  sphere's positions along one axis (the break-up taken to happen at about the projectile's
  size, while the release waves cross it), averaged over y and z;
* Grady's energy-balance fragment size (D.E. Grady, J. Appl. Phys. 53 (1982) 322: the fracture
  energy of a fragment's surface against the kinetic energy of its local expansion)

      s = (24 Γ / (ρ ε̇²))^{1/3},   Γ = K_IC² (1 − ν²) / E   (plane-strain fracture energy);

* the largest fragment of an exponential (Grady–Kipp / Mott) mass distribution with mean mass
  μ = ρ π s³ / 6 over N = M_s / μ fragments, M_s the projectile's mass still solid at the hand-off
  (temperature below the Johnson–Cook T_melt of its material; the solid fraction is printed): the expected largest of N,
  μ (ln N + 0.5772), as a sphere's diameter;
* and, for scale, the Cour-Palais single-wall limit (S1, :mod:`impactdyn.ble`) of the run's wall
  at the projectile material's mean speed along the shot line, and the wall stage's own limit
  for one compact fragment on a resolved mesh, 0.67–0.82 d_c (benchmarks/fragment_crater.py).

K_IC: typical handbook values of plane-strain fracture toughness (MMPDS / ASM ranges for
plate), **not checked against a primary table here**; the estimate is an order of magnitude.

    python benchmarks/grady_fragments.py RUN_FOLDER [RUN_FOLDER ...]
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

from impactdyn import ble
from impactdyn.materials import get_material
from impactdyn.shield import read_particles
from impactdyn.units import KM_S_PER_CM_US
from impactdyn.whipple import load_whipple_case, shield_problem

#: Plane-strain fracture toughness, MPa·√m (typical handbook values; module docstring).
K_IC_MPA_SQRT_M = {"al2024-t4": 34.0, "al6061-t6": 29.0, "al7075-t6": 27.0}
YOUNG_GPA, POISSON = 72.0, 0.33
EULER_GAMMA = 0.5772


def estimate(run: Path) -> dict:
    case = load_whipple_case(run / "case.toml")
    particles, _ = read_particles(run / "shield" / "particles.h5")
    initial = shield_problem(case)[0].particles
    n_p = int(np.count_nonzero(np.any(initial.velocity != 0.0, axis=1)))       # the projectile's come first
    if particles.mass.size != initial.mass.size or not np.array_equal(particles.mass[:n_p], initial.mass[:n_p]):
        raise SystemExit(f"{run}: the hand-off particles are not the shield problem's in its order")
    m, v = particles.mass[:n_p], particles.velocity[:n_p]
    mat = get_material(case.projectile.material)
    solid = particles.temperature[:n_p] < mat.johnson_cook.t_melt
    solid_fraction = float(m[solid].sum() / m.sum())
    w = m / m.sum()
    mean_v = w @ v
    sigma_v = np.sqrt(w @ (v - mean_v) ** 2)                                    # cm/µs, per axis
    radius = 0.5 * case.projectile.diameter_cm
    rate = 0.5 * (sigma_v[1] + sigma_v[2]) / (radius / math.sqrt(5.0)) * 1e6    # 1/s
    rho = mat.rho0 * 1e3                                                         # kg/m³
    gamma = (K_IC_MPA_SQRT_M[mat.name] * 1e6) ** 2 * (1.0 - POISSON**2) / (YOUNG_GPA * 1e9)
    s = (24.0 * gamma / (rho * rate**2)) ** (1.0 / 3.0) * 100.0                 # cm
    mu = mat.rho0 * math.pi * s**3 / 6.0
    total = mat.rho0 * math.pi * case.projectile.diameter_cm**3 / 6.0
    n = solid_fraction * total / mu
    largest = (6.0 * mu * (math.log(n) + EULER_GAMMA) / (math.pi * mat.rho0)) ** (1.0 / 3.0) if n > 1 else s
    speed = mean_v[1] * KM_S_PER_CM_US
    wall_mat = get_material(case.wall.material)
    single = ble.SingleWall(case.wall.thickness_cm, wall_mat.rho0, ble.BRINELL_HARDNESS[wall_mat.name])
    d_c = float(ble.single_wall_critical_diameter(single, speed, 0.0, mat.rho0))
    summary = json.loads((run / "summary.json").read_text())
    return {"run": run.name, "d": case.projectile.diameter_cm, "V": case.projectile.velocity_km_s,
            "t_w": case.wall.thickness_cm, "solid": solid_fraction, "sigma_v": sigma_v * KM_S_PER_CM_US, "rate": rate, "s": s,
            "n": n, "largest": largest, "speed": speed, "d_c": d_c, "verdict": summary["wall"]["verdict"]}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", nargs="+", type=Path)
    args = ap.parse_args()
    print("| run | d (cm) | V (km/s) | t_w (cm) | solid | σ_v y, z (km/s) | ε̇ (1/s) | Grady s (cm) | fragments | "
          "largest (cm) | mean speed (km/s) | (S1) d_c (cm) | wall stage's one-fragment limit (cm) | "
          "simulated verdict |")
    print("| --- " * 14 + "|")
    for run in args.runs:
        r = estimate(run)
        print(f"| {r['run']} | {r['d']:.3f} | {r['V']:.2f} | {r['t_w']:.3f} | {r['solid']:.2f} | {r['sigma_v'][1]:.2f}, "
              f"{r['sigma_v'][2]:.2f} | {r['rate']:.2e} | {r['s']:.3f} | {r['n']:.0f} | {r['largest']:.3f} | "
              f"{r['speed']:.2f} | {r['d_c']:.3f} | {0.67 * r['d_c']:.3f}–{0.82 * r['d_c']:.3f} | {r['verdict']} |",
              flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
