"""Probe for issue 31's next step (b2): is the stretching rate of failed material converged when it is
measured on a length of the material's own rather than the SPH kernel's?

The shield stage records each failed particle's kernel-scale stretching rate when it breaks
(``Particles.failure_strain_rate``); it grows as the particle spacing shrinks (about Δ^{-0.6}).  After
break-up the pieces fly freely, so their relative velocities are frozen: the rate at which the
material was pulled apart can be read at hand-off as the gradient of the velocity with respect to the
**reference** (initial) positions, fitted by least squares over the failed particles within a radius
r = max(s/2, 1.6 Δ) of each one, with s Grady's size at that rate (iterated to a fixed point,
``--iterations``).  This script compares both rates, and the sizes, at two spacings.

    python studies/fragments/rate_probe.py                       # 6 km/s, t/D 0.2, Δ = d/10 and d/20

Not a product path: a measurement to decide whether the rate so measured converges (the gate of
validation/set-4-decision.md asks for the fragments within 20 % at d/10 and d/20).
"""

from __future__ import annotations

import argparse

import numpy as np
from scipy.spatial import cKDTree

from impactdyn import shield
from impactdyn.materials import get_material

DIAMETER_CM = 0.3175
MATERIAL = "al6061-t6"


def material_scale_rates(reference, velocity, spacing, material, iterations):
    """Largest principal value of sym(∂v/∂X) over the neighbours within max(s/2, 1.6 Δ), with s Grady's
    size at that rate (µs⁻¹; NaN where fewer than 5 neighbours); and s (cm)."""
    mat = get_material(material)
    tree = cKDTree(reference)
    size = np.full(len(reference), 0.06)
    rates = np.full(len(reference), np.nan)
    for _ in range(iterations):
        for j in range(len(reference)):
            near = tree.query_ball_point(reference[j], max(0.5 * size[j], 1.6 * spacing))
            if len(near) < 5:
                continue
            design = np.column_stack([np.ones(len(near)), reference[near] - reference[j]])
            coef, *_ = np.linalg.lstsq(design, velocity[near], rcond=None)
            gradient = coef[1:].T
            rates[j] = max(np.linalg.eigvalsh(0.5 * (gradient + gradient.T)).max(), 1e-9)
        found = np.isfinite(rates)
        size[found] = shield.grady_fragment_size(mat.fracture_toughness.K_Ic, mat.rho0, mat.young_modulus,
                                                 rates[found])
    return rates, size


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speed", type=float, default=6.0)
    parser.add_argument("--ratio", type=float, default=0.2)
    parser.add_argument("--spacings", type=float, nargs="+", default=[DIAMETER_CM / 10, DIAMETER_CM / 20])
    parser.add_argument("--time", type=float, default=3.0)
    parser.add_argument("--iterations", type=int, default=4)
    args = parser.parse_args()
    print("| Δ cm | failed | kernel rate at failure, 10/50/90 % (10⁶ s⁻¹) | material-scale rate, 10/50/90 % "
          "(10⁶ s⁻¹) | Grady s median (cm) | failed mass with s ≥ 0.06 cm |")
    print("| --- | --- | --- | --- | --- | --- |")
    for spacing in args.spacings:
        problem = shield.sphere_on_plate(MATERIAL, MATERIAL, DIAMETER_CM, args.speed, 0.0,
                                         args.ratio * DIAMETER_CM, spacing)
        state = shield.run(problem, args.time, options=shield.SPHOptions(failure_model="fragmentation")).state
        failed = (state.damage >= 1.0) & (state.failure_strain_rate > 0.0)
        rates, size = material_scale_rates(problem.particles.position[failed], state.velocity[failed], spacing,
                                           MATERIAL, args.iterations)
        found = np.isfinite(rates)
        mass = state.mass[failed][found]
        kernel = np.quantile(state.failure_strain_rate[failed], [0.1, 0.5, 0.9])
        scale = np.quantile(rates[found], [0.1, 0.5, 0.9])
        coarse = mass[size[found] >= 0.06].sum() / mass.sum()
        print(f"| {spacing:g} | {int(failed.sum())} | {' / '.join(f'{r:.2f}' for r in kernel)} "
              f"| {' / '.join(f'{r:.2f}' for r in scale)} | {np.median(size[found]):.4f} | {coarse:.3f} |",
              flush=True)


if __name__ == "__main__":
    main()
