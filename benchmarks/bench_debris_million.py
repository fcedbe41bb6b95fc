"""The issue-3/13 scale benchmark: N synthetic Al particles all flying 15 µs with a registered integrator.

Same synthetic cloud as ``bench_debris_integrators.py`` (cells of 0.03175 cm, bulk
0.7 cm/µs, random affine perturbations; ρ_ref 2.703, μ 0.276, λ 0.56, η 1), but
every particle flies the full ``--flight`` µs.  Runs ``n`` particles through
:func:`impactdyn.debris.propagate_chunked` (the driver's chunked path) and
reports the wall time, particle-steps per second, the time scaled to 1,000,000
particles (particles are independent: the cost is linear in N), and a flop-rate
estimate from a hand count of the integrator's step (:data:`FLOPS_PER_STEP`).

    python benchmarks/bench_debris_million.py [N] [--flight 15] [--integrator splitting4] [--steps-per-period S]

``--integrator slow`` is the slow-manifold integrator of issue 13, whose
steps_per_period counts steps per rigid rotation period (:mod:`impactdyn.debris._slow_manifold`).
"""

from __future__ import annotations

import argparse
import time

import numba
import numpy as np

from bench_debris_integrators import ALUMINIUM, synthetic_cloud
from impactdyn.debris import INTEGRATORS, ComputeOptions, IntegratorOptions, ParticleCloud, propagate_chunked
from impactdyn.debris._splitting import BLANES_MOAN_S6, VERLET
from _machine import describe_machine

#: Floating-point operations of a splitting step, counted by hand from the kernels (ζ = 0): a
#: stage (drift H J⁻¹; C = FᵀF, E', det F, adj C, S, F S and the kick; Eₚ relaxed) ~290, plus
#: the closing drift and the failure check ~130.
FLOPS_PER_STAGE, FLOPS_PER_STEP_EXTRA = 290, 130
#: Hand counts per step: the splittings by their stages; ``slow``: twenty
#: body-axis rotations of ~45 flops (angle, tan series, Cayley c and s, π and two columns of P turned).
FLOPS_PER_STEP = {"verlet": FLOPS_PER_STAGE * len(VERLET[1]) + FLOPS_PER_STEP_EXTRA,
                  "splitting4": FLOPS_PER_STAGE * len(BLANES_MOAN_S6[1]) + FLOPS_PER_STEP_EXTRA,
                  "slow": 20 * 45}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("n", nargs="?", type=int, default=1_000_000)
    parser.add_argument("--flight", type=float, default=15.0, help="flight time of every particle (µs)")
    parser.add_argument("--integrator", "--method", choices=sorted(INTEGRATORS), default=IntegratorOptions().method)
    parser.add_argument("--steps-per-period", type=float, default=None, help="default: the method's own")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    x0, states, J, m, _ = synthetic_cloud(args.n, args.flight, np.random.default_rng(args.seed))
    n = len(m)
    cloud = ParticleCloud(vertices=x0, states=states, J=J, mass=m, void_fraction=np.zeros(n),
                          density_ratio=np.ones(n), cell=np.zeros((n, 3), int), tet=np.zeros(n, int))
    t_end = np.full(n, args.flight)
    options = IntegratorOptions(method=args.integrator, steps_per_period=args.steps_per_period)
    spp = options.steps_per_period
    propagate_chunked(cloud.subset(slice(0, 8)), t_end[:8] * 1e-3, ALUMINIUM, options)  # compile
    w0 = time.perf_counter()
    _, stats = propagate_chunked(cloud, t_end, ALUMINIUM, options, ComputeOptions())
    wall = time.perf_counter() - w0
    steps = stats.steps.sum()
    print(f"{describe_machine()}, numba {numba.__version__}, "
          f"{numba.get_num_threads()} threads")
    flops = (f"~{FLOPS_PER_STEP[args.integrator] * steps / wall / 1e9:.2f} GFLOP/s "
             f"(hand count {FLOPS_PER_STEP[args.integrator]} flops/step)" if args.integrator in FLOPS_PER_STEP
             else "no flop count")
    print(f"N = {n}, flight {args.flight:g} µs, {args.integrator} "
          f"{'its default' if spp is None else format(spp, 'g')} steps/period: "
          f"wall {wall:.2f} s, {steps / n:.0f} steps/particle, {steps / wall:.3g} particle-steps/s, "
          f"scaled to 1e6 particles: {wall * 1e6 / n:.0f} s, "
          f"{flops}, failed {stats.n_failed}")


if __name__ == "__main__":
    main()
