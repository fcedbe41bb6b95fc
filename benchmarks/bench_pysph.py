"""SPH particle-steps per second of impactdyn against PySPH on PySPH's own 3-D impact example.

PySPH's ``pysph/examples/solid_mech/impact3d.py`` (a steel sphere of radius 5 mm
at 3.1 km/s onto a 2 mm aluminium plate 40 mm × 40 mm; cubic lattice of spacing
0.5 mm, h = 1.3 Δ, fixed Δt = 1 ns, EPEC predictor–corrector with
``SolidMechStep``) is built through its own ``Application`` with its own particle
generators, equations and integrator; only the kernel is switched from its
Gaussian to the cubic spline (``--kernel CubicSpline``, and the artificial-stress
normaliser ``wdeltap`` = W(Δ, h) is recomputed with that kernel), OpenMP on
(``--openmp``). impactdyn's SPH (:mod:`impactdyn.shield`) runs on the very same
particles (PySPH's arrays: positions, masses, velocities, h = 1.3 Δ; the M4
cubic spline of support 2h), with the example's material constants, viscosity
and artificial-stress coefficients and the same fixed Δt, through the shield
stage's own step (``_Solver.step``).

One run of this script sets both codes up (compilation excluded from the
timings), warms them up, and then times the same number of steps of each in
interleaved blocks, so that both see the same shared machine. Each code runs in
a worker process of its own, with the same thread count: in one process numba's
OpenMP pool and PySPH's would be two thread teams on the cores (and numba's pool
resets the process-wide OpenMP thread count), which slows PySPH by about a
third on two cores.

    pip install -e ".[bench]"            # PySPH 1.0b2 from its sdist: Cython, compyle, a C compiler
    python benchmarks/bench_pysph.py [--steps 30] [--rounds 6] [--warmup 3] [--threads N]

If PySPH cannot be imported the script says so and times impactdyn alone on
the same geometry (rebuilt here from the example's parameters).

A "step" is each code's own time step: PySPH's EPEC evaluates the accelerations
(with a neighbour update) twice per step, impactdyn's predicted kick–drift–kick
leapfrog once; both rates are printed (particle-steps/s and particle force passes/s).
impactdyn searches for neighbours only when its reused list's skin is used up
(``SPHOptions.neighbour_skin``); the number of searches is printed.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import os
import platform
import shutil
import statistics
import sys
import tempfile
import time
import traceback
from pathlib import Path
from _machine import describe_machine

# ---- the example's parameters (SI), as in pysph/examples/solid_mech/impact3d.py -------------
DX = 0.0005            # m
HDX = 1.3
R_PROJ = 0.005         # m
V_PROJ = 3100.0        # m/s
DT = 1e-9              # s (the example's fixed time step)
# aluminium plate (Howell & Ball 2002, Table 1, as entered in the example; G and Y read as Pa, as PySPH does)
AL = dict(rho0=2785.0, c0=5328.0, s=1.338, gamma=2.0, G=2.76e7, Y=0.3e6)
# steel projectile
STEEL = dict(rho0=7900.0, c0=4600.0, s=1.490, gamma=2.17, G=8.530e7, Y=0.979e6)
AV_ALPHA, AV_BETA = 1.0, 1.5   # Monaghan viscosity (eta = 0.1 -> 0.01 h^2, as impactdyn's)
AS_EPS, AS_N = 0.3, 4          # Monaghan artificial stress

# SI -> impactdyn units (cm, g, µs, Mbar)
M_TO_CM, KG_TO_G = 100.0, 1000.0
RHO_SI_TO_CGS = 1e-3           # kg/m³ -> g/cm³
V_SI_TO_CM_US = 1e-4           # m/s -> cm/µs
PA_TO_MBAR = 1e-11
S_TO_US = 1e6


def _parse() -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=30, help="timed steps of each code")
    ap.add_argument("--rounds", type=int, default=6, help="timed blocks per code, interleaved between the codes")
    ap.add_argument("--warmup", type=int, default=3, help="untimed steps after compilation (each code); "
                    "the surfaces meet after about 160 steps, the particle layers after about 320")
    ap.add_argument("--threads", type=int, default=None, help="threads of each code (default: all CPUs)")
    ap.add_argument("--library-materials", action="store_true",
                    help="impactdyn side: al2024-t4 and ss304 from impactdyn.materials instead of the "
                         "example's constants")
    ap.add_argument("--only", choices=("both", "pysph", "impactdyn"), default="both")
    return ap.parse_args()


# Parsed at import: the spawned workers import this module again with the same argv.
ARGS = _parse()
THREADS = ARGS.threads or os.cpu_count() or 1
# read by libgomp (PySPH's OpenMP and numba's omp layer) when it loads
os.environ["OMP_NUM_THREADS"] = str(THREADS)

import numpy as np  # noqa: E402


def _import_impactdyn():
    try:
        import impactdyn
    except ImportError:  # a source checkout that is not installed
        sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))
        import impactdyn
    return impactdyn


# ---- PySPH ----------------------------------------------------------------------------------
def _pysph_example():
    """The example's Application with the cubic-spline kernel (and wdeltap of that kernel), and the module."""
    from pysph.base.kernels import CubicSpline
    from pysph.examples.solid_mech import impact3d as ex

    class Impact3DCubic(ex.Impact):
        def create_particles(self):
            arrays = super().create_particles()
            w = CubicSpline(dim=3).kernel(rij=ex.dx, h=ex.hdx * ex.dx)
            for pa in arrays:
                pa.wdeltap[0] = w
            return arrays

    return Impact3DCubic, ex


