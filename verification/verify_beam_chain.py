"""Coupled and linearised modal models against the rigid-link chain (verification record).

The chain (``impactdyn.beam._chain``) is an independent, fully nonlinear model of the
same hub and beam. This script prints, for the record in BENCHMARKS.md:

1. the chain's clamped frequencies against Euler–Bernoulli (second-order convergence);
2. spin-up cases (torque ±τ for 50 ms each, no gravity, no stop; 0.2 s): max |Δθ| and
   max |Δw_tip| of each modal model (n modes) against the chain, whose reference is
   Richardson's extrapolation of the two finest chains (error ∝ 1/N²); its
   uncertainty is the change from the extrapolation one level coarser;
3. the same for the *nonlinear part* of the hub angle, θ(τ) − θ₀ − (τ/τₛ)(θ(τₛ) − θ₀) with
   a small torque τₛ, computed alike for every model and chain: it removes what is
   linear in τ, where the two discretisations differ by a floor that has nothing to do
   with large deflections (with the light hub, a torque step sets the hub ringing at
   frequencies the chain resolves only slowly: max |Δθ| of the linearised model at
   τₛ = 0.1 N·m is 2e-5 rad whatever n, about 2e-4 rad per N·m), and leaves the
   large-deflection physics the ``coupled`` option is about;
4. the smallest Schur complement s(q) = M₀₀ − M₀ᵀM_qq⁻¹M₀ of the coupled mass matrix along
   the coupled run, relative to s(0) (≤ 0 would be a singular mass matrix).

    python verification/verify_beam_chain.py [--links 8,16,32] [--modes 4] [--inertia-ratio 1.0]
"""

from __future__ import annotations

import argparse
import time
import tomllib
from pathlib import Path

import numpy as np

from impactdyn._config import validate
from impactdyn.beam import BeamCase, BeamModel, RigidLinkChain, SimulationError, eigenvalues, simulate

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "beam" / "impactc_sample.toml"
CASES = [(1.0, 1.0), (1.0, 2.0), (1.0, 3.0), (0.002, 0.5), (0.002, 1.0), (0.002, 2.0)]  # (IR, τ in N·m)
THETA0 = 0.5


def spin_up_case(inertia_ratio: float, torque: float, n_modes: int, coupled: bool) -> BeamCase:
    raw = tomllib.loads(EXAMPLE.read_text())
    raw["beam"]["inertia_ratio"] = inertia_ratio
    raw["torque"] = {"amplitude_N_m": torque, "pulse_duration_s": 0.05, "zero_fraction": 0.0}
    raw["model"] = {"n_modes": n_modes, "gravity_m_s2": 0.0, "coupled": coupled}
    raw["initial"] = {"theta_rad": THETA0}
    raw["time"] = {"end_s": 0.2, "output_step_s": 2e-4}
    raw["output"]["response_point_m"] = raw["beam"]["length_m"]
    raw["solver"] = {"rtol": 1e-10, "atol": 1e-13}
    return validate(BeamCase, raw)


def richardson(a, b, n_a, n_b):
    return (n_b**2 * b - n_a**2 * a) / (n_b**2 - n_a**2)


def nonlinear_part(theta, theta_small, torque, small_torque):
    """θ(τ) − θ₀ − (τ/τₛ)(θ(τₛ) − θ₀): the hub angle less its part linear in τ."""
    return theta - THETA0 - torque / small_torque * (theta_small - THETA0)


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
    """min over states (m, 2n + 7) of s(q) = M₀₀ − M₀ᵀM_qq⁻¹M₀ of ``model``'s mass matrix, over s(0)."""
    def schur(state):
        M = model.mass_matrix(state)
        return M[0, 0] - M[0, 1:] @ np.linalg.solve(M[1:, 1:], M[1:, 0])

    return min(schur(state) for state in y) / schur(np.zeros_like(y[0]))


def chain_runs(case, t, links):
    """Hub angle and tip deflection of the chains with ``links`` links, {N: (θ, w)}."""
    out = {}
    for N in links:
        r = RigidLinkChain.from_case(case, N).simulate(case, t)
        out[N] = (r.theta, r.tip_deflection)
    return out


