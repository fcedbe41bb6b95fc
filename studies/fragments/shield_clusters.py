"""Does the shield stage hand off fragments? Clusters of touching SPH particles behind the bumper (issue 11).

At the hand-off time the particles behind the bumper's back face that move towards the wall faster
than ``--min-speed`` (km/s; 0 keeps the bumper's slow rim too) are linked when they lie within
``link`` times the SPH spacing of each other; a solid fragment that holds together is a connected
cluster at about the reference density.  For each finished Whipple run and each link factor this
prints the number of clusters and the three largest, as fractions of the (half-model) projectile's
mass, with their mean density over the projectile material's ρ₀, their speeds and particle counts.

    python studies/fragments/shield_clusters.py RUN_FOLDER [RUN_FOLDER ...] [--links 1.05 1.2 1.5] [--min-speed 1]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from impactdyn.materials import get_material
from impactdyn.shield import read_particles
from impactdyn.units import KM_S_PER_CM_US
from impactdyn.whipple import load_whipple_case
from _particles import linked_clusters


def clusters(run: Path, link: float, min_speed_km_s: float) -> tuple[int, np.ndarray, np.ndarray, np.ndarray,
                                                                      np.ndarray]:
    """(number of clusters, the three largest cluster masses over the half projectile's, their mean
    ρ/ρ₀ of the projectile material, their speeds in km/s, their particle counts) at the hand-off of
    ``run``, among the particles behind the bumper moving towards the wall faster than ``min_speed_km_s``."""
    case = load_whipple_case(run / "case.toml")
    particles, _ = read_particles(run / "shield" / "particles.h5")
    behind = np.flatnonzero((particles.position[:, 1] >= case.bumper.thickness_cm)
                            & (particles.velocity[:, 1] * KM_S_PER_CM_US > min_speed_km_s))
    count, label = linked_clusters(particles.position[behind], link * case.shield.spacing_cm)
    mass = np.bincount(label, weights=particles.mass[behind])
    top = np.argsort(mass)[::-1][:3]
    rho0 = get_material(case.projectile.material).rho0
    projectile = rho0 * np.pi / 6.0 * case.projectile.diameter_cm**3 / 2.0      # the half model's
    density = np.array([particles.density[behind][label == t].mean() / rho0 for t in top])
    m, v = particles.mass[behind], particles.velocity[behind]
    speed = np.array([np.linalg.norm(m[label == t] @ v[label == t]) / m[label == t].sum() for t in top])
    sizes = np.array([np.count_nonzero(label == t) for t in top])
    return count, mass[top] / projectile, density, speed * KM_S_PER_CM_US, sizes


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", nargs="+", type=Path)
    ap.add_argument("--links", type=float, nargs="+", default=[1.05, 1.2, 1.5])
    ap.add_argument("--min-speed", type=float, default=1.0, help="km/s towards the wall (0: every particle)")
    args = ap.parse_args()
    print("| run | link / spacing | clusters | three largest / half projectile | their ρ/ρ₀ | their speed (km/s) "
          "| their particles |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for run in args.runs:
        for link in args.links:
            count, share, density, speed, sizes = clusters(run, link, args.min_speed)
            print(f"| {run.name} | {link:g} | {count} | {', '.join(f'{x:.4f}' for x in share)} | "
                  f"{', '.join(f'{x:.2f}' for x in density)} | {', '.join(f'{x:.2f}' for x in speed)} | "
                  f"{', '.join(map(str, sizes))} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
