"""Where a wall solver step spends its time: the element pass and the node pass timed apart, and
the element pass's block kernels timed alone (issue 11; BENCHMARKS.md, "solver throughput").

The wall of :mod:`bench_wall` (the report's 50 × 4 × 100 elements, refined ``--refinement`` times
through the thickness and in the plane) under its synthetic deposition, advanced ``--advance`` µs
past the first arrival so that some elements yield; then, per hourglass form:

* the element pass and ``node_pass`` called alone ``--repeat`` times each (:mod:`impactdyn.wall._step`;
  the element pass with the current step, the node pass with a zero step so that nothing moves),
  median and fastest, in ns per element;
* with ``--kernels``, once after the forms: each block kernel of the element pass called 5,000 times
  on one block array (the thread's array after a real pass: data in L1, no gather), median of 7, in
  ns per element.
  Each call first nudges one input of that kernel (by 1e-300 × the call's index), so that the
  compiler cannot hoist an unchanged call out of the loop.

    python benchmarks/bench_wall_passes.py [--refinement 2] [--threads 1] [--model johnson_cook]
        [--forms viscous stiffness assumed_strain] [--repeat 30] [--advance 3] [--kernels]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numba
import numpy as np

from _machine import describe_machine
from bench_wall import bench_solver
from impactdyn import wall
from impactdyn.materials import get_material
from impactdyn.wall import _blocks, _hex, _hourglass, _kinematics, _step
from impactdyn.wall._state import EPS_P

#: The block kernels, in the element pass's order, and the row each one's nudge goes to (one of its inputs).
KERNELS = (("volume_gradient", _blocks.R_X), ("hourglass_shapes", _blocks.R_B), ("reciprocal_vectors", _blocks.R_B),
           ("velocity_gradients", _blocks.R_V), ("midstep_gradients", _blocks.R_LB),
           ("characteristic_lengths", _blocks.R_X), ("assumed_strain_forces", _blocks.R_QD),
           ("nodal_forces", _blocks.R_SIG), ("stable_steps", _blocks.R_C))


@numba.njit
def _repeat_kernel(A, which, calls, nudge_row, dt, lam, shear):
    for it in range(calls):
        A[nudge_row * _hex.BLOCK] += 1e-300 * it
        if which == 0:
            _hex.volume_gradient(A)
        elif which == 1:
            _hex.hourglass_shapes(A)
        elif which == 2:
            _kinematics.reciprocal_vectors(A)
        elif which == 3:
            _kinematics.velocity_gradients(A)
        elif which == 4:
            _kinematics.midstep_gradients(A, 0.5 * dt)
        elif which == 5:
            _hex.characteristic_lengths(A)
        elif which == 6:
            _hourglass.assumed_strain_forces(A, dt, lam, shear)
        elif which == 7:
            _step.nodal_forces(A)
        else:
            _step.stable_steps(A, 1.5, 0.06)


def solver_after_load(refinement: int, model_name: str, form: str, advance_us: float) -> wall.WallSolver:
    """The bench wall's solver, ``advance_us`` past the synthetic load's first arrival."""
    solver = bench_solver(refinement, form, model_name)
    solver.advance(solver.time + advance_us)
    return solver


def time_passes(solver: wall.WallSolver, repeat: int) -> tuple[list[float], list[float]]:
    """Seconds per call of the element pass and of the node pass, ``repeat`` calls each."""
    dt = float(solver.clock[_step.DT_NEXT])
    element, node = [], []
    for _ in range(repeat):
        t0 = time.perf_counter()
        solver.element_pass(dt, dt)
        element.append(time.perf_counter() - t0)
    for _ in range(repeat):
        t0 = time.perf_counter()
        _step.node_pass(solver.nodes, solver.elements, False, 0.0, 0.0)
        node.append(time.perf_counter() - t0)
    return element, node


def time_kernels(solver: wall.WallSolver, calls: int = 5000) -> dict[str, float]:
    """ns per element of each block kernel on the solver's first block array (median of 7 runs); the
    assumed-strain kernel with the library aluminium's elastic constants (its cost does not depend on them)."""
    material = get_material("al6061-t6")
    shear = material.shear_modulus
    lam = material.rho0 * material.c0 ** 2 - 2.0 / 3.0 * shear
    dt = float(solver.clock[_step.DT_NEXT])
    out = {}
    for which, (name, row) in enumerate(KERNELS):
        runs = []
        for _ in range(8):  # the first compiles the driver (or loads it) and warms the caches
            A = solver.work[0].copy()
            t0 = time.perf_counter()
            _repeat_kernel(A, which, calls, row, dt, lam, shear)
            runs.append(time.perf_counter() - t0)
        out[name] = statistics.median(runs[1:]) / (calls * _hex.BLOCK) * 1e9
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--refinement", type=int, default=2)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--model", choices=sorted(wall.MODELS), default="johnson_cook")
    ap.add_argument("--forms", nargs="+", choices=wall.HOURGLASS_FORMS, default=list(wall.HOURGLASS_FORMS))
    ap.add_argument("--repeat", type=int, default=30)
    ap.add_argument("--advance", type=float, default=3.0, help="µs of the synthetic load before the timing")
    ap.add_argument("--kernels", action="store_true", help="also time the element pass's block kernels alone")
    args = ap.parse_args()
    numba.set_num_threads(args.threads)
    print(f"wall solver passes: {describe_machine()}, numba {numba.__version__}, {args.threads} thread(s), "
          f"model {args.model}, refinement {args.refinement}")
    for form in args.forms:
        solver = solver_after_load(args.refinement, args.model, form, args.advance)
        ne = solver.mesh.n_elements
        element, node = time_passes(solver, args.repeat)
        yielded = int(np.count_nonzero(solver.es[:, EPS_P] > 0.0))
        print(f"{form:15s} {ne} elements: element pass {statistics.median(element) / ne * 1e9:.0f} ns per element "
              f"(fastest {min(element) / ne * 1e9:.0f}), node pass {statistics.median(node) / ne * 1e9:.0f} "
              f"(fastest {min(node) / ne * 1e9:.0f}); {yielded} elements yielded")
    if args.kernels:  # the same block kernels whatever the form (the assumed-strain one only runs with its form)
        print("block kernels alone, one block in L1:")
        for name, ns in time_kernels(solver).items():
            print(f"    {name:24s} {ns:6.1f} ns per element")


if __name__ == "__main__":
    main()
