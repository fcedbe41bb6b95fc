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
  μ = ρ π s³ / 6 over the projectile's mass still solid at the hand-off, M_s (temperature below
  the Johnson–Cook T_melt of its material; the solid fraction is printed): the mass M with one
  expected fragment heavier than it, (M_s/μ) exp(−M/μ) = 1, as a sphere's diameter;
* and, for scale, the Cour-Palais single-wall limit (S1, :mod:`impactdyn.ble`) of the run's wall
  at the projectile material's mean speed along the shot line, and the wall stage's own limit
  for one compact fragment on a resolved mesh, 0.67–0.82 d_c (studies/fragments/fragment_crater.py).

``--local`` replaces the bulk rate by each particle's own: the symmetric part of ∂v/∂X, the
hand-off velocities' least-squares gradient over the particle's neighbours in the initial lattice
(within 1.75 spacings; the debris keeps its velocities, so this is the rate at which that piece
of the projectile was torn apart), its largest eigenvalue (the fastest stretch) taken as ε̇_i;
each solid particle's mass breaks into fragments of mean size s_i by the formula above, and the
largest fragment is the mass M with one expected fragment heavier than it,
Σ_i (M_i/μ_i) exp(−M/μ_i) = 1 over the whole projectile (twice the half model's particles).

K_IC: typical handbook values of plane-strain fracture toughness (MMPDS / ASM ranges for
plate), **not checked against a primary table here**; the estimate is an order of magnitude.

    python studies/fragments/grady_fragments.py RUN_FOLDER [RUN_FOLDER ...] [--local]
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

from impactdyn import ble
from impactdyn.materials import get_material
from impactdyn.shield import read_particles
from impactdyn.units import KM_S_PER_CM_US
from impactdyn.whipple import load_whipple_case, shield_problem
from _particles import projectile_count

#: Plane-strain fracture toughness, MPa·√m (typical handbook values; module docstring).
K_IC_MPA_SQRT_M = {"al2024-t4": 34.0, "al6061-t6": 29.0, "al7075-t6": 27.0}
YOUNG_GPA, POISSON = 72.0, 0.33


def grady_size(rate, material) -> np.ndarray:
    """Grady's fragment size s = (24 Γ / (ρ ε̇²))^{1/3}, cm, at the strain rate ``rate`` (1/s)."""
    gamma = (K_IC_MPA_SQRT_M[material.name] * 1e6) ** 2 * (1.0 - POISSON**2) / (YOUNG_GPA * 1e9)   # J/m²
    return (24.0 * gamma / (material.rho0 * 1e3 * np.asarray(rate) ** 2)) ** (1.0 / 3.0) * 100.0


def stretch_rates(initial: np.ndarray, velocity: np.ndarray, spacing: float) -> np.ndarray:
    """Per particle, the largest eigenvalue of sym(∂v/∂X) over its initial neighbours, 1/s; (n, 3) → (n,)."""
    rates = np.empty(len(initial))
    for i, near in enumerate(cKDTree(initial).query_ball_point(initial, 1.75 * spacing)):
        near = [j for j in near if j != i]
        grad, *_ = np.linalg.lstsq(initial[near] - initial[i], velocity[near] - velocity[i], rcond=None)
        rates[i] = np.linalg.eigvalsh(0.5 * (grad + grad.T))[-1] * 1e6
    return rates


def largest_fragment(mass: np.ndarray, size: np.ndarray, density: float) -> float:
    """The diameter (cm) of the mass M with one expected fragment heavier than it, when each ``mass``
    breaks into exponentially distributed fragments of mean size ``size`` (module docstring)."""
    mean = density * math.pi * size**3 / 6.0
    count = mass / mean
    lo, hi = 1e-12, float(mass.sum())
    for _ in range(200):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if (count * np.exp(-mid / mean)).sum() > 1.0 else (lo, mid)
    return (6.0 * lo / (math.pi * density)) ** (1.0 / 3.0)


def estimate(run: Path, local: bool) -> dict:
    case = load_whipple_case(run / "case.toml")
    particles, _ = read_particles(run / "shield" / "particles.h5")
    problem = shield_problem(case)[0]
    initial = problem.particles
    n_p = projectile_count(problem)
    if particles.mass.size != initial.mass.size or not np.array_equal(particles.mass[:n_p], initial.mass[:n_p]):
        raise SystemExit(f"{run}: the hand-off particles are not the shield problem's in its order")
    m, v = particles.mass[:n_p], particles.velocity[:n_p]
    mat = get_material(case.projectile.material)
    solid = particles.temperature[:n_p] < mat.johnson_cook.t_melt
    w = m / m.sum()
    mean_v = w @ v
    sigma_v = np.sqrt(w @ (v - mean_v) ** 2)                                    # cm/µs, per axis
    if local:
        rates = stretch_rates(initial.position[:n_p], v, case.shield.spacing_cm)[solid]
        rate = float(np.median(rates))
        sizes = grady_size(np.maximum(rates, 1e3), mat)
    else:
        radius = 0.5 * case.projectile.diameter_cm
        rate = 0.5 * (sigma_v[1] + sigma_v[2]) / (radius / math.sqrt(5.0)) * 1e6
        sizes = np.full(int(solid.sum()), grady_size(rate, mat))
    speed = mean_v[1] * KM_S_PER_CM_US
    wall_mat = get_material(case.wall.material)
    single = ble.SingleWall(case.wall.thickness_cm, wall_mat.rho0, ble.BRINELL_HARDNESS[wall_mat.name])
    summary = json.loads((run / "summary.json").read_text())
    return {"run": run.name, "d": case.projectile.diameter_cm, "V": case.projectile.velocity_km_s,
            "t_w": case.wall.thickness_cm, "solid": float(m[solid].sum() / m.sum()), "sigma_v": sigma_v * KM_S_PER_CM_US,
            "rate": rate, "s": float(np.median(sizes)), "largest": largest_fragment(2.0 * m[solid], sizes, mat.rho0),
            "speed": speed, "d_c": float(ble.single_wall_critical_diameter(single, speed, 0.0, mat.rho0)),
            "verdict": summary["wall"]["verdict"]}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", nargs="+", type=Path)
    ap.add_argument("--local", action="store_true", help="each particle's own stretch rate (module docstring)")
    args = ap.parse_args()
    print("| run | d (cm) | V (km/s) | t_w (cm) | solid | σ_v y, z (km/s) | ε̇ (1/s; --local: median) | "
          "Grady s (cm; median) | largest (cm) | mean speed (km/s) | (S1) d_c (cm) | "
          "wall stage's one-fragment limit (cm) | simulated verdict |")
    print("| --- " * 13 + "|")
    for run in args.runs:
        r = estimate(run, args.local)
        print(f"| {r['run']} | {r['d']:.3f} | {r['V']:.2f} | {r['t_w']:.3f} | {r['solid']:.2f} | {r['sigma_v'][1]:.2f}, "
              f"{r['sigma_v'][2]:.2f} | {r['rate']:.2e} | {r['s']:.3f} | {r['largest']:.3f} | "
              f"{r['speed']:.2f} | {r['d_c']:.3f} | {0.67 * r['d_c']:.3f}–{0.82 * r['d_c']:.3f} | {r['verdict']} |",
              flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
