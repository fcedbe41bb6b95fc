"""Time the debris-particle integrators and measure their arrival-vertex error (DESIGN §5).

A synthetic aluminium debris cloud: N tetrahedral particles cut from cells of
edge 0.03175 cm (the five tetrahedra of each cell), each with its own random
affine velocity field — a bulk 0.7 cm/µs along y, perturbed by a few per cent in
its mean and across the particle — and a flight time uniform in
[0.5, t_max] µs. ParticleMaterial: ρ_ref 2.703 g/cm³, μ 0.276 Mbar, λ 0.56 Mbar,
η 1 Mbar·µs (the value DC3D's ELDATA hard-codes), ζ 0.

Each configuration propagates all N particles (after a warm-up that compiles it);
the error is that of the four arrival vertices c + F (xₖ − c₀) against scipy's
DOP853 at rtol 1e-12 on a random subset of particles.

    python benchmarks/bench_debris_integrators.py [N] [--n-ref 16] [--t-max 15] [--seed 0]

Prints a markdown table, and the speed ratio of the default integrator over
legacy at eps = 1e-6.

Deposition equivalence (issue 13): with ``--equivalence RUN [RUN ...]`` (Whipple run
folders with a ``debris/`` stage, e.g. of ``impactdyn whipple run
examples/whipple/table2_7a.toml``) the debris stage of each run (``run_debris``
from its hand-off grid: seeding, propagation, deposition) is repeated with the run's
own integrator, :data:`DEFAULT` and each ``--methods`` entry, and the script prints
the stage's wall time and the L1 difference of the wall's element impulses relative
to the total impulse (:func:`impulse_difference`) against DEFAULT.
"""

from __future__ import annotations

import argparse
import time

import numba
import numpy as np
from scipy.integrate import solve_ivp

from impactdyn.debris._integrators import IntegratorOptions, propagate
from impactdyn.debris._particle import F_SLICE, ParticleMaterial, C_SLICE, state_rates
from impactdyn.debris._tets import initial_state, tet_vertices
from _machine import describe_machine

ALUMINIUM = ParticleMaterial(mu=0.276, lam=0.56, rho_ref=2.703, eta=1.0, zeta=0.0)
CELL = 0.03175
BULK_VELOCITY = np.array([0.0, 0.7, 0.0])
DEFAULT = ("splitting4", {})
CONFIGURATIONS = [
    ("legacy", {"eps": 1e-6}),
    ("rk45", {"eps": 1e-6}),
    ("rk45", {"eps": 1e-8}),
    ("verlet", {"steps_per_period": 8}),
    ("verlet", {"steps_per_period": 32}),
    ("verlet", {"steps_per_period": 128}),
    ("splitting4", {"steps_per_period": 4}),
    ("splitting4", {"steps_per_period": 6}),
    DEFAULT,
    ("splitting4", {"steps_per_period": 16}),
    ("slow", {}),
    ("slow", {"steps_per_period": 48}),
]