def reference(runs, links):
    """Richardson's extrapolation of the two finest of ``runs`` (arrays by N) and its
    uncertainty, max |change| from the extrapolation one level coarser."""
    n1, n2, n3 = links[-3:]
    ref = richardson(runs[n2], runs[n3], n2, n3)
    return ref, np.max(np.abs(ref - richardson(runs[n1], runs[n2], n1, n2)))


def spin_ups(links, n_modes, inertia_ratios, small_torque):
    print(f"\nspin-up, {n_modes} modes, chains of {links} links: max |Δθ| (rad) and max |Δw_tip| (m) against the"
          f" chain; nonlinear part with τₛ = {small_torque} N·m; s(q)/s(0): coupled mass matrix, min along its run;"
          " wall time of each modal run (rtol 1e-10)")
    print("| IR | τ (N·m) | tip/L | chain ref. unc. θ / w | linear Δθ / Δw | coupled Δθ / Δw | coupled/linear Δθ "
          "| nonlinear part: ref. unc. / linear / coupled Δ | coupled/linear | s(q)/s(0) | run linear / coupled (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    links = links[-3:]
    for ir in sorted(inertia_ratios, reverse=True):
        small = {c: simulate(spin_up_case(ir, small_torque, n_modes, c)) for c in (False, True)}
        small_chain = chain_runs(small[False].case, small[False].t, links)
        for tau in [tau for i, tau in CASES if i == ir]:
            base = spin_up_case(ir, tau, n_modes, False)
            runs, wall = {}, {}
            for c in (False, True):
                t0 = time.perf_counter()
                try:
                    runs[c] = simulate(spin_up_case(ir, tau, n_modes, c))
                except SimulationError as exc:
                    runs[c] = exc
                wall[c] = time.perf_counter() - t0
            ch = chain_runs(base, runs[False].t, links)
            th, unc_th = reference({N: ch[N][0] for N in links}, links)
            w, unc_w = reference({N: ch[N][1] for N in links}, links)
            nl, unc_nl = reference({N: nonlinear_part(ch[N][0], small_chain[N][0], tau, small_torque)
                                    for N in links}, links)
            cells, d_th, d_nl = [], {}, {}
            for c, r in runs.items():
                if isinstance(r, SimulationError):
                    cells.append(f"fails: {r}")
                    continue
                d_th[c] = np.max(np.abs(r.theta - th))
                d_nl[c] = np.max(np.abs(nonlinear_part(r.theta, small[c].theta, tau, small_torque) - nl))
                cells.append(f"{d_th[c]:.2e} / {np.max(np.abs(r.model.deflection(r.y) - w)):.2e}")
            ok = True in d_th
            margin = f"{schur_margin(runs[True].model, runs[True].y):.4f}" if ok else "–"
            print(f"| {ir} | {tau} | {np.max(np.abs(w)) / base.beam.length_m:.3f} | {unc_th:.1e} / {unc_w:.1e} | "
                  f"{cells[0]} | {cells[1]} | {d_th[True] / d_th[False] if ok else float('nan'):.2f} | "
                  f"{unc_nl:.1e} / {d_nl[False]:.2e} / {d_nl[True] if ok else float('nan'):.2e} | "
                  f"{d_nl[True] / d_nl[False] if ok else float('nan'):.3f} | {margin} | {wall[False]:.1f} / {wall[True]:.1f} |",
                  flush=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--links", default="8,16,32", help="chain sizes, at least three (the last two extrapolated)")
    ap.add_argument("--modes", type=int, default=4)
    ap.add_argument("--inertia-ratio", type=float, action="append",
                    help="run only the spin-up cases of this hub (repeatable; default: all)")
    ap.add_argument("--small-torque", type=float, default=0.1, help="τₛ of the nonlinear part (N·m)")
    args = ap.parse_args()
    links = [int(x) for x in args.links.split(",")]
    frequencies(links + [2 * links[-1], 4 * links[-1]])
    spin_ups(links, args.modes, args.inertia_ratio or {ir for ir, _ in CASES}, args.small_torque)


if __name__ == "__main__":
    main()
