"""Coupled and linearised modal models against the rigid-link chain (verification record).

The chain (``impactdyn.beam._chain``) is an independent, fully nonlinear model of the
same hub and beam. This script prints, for the record in BENCHMARKS.md:

1. the chain's clamped frequencies against Euler–Bernoulli (second-order convergence);
2. spin-up cases (torque ±τ for 50 ms each, no gravity, no stop; 0.2 s): max |Δθ| and
   max |Δw_tip| of each modal model (n modes) against the chain, whose reference is
   Richardson's extrapolation of the two finest chains (error ∝ 1/N²); its
   uncertainty is the change from the extrapolation one level coarser.

    python benchmarks/bench_beam_chain.py [--links 8,16,32] [--modes 4] [--inertia-ratio 1.0]
"""

from __future__ import annotations

import argparse
import tomllib
from pathlib import Path

import numpy as np

from impactdyn._config import validate
from impactdyn.beam import BeamCase, BeamModel, RigidLinkChain, SimulationError, eigenvalues, simulate

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "beam" / "impactc_sample.toml"
CASES = [(1.0, 1.0), (1.0, 2.0), (1.0, 3.0), (0.002, 0.5), (0.002, 1.0), (0.002, 2.0)]  # (IR, τ in N·m)


def spin_up_case(inertia_ratio: float, torque: float, n_modes: int, coupled: bool) -> BeamCase:
    raw = tomllib.loads(EXAMPLE.read_text())
    raw["beam"]["inertia_ratio"] = inertia_ratio
    raw["torque"] = {"amplitude_N_m": torque, "pulse_duration_s": 0.05, "zero_fraction": 0.0}
    raw["model"] = {"n_modes": n_modes, "gravity_m_s2": 0.0, "coupled": coupled}
    raw["initial"] = {"theta_rad": 0.5}
    raw["time"] = {"end_s": 0.2, "output_step_s": 2e-4}
    raw["output"]["response_point_m"] = raw["beam"]["length_m"]
    raw["solver"] = {"rtol": 1e-10, "atol": 1e-13}
    return validate(BeamCase, raw)


def richardson(a, b, n_a, n_b):
    return (n_b**2 * b - n_a**2 * a) / (n_b**2 - n_a**2)


def frequencies(links):
    case = spin_up_case(1.0, 0.0, 3, False)
    bm = case.beam
    scale = np.sqrt(bm.EI_N_m2 / (bm.mass_per_length_kg_m * bm.length_m**4))
    beta_sq = eigenvalues(3) ** 2
    print("clamped frequencies, relative error ω_chain/ω_EB − 1 (modes 1–3):")
    for N in links:
        err = RigidLinkChain.from_case(case, N).clamped_frequencies()[:3] / scale / beta_sq - 1
        print(f"  N = {N:3d}: " + "  ".join(f"{e:+.3e}" for e in err))


def schur_margin(model: BeamModel, y: np.ndarray) -> float:
    """min over states (m, 2n + 7) of the coupled model's Schur complement
    M₀₀(q) − |M₀|²/ρL = s₀ + qᵀPq, relative to s₀ (q = 0); ≤ 0: singular mass matrix."""
    rho_l = model.sc[0]
    s0 = model.sc[1] - model.m0 @ model.m0 / rho_l
    q = model.split(y)[1]
    qpq = np.einsum("ti,ij,tj->t", q, rho_l * np.eye(model.n) - model.G, q)
    return float(np.min(s0 + qpq) / s0)


def spin_ups(links, n_modes, inertia_ratios):
    print(f"\nspin-up, {n_modes} modes; max |Δθ| (rad) and max |Δw_tip| (m) against the chain; last column:")
    print("min of the coupled model's Schur complement s(q)/s(0) along the linear run (≤ 0: singular)")
    print("| IR | τ (N·m) | tip/L | chain ref. unc. θ / w | linear Δθ / Δw | coupled Δθ / Δw | s(q)/s(0) |")
    print("|---|---|---|---|---|---|---|")
    n1, n2, n3 = links[-3:]
    for ir, tau in CASES:
        if ir not in inertia_ratios:
            continue
        base = spin_up_case(ir, tau, n_modes, False)
        linear = simulate(base)
        ch = {N: RigidLinkChain.from_case(base, N).simulate(base, linear.t) for N in (n1, n2, n3)}
        th = richardson(ch[n2].theta, ch[n3].theta, n2, n3)
        w = richardson(ch[n2].tip_deflection, ch[n3].tip_deflection, n2, n3)
        unc_th = np.max(np.abs(th - richardson(ch[n1].theta, ch[n2].theta, n1, n2)))
        unc_w = np.max(np.abs(w - richardson(ch[n1].tip_deflection, ch[n2].tip_deflection, n1, n2)))
        cells = []
        for r in (linear, None):
            if r is None:
                try:
                    r = simulate(spin_up_case(ir, tau, n_modes, True))
                except SimulationError as exc:
                    cells.append(f"fails: {exc}")
                    continue
            cells.append(f"{np.max(np.abs(r.theta - th)):.2e} / {np.max(np.abs(r.model.deflection(r.y) - w)):.2e}")
        print(f"| {ir} | {tau} | {np.max(np.abs(w)) / base.beam.length_m:.3f} | {unc_th:.1e} / {unc_w:.1e} | "
              f"{cells[0]} | {cells[1]} | {schur_margin(linear.model, linear.y):.2f} |", flush=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--links", default="8,16,32", help="chain sizes, at least three (the last two extrapolated)")
    ap.add_argument("--modes", type=int, default=4)
    ap.add_argument("--inertia-ratio", type=float, action="append",
                    help="run only the spin-up cases of this hub (repeatable; default: all)")
    args = ap.parse_args()
    links = [int(x) for x in args.links.split(",")]
    frequencies(links + [2 * links[-1], 4 * links[-1]])
    spin_ups(links, args.modes, args.inertia_ratio or {ir for ir, _ in CASES})


if __name__ == "__main__":
    main()
