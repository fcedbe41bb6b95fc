"""Beam sample runs: impactdyn (compiled Rosenbrock) against a plain SciPy baseline.

The baseline is what a straightforward port looks like: the same equations with a
NumPy right-hand side in Python, SciPy's LSODA through ``solve_ivp`` (finite-difference
Jacobian, no compilation), terminal events for impacts (IMPACTC) or the Hertz force
inside the right-hand side (IMPACTB). Same tolerances (rtol 1e-8, atol 1e-11).

    python benchmarks/bench_beam.py [--repeat 5]
"""

from __future__ import annotations

import argparse
import platform
import statistics
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

from impactdyn.beam import BeamModel, listing_restitution, load_case, simulate
from impactdyn.beam._simulate import initial_state, torque_schedule
from _machine import describe_machine

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "beam"


def baseline(case) -> tuple[float, float]:
    """Plain SciPy run of a sample case; returns (first impact time, approach speed)."""
    m = BeamModel.from_case(case)
    n, sc = m.n, m.sc
    rho_l, j0, c, g_th, g_mod, arm = sc[0], sc[1], sc[2], sc[4], sc[5], sc[8]
    M = m.mass_matrix(np.zeros(m.n_state))
    corners, torques = torque_schedule(case)
    hertz = case.contact.model == "hertz"
    J = m.jacobian_row()

    def rhs(t, y):
        th, q, thd, qd = y[0], y[1 : n + 1], y[n + 1], y[n + 2 :]
        tau = torques[np.searchsorted(corners, t, side="left")]
        f = 0.0
        if hertz:
            g = J[0] * th + q @ m.phi_p
            if g < 0:
                d, dd = -g, -(J[0] * thd + qd @ m.phi_p)
                f = max(0.0, case.contact.stiffness_N_m1_5 * d * (np.sqrt(d) + 0.75 * case.contact.damping_s_m * dd))
        Q0 = tau - c * thd - g_th * np.cos(th) + f * arm
        Qq = (-m.kd * q - thd**2 * ((m.G - rho_l * np.eye(n)) @ q) - m.cd * qd
              - g_mod * m.b * np.cos(th) + f * m.phi_p)
        acc = np.linalg.solve(M, np.concatenate([[Q0], Qq]))
        return np.concatenate([[thd], qd, acc])

    y = initial_state(case, m)[: 2 * n + 2]
    t, t_end = case.time.start_s, case.time.end_s
    t_eval = np.arange(t, t_end + 1e-12, case.time.output_step_s)
    first = None
    if hertz:
        sol = solve_ivp(rhs, (t, t_end), y, method="LSODA", rtol=1e-8, atol=1e-11, t_eval=t_eval)
        gaps = J[0] * sol.y[0] + m.phi_p @ sol.y[1 : n + 1]
        return float(sol.t[np.argmax(gaps < 0)]), float("nan")

    def strike(t, y):
        return J[0] * y[0] + y[1 : n + 1] @ m.phi_p

    strike.terminal, strike.direction = True, -1
    rest = case.contact.rest_velocity_m_s
    while t < t_end:
        sol = solve_ivp(rhs, (t, t_end), y, method="LSODA", rtol=1e-8, atol=1e-11, events=strike,
                        t_eval=t_eval[t_eval > t], first_step=1e-7)
        if sol.status != 1:
            break
        t, y = sol.t_events[0][0], sol.y_events[0][0].copy()
        v = y[n + 1 :]
        v_app = -(J @ v)
        if first is None:
            first = (t, v_app)
        if v_app < rest:  # the baseline simply stops chattering by a plastic impact
            e = 0.0
        else:
            e = listing_restitution(v_app)
        minv_j = np.linalg.solve(M, J)
        y[n + 1 :] = v - (1 + e) * (J @ v) / (J @ minv_j) * minv_j
        t = t + 1e-9  # step off the stop, as a plain port must, to re-arm the event
        if len(sol.t_events[0]) and t_end - t < 1e-9:
            break
    return first


def median_time(fn, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--baseline-repeat", type=int, default=3)
    args = ap.parse_args()
    print(f"machine: {describe_machine()}, {platform.platform()}")
    print("| sample | impactdyn median (s) | baseline median (s) | speed-up | first impact (ours / baseline) |")
    print("|---|---|---|---|---|")
    for name in ("impactc_sample", "impactb_sample"):
        case = load_case(EXAMPLES / f"{name}.toml")
        simulate(case)  # compile / load the numba cache outside the timing
        ours, r = median_time(lambda: simulate(case), args.repeat)
        base, b = median_time(lambda: baseline(case), args.baseline_repeat)
        print(f"| {name} | {ours:.3f} | {base:.3f} | {base / ours:.1f}x | "
              f"{r.impacts[0].t_start:.7f} / {b[0]:.7f} |")


if __name__ == "__main__":
    main()
