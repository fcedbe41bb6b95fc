"""Element-steps per second of the wall solver on the report's wall (DESIGN §9, issue 11).

The Table 2 wall of the 1994 report: 51 × 5 × 101 nodes (50 × 4 × 100 elements of
0.16 × 0.079 × 0.16 cm, Al 6061-T6, the App. D type-13 card), DYNGEN's supports, loaded by
a synthetic deposition (a Gaussian patch of impulses on the front face arriving over 2 µs,
an 8 × 8 mm hot spot; the speed does not depend on the load while no element fails).
After a warm-up that compiles the kernels (or loads them from numba's cache) the run is
timed over a fixed number of steps, at the default mesh and at 2× refinement (through the
thickness and in the plane), with the steps driven two ways:

* ``compiled`` — the whole step loop in compiled code (the model's ``advance`` of
  :func:`impactdyn.wall._step.step_kernels` called once for all the timed steps; what
  :func:`impactdyn.wall.run_wall` does between history samples);
* ``python`` — a Python loop calling ``advance`` for one step at a time (the cost of the
  Python-side call per step).

    python benchmarks/bench_wall.py [--steps 200] [--threads 2] [--repeat 3]
        [--hourglass assumed_strain stiffness] [--material-model mat13] [--roofline]

``--roofline`` also measures the machine's memory bandwidth (a parallel STREAM triad,
a[i] = b[i] + s·c[i] over arrays of 3 × 64 MB, counted as 24 bytes per i: two reads and
one write) and prints, per mesh, the solver's state in bytes per element (the element
arrays plus the node arrays per element, :class:`impactdyn.wall.WallSolver`) and the
bytes per element-step that the measured rate would mean if memory traffic alone set it
(bandwidth / rate).  A step reads the state and writes most of it back, so a value near
twice the state says the rate is bound by memory, not by arithmetic.

``--hourglass`` takes one or more of :data:`impactdyn.wall.HOURGLASS_FORMS`; without it the
wall solver's default form (:class:`impactdyn.wall.WallOptions`; "assumed_strain" since
2026-11-24) is run, and the form is printed with every line.  With several forms the cases
alternate run by run (form A, form B, form A, ...) so that both see the same load.

Prints, per mesh and driver: elements, steps, element-steps per second of wall time (median of
the repeats) and per CPU-second of the process (all threads; on a machine shared with other
work the wall-time rate falls with the load, the CPU-time rate much less: threads × the
CPU-time rate is what the threads would do on cores of their own, if they scaled perfectly).  The numba threading layer and thread count are printed too: under CPU
oversubscription the OpenMP layer's spin-waiting costs milliseconds per parallel launch
(``OMP_WAIT_POLICY=passive`` avoids it).
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import numba
import numpy as np

from impactdyn import wall
from impactdyn.wallgrid import WallDeposition, WallGrid
from _machine import describe_machine


def report_wall() -> WallGrid:
    """The report's wall grid (examples/whipple/table2_7a.toml: x 0…8, z −4…12 cm, t = 0.3175 cm)."""
    return WallGrid.uniform((0.0, 8.0), (0.0, 0.3175), (-4.0, 12.0), (51, 5, 101))


def synthetic_deposition(grid: WallGrid, total_impulse: float = 0.05) -> WallDeposition:
    """Impulses normal to the wall in a Gaussian patch (σ = 0.4 cm) about (x, z) = (0, 1.5) cm, t 10…12 µs."""
    nx, _, nz = grid.shape
    xc = 0.5 * (grid.x[1:] + grid.x[:-1])
    zc = 0.5 * (grid.z[1:] + grid.z[:-1])
    w = np.exp(-0.5 * ((xc[None, :] / 0.4) ** 2 + ((zc[:, None] - 1.5) / 0.4) ** 2)).ravel()
    keep = np.flatnonzero(w > 1e-3 * w.max())
    w = w[keep] / w[keep].sum()
    time_us = 10.0 + 2.0 * np.linspace(0.0, 1.0, keep.size)
    impulse = np.zeros((keep.size, 3))
    impulse[:, 1] = total_impulse * w
    return WallDeposition(element=keep.astype(np.int64), time=time_us, impulse=impulse)


@numba.njit(parallel=True, cache=True)
def _triad(a, b, c, scale):
    for i in numba.prange(a.size):
        a[i] = b[i] + scale * c[i]


def triad_bandwidth(n: int = 8_000_000, repeat: int = 20) -> float:
    """Median bytes per second of the parallel triad over float64 arrays of ``n`` (24 bytes per element)."""
    a, b, c = np.zeros(n), np.ones(n), np.full(n, 2.0)
    _triad(a, b, c, 3.0)
    rates = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        _triad(a, b, c, 3.0)
        rates.append(24.0 * n / (time.perf_counter() - t0))
    return statistics.median(rates)