class PySPHRun:
    """The example's Application set up (compiled) and warmed up; ``block(k)`` times k more steps."""

    def __init__(self, warmup: int, threads: int):
        import compyle
        import Cython
        import pysph
        from compyle.config import get_config
        from pysph.base.omp_threads import get_number_of_threads, set_number_of_threads

        app_cls, ex = _pysph_example()
        assert (ex.dx, ex.hdx, ex.r, ex.v_s) == (DX, HDX, R_PROJ, V_PROJ), "the example's parameters changed"
        self.threads, self._set_threads, self._get_threads = threads, set_number_of_threads, get_number_of_threads
        self._set_threads(threads)
        self.omp_threads_seen: set[int] = set()
        app = app_cls(fname="impact3d_bench")
        t0 = time.perf_counter()
        # --openmp is compyle's option: PySPH 1.0b2 runs serially without it
        self.out_dir = tempfile.mkdtemp(prefix="bench_pysph_")  # PySPH's log and info files
        app.setup(["--openmp", "--kernel", "CubicSpline", "--disable-output", "-q",
                   "-d", self.out_dir, "--max-steps", str(warmup)])
        self.setup_s = time.perf_counter() - t0
        arrays = {pa.name: pa for pa in app.particles}
        props = ("x", "y", "z", "m", "u", "v", "w", "h")
        #: the example's initial particles (SI), for the impactdyn side
        self.geometry = {name: {p: pa.get(p).astype(float).copy() for p in props} for name, pa in arrays.items()}
        self.app, self.solver = app, app.solver
        self.omp_threads_seen.add(self._get_threads())
        t0 = time.perf_counter()
        self.solver.solve(show_progress=False)  # the solver's own loop: initial accelerations + warm-up steps
        self.warm_s = time.perf_counter() - t0
        assert self.solver.count == warmup
        self.info = dict(
            name="PySPH", n=sum(pa.get_number_of_particles() for pa in app.particles), passes=2,
            n_plate=arrays["plate"].get_number_of_particles(), n_proj=arrays["projectile"].get_number_of_particles(),
            setup_s=self.setup_s, warm_s=self.warm_s,
            describe=(f"PySPH {pysph.__version__} (compyle {compyle.__version__}, Cython {Cython.__version__}): "
                      f"{type(self.solver.kernel).__name__} kernel, {type(self.solver.integrator).__name__} "
                      f"(SolidMechStep), {type(app.nnps).__name__}, OpenMP "
                      f"{'on' if get_config().use_openmp else 'off'}"))

    def block(self, steps: int) -> tuple[float, float]:
        solver, integ = self.solver, self.solver.integrator
        self._set_threads(self.threads)
        self.omp_threads_seen.add(self._get_threads())
        t0, c0 = time.perf_counter(), time.process_time()
        for _ in range(steps):  # the body of Solver.solve's loop (no callbacks, no output)
            integ.step(solver.t, solver.dt)
            solver.t += solver.dt
            solver.count += 1
            solver.dt = solver._get_timestep()
            solver.update_particle_time()
            if solver.reorder_freq > 0 and solver.count % solver.reorder_freq == 0:
                solver.reorder_particles()
        return time.perf_counter() - t0, time.process_time() - c0

    def finish(self) -> dict:
        finite = all(np.isfinite(pa.get(p)).all() for pa in self.app.particles for p in ("x", "u", "rho", "p"))
        shutil.rmtree(self.out_dir, ignore_errors=True)
        return dict(finite=finite, note=f"OpenMP threads in its parallel regions: {sorted(self.omp_threads_seen)}")


