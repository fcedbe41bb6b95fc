"""Particle-steps per second of the SPH shield stage on a sphere-on-plate impact (DESIGN §6, §8).

The Table 2 "7a" geometry of the 1994 report (Al 6061-T6 sphere of 0.575 cm on a
0.127 cm Al 6061-T6 bumper, 7 km/s, 25°), half model, plate radius 2 d, run for
a fixed number of steps after a warm-up run that compiles the kernels (or loads
them from numba's cache). Reports particles, steps, wall time, particle-steps/s
and the split of the time over the kernels.

    python benchmarks/bench_sph.py [--spacing 0.0254] [--steps 100] [--threads N]

The numba threading layer and thread count are printed with the result: under
CPU oversubscription the OpenMP layer's default spin-waiting costs milliseconds
per parallel launch (``OMP_WAIT_POLICY=passive`` or
``NUMBA_THREADING_LAYER=workqueue`` avoid it), which matters for small runs.
"""

from __future__ import annotations

import argparse
import time

import numba

from impactdyn import shield
from impactdyn.shield import _integrate, _neighbours
from _machine import describe_machine


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--spacing", type=float, default=0.0254, help="particle spacing, cm")
    ap.add_argument("--steps", type=int, default=100, help="timed steps")
    ap.add_argument("--threads", type=int, default=None, help="numba threads (default: all)")
    args = ap.parse_args()
    if args.threads:
        numba.set_num_threads(args.threads)

    problem = shield.sphere_on_plate("al6061-t6", "al6061-t6", diameter_cm=0.575, velocity_km_s=7.0,
                                     obliquity_deg=25.0, plate_thickness_cm=0.127, spacing_cm=args.spacing)
    n = len(problem.particles)
    shield.run(problem, t_end_us=1e-3)  # compile / load the cached kernels

    timers: dict[str, float] = {}
    calls: dict[str, int] = {}

    def timed(module, name):
        fn = getattr(module, name)

        def wrapper(*a, **k):
            t0 = time.perf_counter()
            out = fn(*a, **k)
            timers[name] = timers.get(name, 0.0) + time.perf_counter() - t0
            calls[name] = calls.get(name, 0) + 1
            return out
        setattr(module, name, wrapper)
        return fn

    originals = {(m, name): timed(m, name) for m, name in [
        (_integrate, "kick_drift_predict"), (_integrate, "pair_sums"), (_integrate, "finish_step"),
        (_neighbours, "list_drift"), (_neighbours, "find_neighbours")]}
    steps = 0
    t_stop = 0.0

    class Stop(Exception):
        pass

    def count(t, t_end):
        nonlocal steps, t_stop
        steps += 1
        t_stop = t
        if steps == args.steps:
            raise Stop

    t0, c0 = time.perf_counter(), time.process_time()
    try:
        shield.run(problem, t_end_us=10.0, progress=count)
    except Stop:
        pass
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    for (m, name), fn in originals.items():
        setattr(m, name, fn)

    print(f"machine: {describe_machine()}; numba {numba.__version__}, "
          f"threading layer {numba.threading_layer()}, {numba.get_num_threads()} threads")
    print(f"sphere on plate (7a), spacing {args.spacing} cm: {n} particles, {steps} steps to t = {t_stop:.4f} us")
    print(f"wall {wall:.2f} s -> {n * steps / wall:,.0f} particle-steps/s; "
          f"CPU {cpu:.2f} s -> {n * steps / cpu:,.0f} particle-steps per CPU-second")
    for name, t in sorted(timers.items(), key=lambda kv: -kv[1]):
        print(f"  {name:20s} {t:7.2f} s  ({100 * t / wall:4.1f} %)")
    print(f"neighbour searches: {calls.get('find_neighbours', 0)} in {steps} steps")


if __name__ == "__main__":
    main()