def synthetic_cloud(n: int, t_max: float, rng: np.random.Generator):
    """Vertices ``(n, 4, 3)``, states ``(n, 33)``, J ``(n, 3, 3)``, m, t_end ``(n,)``."""
    n_cells = -(-n // 5)
    side = int(np.ceil(n_cells ** (1 / 3)))
    index = np.stack(np.unravel_index(np.arange(n_cells), (side,) * 3), axis=-1)
    x = tet_vertices(index * CELL, np.full(3, CELL)).reshape(-1, 4, 3)[:n]
    m = ALUMINIUM.rho_ref * np.abs(np.linalg.det(x[:, 1:] - x[:, :1])) / 6
    centre = x.mean(axis=1, keepdims=True)
    mean_velocity = BULK_VELOCITY * (1 + 0.03 * rng.standard_normal((n, 1, 3)))
    # a gradient that changes the velocity by ~3 % of the bulk speed across a cell
    gradient = 0.03 * np.linalg.norm(BULK_VELOCITY) / CELL * rng.standard_normal((n, 3, 3))
    v = mean_velocity + np.einsum("nij,nkj->nki", gradient, x - centre)
    states, J = initial_state(x, v, m)
    return x, states, J, m, rng.uniform(0.5, t_max, n)


def arrival_vertices(states, x0):
    """c + F (xₖ − c₀) of each particle, ``(n, 4, 3)``."""
    F = states[:, F_SLICE].reshape(-1, 3, 3)
    c0 = x0.mean(axis=1, keepdims=True)
    return states[:, None, C_SLICE] + np.einsum("nij,nkj->nki", F, x0 - c0)


def reference_states(states, J, m, t_end):
    """DOP853 at rtol 1e-12 (scipy), one particle at a time."""
    V0 = ALUMINIUM.reference_volume(m)
    out = np.empty_like(states)
    for k in range(len(states)):
        sol = solve_ivp(lambda t, y: state_rates(y, J[k], m[k], V0[k], ALUMINIUM), (0.0, t_end[k]),
                        states[k], method="DOP853", rtol=1e-12, atol=1e-16 + 1e-14 * np.abs(states[k]))
        if sol.status != 0:
            raise RuntimeError(f"reference failed for particle {k}: {sol.message}")
        out[k] = sol.y[:, -1]
    return out


def impulse_difference(impulse, reference) -> float:
    """Σₑ |Iₑ − Iₑʳᵉᶠ| / Σₑ |Iₑʳᵉᶠ|: L1 over the face elements e of the element impulse vectors ``(nx, nz, 3)``.

    |·| is the Euclidean norm of an element's impulse vector; 0 when every element
    receives the same impulse as with the reference integrator.
    """
    return float(np.linalg.norm(impulse - reference, axis=-1).sum() / np.linalg.norm(reference, axis=-1).sum())


def deposition_equivalence(run: str, methods: list[str]) -> None:
    """Repeat a Whipple run's debris stage with its own integrator, DEFAULT and ``methods``; print a row each."""
    from pathlib import Path

    from impactdyn.debris import build, load_debris_case, run_debris

    case = load_debris_case(Path(run) / "debris" / "config.resolved.toml")
    kwargs = build(case, source=run)
    own = case.integrator
    step = {} if own.steps_per_period is None else dict(steps_per_period=own.steps_per_period)
    runs = {f"{label(own.method, step)} (the run's own)": own}
    for method in [DEFAULT[0], *methods]:  # each at its default step
        runs[label(method, {})] = IntegratorOptions(method=method, max_steps=own.max_steps)
    results = {}
    for name, integrator in runs.items():
        w0 = time.perf_counter()
        result = run_debris(**{**kwargs, "integrator": integrator})
        results[name] = (time.perf_counter() - w0, result)
    _, ref = results[label(*DEFAULT)]
    for name, (w, result) in results.items():
        print(f"| {Path(run).name} | {name} | {w:.1f} | {result.stats.steps.mean():.0f} "
              f"| {result.stats.n_failed} | {impulse_difference(result.impulse, ref.impulse):.2e} |")


def label(method: str, options: dict) -> str:
    return method + "".join(f", {k}={v:g}" for k, v in options.items())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("n", nargs="?", type=int, default=100_000, help="number of particles")
    parser.add_argument("--n-ref", type=int, default=16, help="particles checked against DOP853")
    parser.add_argument("--t-max", type=float, default=15.0, help="longest flight time (µs)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--equivalence", nargs="+", metavar="RUN", help="Whipple run folders (only this part runs)")
    parser.add_argument("--methods", nargs="+", default=["slow"], help="integrators compared with the default")
    parser.add_argument("--only", nargs="+", metavar="METHOD", help="time only these methods' configurations")
    args = parser.parse_args()
    if args.equivalence:
        print("| run | integrator | debris stage wall (s) | steps/particle | failed "
              "| L1 impulse difference vs default |")
        print("|---|---|---|---|---|---|")
        for run in args.equivalence:
            deposition_equivalence(run, args.methods)
        return

    rng = np.random.default_rng(args.seed)
    x0, states, J, m, t_end = synthetic_cloud(args.n, args.t_max, rng)
    subset = rng.choice(args.n, size=min(args.n_ref, args.n), replace=False)
    t0 = time.perf_counter()
    reference = arrival_vertices(reference_states(states[subset], J[subset], m[subset], t_end[subset]),
                                 x0[subset])
    t_reference = time.perf_counter() - t0

    rows, wall, cpu, worst = [], {}, {}, {}
    for method, options in CONFIGURATIONS:
        if args.only and method not in args.only:
            continue
        propagate(states[:8], J[:8], m[:8], t_end[:8] * 1e-3, ALUMINIUM, method=method, **options)
        w0, c0 = time.perf_counter(), time.process_time()
        out, stats = propagate(states, J, m, t_end, ALUMINIUM, method=method, **options)
        w, c = time.perf_counter() - w0, time.process_time() - c0
        error = np.linalg.norm(arrival_vertices(out[subset], x0[subset]) - reference, axis=-1).max(axis=1)
        wall[label(method, options)], cpu[label(method, options)] = w, c
        worst[label(method, options)] = error.max()
        steps = stats.steps.sum()
        rows.append(f"| {label(method, options)} | {w:.2f} | {c:.2f} | {steps / args.n:.0f} "
                    f"| {100 * stats.rejected.sum() / max(1, steps):.1f} | {steps / w:.3g} "
                    f"| {error.max():.2e} | {np.median(error):.2e} | {stats.n_failed} |")

    print(f"N = {args.n} particles, flight 0.5–{args.t_max:g} µs (mean {t_end.mean():.2f}), "
          f"reference: DOP853 rtol 1e-12 on {len(subset)} particles ({t_reference:.0f} s); "
          f"{describe_machine()}, "
          f"numba {numba.__version__} with {numba.get_num_threads()} threads\n")
    print("| integrator | wall (s) | CPU (s) | steps/particle | rejected (%) | particle-steps/s (wall) "
          "| max vertex error (cm) | median vertex error (cm) | failed |")
    print("|---|---|---|---|---|---|---|---|---|")
    print("\n".join(rows))
    legacy, default = label("legacy", {"eps": 1e-6}), label(*DEFAULT)
    if legacy in wall and default in wall:
        print(f"\nspeed ratio {default} (default) over legacy at eps=1e-6: wall {wall[legacy] / wall[default]:.1f}×, "
              f"CPU {cpu[legacy] / cpu[default]:.1f}×; max vertex error {worst[default]:.2e} against "
              f"{worst[legacy]:.2e} cm")

if __name__ == "__main__":
    main()