def example_geometry() -> dict:
    """The example's particles (SI), from its own generators if PySPH imports, else rebuilt identically."""
    try:
        _, ex = _pysph_example()
    except ImportError:
        ex = None
    if ex is not None:
        props = ("x", "y", "z", "m", "u", "v", "w", "h")
        return {name: {p: pa.get(p).astype(float) for p in props}
                for name, pa in (("plate", ex.get_plate_particles()), ("projectile", ex.get_projectile_particles()))}
    x, y, z = np.mgrid[0:0.002 + DX:DX, -0.02:0.02 + DX:DX, -0.02:0.02 + DX:DX]
    plate = dict(x=x.ravel(), y=y.ravel(), z=z.ravel())
    x, y, z = np.mgrid[-R_PROJ:R_PROJ + 1e-6:DX, -R_PROJ:R_PROJ + 1e-6:DX, -R_PROJ:R_PROJ + 1e-6:DX]
    x, y, z = x.ravel(), y.ravel(), z.ravel()
    keep = np.flatnonzero(x * x + y * y + z * z <= R_PROJ * R_PROJ)
    proj = dict(x=x[keep] - (R_PROJ + 2 * DX), y=y[keep], z=z[keep])
    for d, mat, u in ((plate, AL, 0.0), (proj, STEEL, V_PROJ)):
        n = d["x"].size
        d.update(m=np.full(n, DX ** 3 * mat["rho0"]), u=np.full(n, u), v=np.zeros(n), w=np.zeros(n),
                 h=np.full(n, HDX * DX))
    return {"plate": plate, "projectile": proj}


# ---- impactdyn --------------------------------------------------------------------------------
def impactdyn_problem(geometry: dict, library: bool):
    """A :class:`impactdyn.shield.Problem` of the example's particles (no mirror plane: the full model)."""
    _import_impactdyn()
    from impactdyn.materials import Material, get_material
    from impactdyn.shield import Domain, Problem
    from impactdyn.shield._problems import _particles

    def material(name: str, c: dict, specific_heat_j_gk: float) -> Material:
        # the example's constants in impactdyn units; no spall or strain failure (the example has none)
        return Material(name=name, rho0=c["rho0"] * RHO_SI_TO_CGS, c0=c["c0"] * V_SI_TO_CM_US, s=c["s"],
                        gamma0=c["gamma"], shear_modulus=c["G"] * PA_TO_MBAR, yield_stress=c["Y"] * PA_TO_MBAR,
                        specific_heat=specific_heat_j_gk * 1e-5, source="PySPH impact3d.py example")

    if library:
        materials = (get_material("al2024-t4"), get_material("ss304"))
    else:
        materials = (material("example-aluminium", AL, 0.875), material("example-steel", STEEL, 0.500))
    parts = [geometry["plate"], geometry["projectile"]]
    pos = np.concatenate([np.stack([g["x"], g["y"], g["z"]], axis=-1) for g in parts]) * M_TO_CM
    vel = np.concatenate([np.stack([g["u"], g["v"], g["w"]], axis=-1) for g in parts]) * V_SI_TO_CM_US
    mass = np.concatenate([g["m"] for g in parts]) * KG_TO_G
    mat = np.concatenate([np.full(g["x"].size, k, dtype=np.int64) for k, g in enumerate(parts)])
    if library:  # the example's lattice volume Δ³ with the library densities
        mass = (DX * M_TO_CM) ** 3 * np.array([m.rho0 for m in materials])[mat]
    particles = _particles(pos, vel, mass, mat, materials)  # h = 1.3 (m/ρ₀)^(1/3) = 1.3 Δ
    h_pysph = np.concatenate([g["h"] for g in parts]) * M_TO_CM
    assert np.allclose(particles.smoothing_length, h_pysph, rtol=1e-9), "h differs from PySPH's"
    return Problem(particles=particles, materials=materials, spacing_cm=DX * M_TO_CM, domain=Domain(),
                   name="PySPH impact3d: steel sphere on aluminium plate, 3.1 km/s")