def state_bytes_per_element(solver: wall.WallSolver) -> float:
    """The solver's per-element and per-node arrays, in bytes per element."""
    nodes, elements = solver.nodes, solver.elements
    state = (nodes.x, nodes.v, nodes.mass, nodes.free, nodes.rear, elements.conn, elements.vol0, elements.mass,
             elements.S, elements.es, elements.flags, elements.Lbuf, elements.Qhg, elements.Shg, elements.F,
             elements.node_ptr, elements.node_entry)
    return sum(a.nbytes for a in state) / solver.mesh.n_elements


def bench_solver(refinement: int, hourglass: str | None = None, material_model: str = "mat13") -> wall.WallSolver:
    """The report's wall refined ``refinement`` times (thickness and plane) under the synthetic
    deposition, at its first arrival; ``hourglass`` None: the solver's default form."""
    grid = report_wall()
    options = wall.WallOptions(refinement_thickness=refinement, refinement_plane=refinement,
                               material_model=material_model)
    if hourglass is not None:
        options = options.replaced(hourglass=hourglass)
    model = wall.wall_model(material_model, "al6061-t6")
    mesh = wall.build_mesh(grid, model.density, refinement, refinement)
    load = wall.nodal_load(mesh, synthetic_deposition(grid), options.spread)
    return wall.WallSolver(mesh, model, options, load=load, t_start=float(load.time.min()))


def measure(refinement: int, steps: int, driver: str, hourglass: str | None = None,
            material_model: str = "mat13") -> tuple[int, int, float, float, float]:
    solver = bench_solver(refinement, hourglass, material_model)
    mesh = solver.mesh
    solver.advance(solver.time + 0.5)  # warm-up: compile or load the kernels, apply the first loads
    n0 = solver.steps
    t0, c0 = time.perf_counter(), time.process_time()
    if driver == "compiled":
        solver.advance(np.inf, max_steps=steps)
    else:
        for _ in range(steps):
            solver.advance(np.inf, max_steps=1)
    elapsed, cpu = time.perf_counter() - t0, time.process_time() - c0
    return mesh.n_elements, solver.steps - n0, elapsed, cpu, state_bytes_per_element(solver)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=200, help="timed steps per run")
    ap.add_argument("--threads", type=int, default=2, help="numba threads")
    ap.add_argument("--repeat", type=int, default=3, help="runs per case (median reported)")
    ap.add_argument("--refinements", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--material-model", choices=sorted(wall.MODELS), default="mat13",
                    help="wall material model (default mat13, the model of every figure in BENCHMARKS.md; "
                         f"the wall stage's default is {wall.WallOptions().material_model!r})")
    ap.add_argument("--hourglass", nargs="+", choices=wall.HOURGLASS_FORMS, default=None,
                    help=f"hourglass form(s) (default: the WallOptions default, {wall.WallOptions().hourglass!r})")
    ap.add_argument("--roofline", action="store_true",
                    help="also measure the memory bandwidth and print the bytes per element-step it implies")
    args = ap.parse_args()
    numba.set_num_threads(args.threads)
    bandwidth = triad_bandwidth() if args.roofline else None
    default_form = wall.WallOptions().hourglass
    forms = args.hourglass or [default_form]
    print(f"impactdyn wall solver benchmark: {describe_machine()}, "
          f"numba {numba.__version__}, {args.threads} threads, "
          f"OMP_WAIT_POLICY={os.environ.get('OMP_WAIT_POLICY', '(unset)')}; "
          f"hourglass form(s) {', '.join(forms)} (default {default_form!r}); material model {args.material_model}; "
          f"1-min load average {os.getloadavg()[0]:.2f}")
    for r in args.refinements:
        for driver in ("compiled", "python"):
            rates = {f: [] for f in forms}
            cpu_rates = {f: [] for f in forms}
            for _ in range(args.repeat):
                for f in forms:  # alternate the forms run by run
                    ne, n, el, cpu, state = measure(r, args.steps, driver, f, args.material_model)
                    rates[f].append(ne * n / el)
                    cpu_rates[f].append(ne * n / cpu)
            for f in forms:
                print(f"refinement {r}: {ne} elements, {n} steps, hourglass {f}, driver {driver:8s}: "
                      f"{statistics.median(rates[f]) / 1e6:.2f} M element-steps/s "
                      f"(runs {', '.join(f'{x / 1e6:.2f}' for x in rates[f])}); "
                      f"{statistics.median(cpu_rates[f]) / 1e6:.2f} M per CPU-second; "
                      f"load average {os.getloadavg()[0]:.2f}")
                if bandwidth is not None and driver == "compiled":
                    print(f"  state {state:.0f} bytes per element; at the triad's bandwidth the median rate means "
                          f"{bandwidth / statistics.median(rates[f]):.0f} bytes per element-step")
    if bandwidth is not None:
        print(f"memory bandwidth (parallel triad, {args.threads} threads, median of 20): {bandwidth / 1e9:.2f} GB/s")
    print(f"threading layer: {numba.threading_layer()}")


if __name__ == "__main__":
    main()