class ImpactdynRun:
    """impactdyn's shield SPH on ``problem`` with the example's numerics, compiled and warmed up."""

    def __init__(self, problem, warmup: int, threads: int, library: bool):
        impactdyn = _import_impactdyn()
        import numba
        from impactdyn.shield import SPHOptions
        from impactdyn.shield._integrate import _Solver

        numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
        options = SPHOptions(alpha=AV_ALPHA, beta=AV_BETA, artificial_stress=AS_EPS, artificial_stress_power=AS_N,
                             h_factor=HDX, flow_stress="perfectly_plastic", failure=False)
        self.dt = DT * S_TO_US
        t0 = time.perf_counter()
        self.solver = _Solver(problem, options)  # initial EOS and rates: compiles (or loads numba's cache)
        self.solver.step(self.dt)                # compiles the step kernels
        setup_s = time.perf_counter() - t0
        t0 = time.perf_counter()
        for _ in range(warmup - 1):
            self.solver.step(self.dt)
        warm_s = time.perf_counter() - t0
        self.dt_stable = self.solver.dt
        h = problem.particles.smoothing_length
        self.info = dict(
            name="impactdyn", n=len(problem.particles), passes=1, setup_s=setup_s, warm_s=warm_s,
            describe=(f"impactdyn {getattr(impactdyn, '__version__', '?')} (numba {numba.__version__}, threading "
                      f"layer {numba.threading_layer()}, {numba.get_num_threads()} threads): M4 cubic spline, "
                      f"h/dx {h.mean() / (DX * M_TO_CM):.3f}, predicted kick-drift-kick leapfrog, "
                      f"{'library materials al2024-t4 / ss304' if library else 'the example materials'}"))

    def block(self, steps: int) -> tuple[float, float]:
        solver = self.solver
        t0, c0 = time.perf_counter(), time.process_time()
        for _ in range(steps):
            solver.step(self.dt)
            self.dt_stable = min(self.dt_stable, solver.dt)  # its own stable step at the new state
        return time.perf_counter() - t0, time.process_time() - c0

    def finish(self) -> dict:
        s = self.solver
        finite = all(bool(np.isfinite(a).all()) for a in (s.state.x, s.state.v, s.state.rho))
        searches = getattr(s.neighbours, "builds", None)  # the reused neighbour list's searches, set-up included
        searched = "" if searches is None else f"; neighbour searches {searches} in {s.steps} steps + set-up"
        return dict(finite=finite, note=f"its own stable dt >= {self.dt_stable:.3g} us over the run "
                                        f"(fixed dt {self.dt:.3g} us used){searched}")


# ---- worker processes ---------------------------------------------------------------------------
def _worker(kind: str, conn, geometry) -> None:
    """Set one code up in this process, then answer ("block", k) and ("finish", None) requests."""
    try:
        if kind == "PySPH":
            run = PySPHRun(ARGS.warmup, THREADS)
            conn.send(("ready", dict(run.info, geometry=run.geometry)))
        else:
            run = ImpactdynRun(impactdyn_problem(geometry, ARGS.library_materials), ARGS.warmup, THREADS,
                               ARGS.library_materials)
            conn.send(("ready", run.info))
        while True:
            cmd, arg = conn.recv()
            if cmd == "block":
                conn.send(("ok", run.block(arg)))
            else:
                conn.send(("ok", run.finish()))
                return
    except Exception:
        conn.send(("error", traceback.format_exc()))


class _Remote:
    def __init__(self, ctx, kind: str, geometry=None):
        self.conn, child = ctx.Pipe()
        self.proc = ctx.Process(target=_worker, args=(kind, child, geometry), daemon=True)
        self.proc.start()
        self.info = self._get()

    def _get(self):
        status, value = self.conn.recv()
        if status == "error":
            raise RuntimeError(f"worker failed:\n{value}")
        return value

    def block(self, steps: int) -> tuple[float, float]:
        self.conn.send(("block", steps))
        return self._get()

    def finish(self) -> dict:
        self.conn.send(("finish", None))
        out = self._get()
        self.proc.join()
        return out


# ---- driver and report ----------------------------------------------------------------------------
def main() -> None:
    args = ARGS
    print(f"machine: {platform.platform()}, {describe_machine()}; "
          f"Python {platform.python_version()}, NumPy {np.__version__}; "
          f"load average (1 min) at start {os.getloadavg()[0]:.2f}")
    print("case: PySPH examples/solid_mech/impact3d.py: steel sphere r = 5 mm at 3.1 km/s on a 2 x 40 x 40 mm "
          f"aluminium plate; spacing {DX * 1e3:g} mm, h = {HDX} dx, cubic spline (support 2h), dt = {DT:g} s "
          f"fixed; {THREADS} threads per code, each code in its own process")
    ctx = mp.get_context("spawn")
    runs: dict[str, _Remote] = {}
    if args.only in ("both", "pysph"):
        try:
            import pysph  # noqa: F401
        except ImportError as exc:
            print(f"PySPH: NOT RUN: PySPH is not installed ({exc}); install it with "
                  "pip install 'pysph==1.0b2' (or pip install -e '.[bench]'); timing impactdyn alone")
        else:
            runs["PySPH"] = _Remote(ctx, "PySPH")
    if args.only in ("both", "impactdyn"):
        geometry = runs["PySPH"].info.pop("geometry") if "PySPH" in runs else example_geometry()
        runs["impactdyn"] = _Remote(ctx, "impactdyn", geometry)

    # interleaved blocks, so that both codes see the same (shared, noisy) machine
    rounds = max(1, min(args.rounds, args.steps))
    per = [args.steps // rounds + (k < args.steps % rounds) for k in range(rounds)]
    times: dict[str, list[tuple[float, float]]] = {name: [] for name in runs}
    for k in per:
        for name, run in runs.items():
            times[name].append(run.block(k))

    rate = {}
    for name, run in runs.items():
        info, final = run.info, run.finish()
        wall = sum(w for w, _ in times[name])
        cpu = sum(c for _, c in times[name])
        rate[name] = info["n"] * args.steps / wall
        print(info["describe"])
        counts = f" (plate {info['n_plate']}, projectile {info['n_proj']})" if "n_plate" in info else ""
        print(f"  particles {info['n']}{counts}; setup incl. compile/cache load {info['setup_s']:.1f} s; "
              f"warm-up {args.warmup} steps {info['warm_s']:.2f} s; {final['note']}")
        blocks = ", ".join(f"{w:.2f}" for w, _ in times[name])
        print(f"  {args.steps} steps in {wall:.3f} s wall (blocks of {per[0]}: {blocks} s; CPU {cpu:.2f} s) -> "
              f"{rate[name]:,.0f} particle-steps/s; {info['passes']} force pass(es)/step -> "
              f"{info['passes'] * rate[name]:,.0f} particle-passes/s; state finite: {final['finite']}")
    print(f"load average (1 min) at the end: {os.getloadavg()[0]:.2f}")
    if len(rate) == 2:
        assert runs["PySPH"].info["n"] == runs["impactdyn"].info["n"]
        ratio = rate["impactdyn"] / rate["PySPH"]
        per_block = [wp / wi for (wp, _), (wi, _) in zip(times["PySPH"], times["impactdyn"])]
        print(f"RATIO impactdyn/PySPH particle-steps/s: {ratio:.2f}x (blocks: "
              f"{', '.join(f'{r:.2f}' for r in per_block)}; median block {statistics.median(per_block):.2f}x; "
              f"per force pass {ratio / 2:.2f}x)")


if __name__ == "__main__":
    main()
