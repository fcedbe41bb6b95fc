"""Wall solver against CalculiX: an impulsively loaded clamped plate (issue 11 acceptance; not a CI test).

The problem, the same in both codes:

* a square Al 6061-T6 plate, 2 cm × 2 cm × 0.16 cm, all four edges clamped through the
  thickness.  The wall mesh always has its symmetry plane at x = x[0] (x fixed there,
  :meth:`impactdyn.wallgrid.WallGrid.constrained_dofs`), so both codes model the half plate
  x ∈ [0, 1], z ∈ [−1, 1] cm with that plane as the plate's centre line; ``supports="clamped"``
  fixes every translation on the other three edges.  The CalculiX deck is written from the
  wall solver's own mesh (:func:`impactdyn.wall.build_mesh`): the same nodes, the same
  hexahedra (C3D8R; the wall's node order is Abaqus/CalculiX's), the same fixed translations.
* the report's type-13 card (:data:`impactdyn.materials.AL_6061_T6_MAT13`) with failure off
  (``failure_strain`` 0, ``failure_pressure`` −1e30 Mbar): ρ 2.703 g/cm³, G 0.276, K 0.720,
  σ_y 2.9e-3 Mbar, E_h 3.88e-3 Mbar.  CalculiX: *ELASTIC E = 9KG/(3K+G), ν = (3K−2G)/(2(3K+G));
  *PLASTIC (isotropic hardening, true stress vs equivalent plastic strain) the straight line
  σ_y + E_h ε_p through (0, σ_y) and (10, σ_y + 10 E_h); *DENSITY ρ.
* impulsive load: an initial velocity V0 normal to the plate (+y) on a central patch
  |x|, |z| ≤ a, through the whole thickness.  The patch is the set of elements whose centre
  lies inside it; each node takes the velocity V0 times the share of its lumped mass that
  comes from patch elements (1 inside, 1/2 on the patch's edges, 1/4 at its corners), so the
  momentum is ρ V_patch V0 on every mesh.  The same nodal velocities go to CalculiX as
  *INITIAL CONDITIONS, TYPE=VELOCITY (both codes lump ρV/8 to each node of a hexahedron, so
  the momentum and the kinetic energy are identical).
* no damping in either code (no mass-proportional damping; CalculiX's explicit α-method keeps
  its default α = −0.05, a small high-frequency dissipation; impactdyn its default bulk
  viscosity, which is negligible here).  Both run to ``--end-time``; the plate then vibrates
  elastically about its permanent shape, so the permanent deflection is the mean of the
  centre node's deflection (rear face, x = z = 0) over the second half of the run.  impactdyn's
  plate is then also brought to rest (:meth:`impactdyn.wall.WallSolver.settle`, the
  ``settle = true`` measure) and its settled deflection printed beside its own mean.
* impactdyn runs with its defaults (:class:`impactdyn.wall.WallOptions`: the assumed-strain
  hourglass form since 2026-11-24, QH 0.1, Q1 1.5, Q2 0.06, Courant 0.9); CalculiX 2.20 with NLGEOM (large deformation, as the wall solver's updated
  Lagrangian formulation) and *DYNAMIC, EXPLICIT with its own stable increment (the third
  number on the *DYNAMIC line, the minimum increment below which CalculiX scales masses, is
  set far below it: no mass scaling).

Diagnostics (impactdyn only, cheap; they change no default): the same plate with every
other hourglass form (:data:`impactdyn.wall.HOURGLASS_FORMS`) and QH values on every mesh, which is where the two codes differ most (CalculiX's C3D8R has a fixed
Flanagan–Belytschko hourglass stiffness 0.0005·C·ΣB²/V, about QH ≈ 0.01 in the wall solver's
normalisation ``QH ρc² ΣB²/(24 V)`` — see BENCHMARKS.md), and a finer impactdyn-only mesh.

Speed: element-steps per second of both on every mesh (``--repeat`` alternating runs of the
two codes on the first mesh, one on the others; medians, and the median of the per-pair
ratios): impactdyn through :meth:`WallSolver.run` (the production driver, with its history
samples) and through one compiled :meth:`WallSolver.advance` call, both from a fresh solver
with the kernels already compiled; CalculiX the ccx process's wall time (input, set-up and
output included) × its increments (ceil(end time / its constant increment)).  Both with
``--threads`` threads (OMP_NUM_THREADS for ccx, numba's thread count for impactdyn).  The
runs alternate because the machine this was written on is shared: the 1-minute load
average is printed with the numbers.

    OMP_WAIT_POLICY=passive python verification/verify_wall_calculix.py [--mesh 0.1 0.05]
        [--layers 4] [--v0 0.025] [--patch 0.5] [--end-time 100] [--repeat 3] [--threads 2]
        [--ccx ccx] [--keep DIR] [--json FILE] [--no-diagnostics]

Speed only, on the report's wall (``--report-wall R [R ...]``, issue 11's speed acceptance): the
grid of :func:`bench_wall.report_wall` (the ``table2_7a`` wall, 50 × 4 × 100 elements of
0.16 × 0.079 × 0.16 cm) refined R times through the thickness and in the plane, every edge
face clamped (``supports="clamped"``; x = 0 stays the symmetry plane), the same type-13 card
without failure, the same initial-velocity patch about (x, z) = (0, 0) and a short run
(``--end-time``, default 100 µs for the plate; use 5–10 µs here).  Both codes are timed as
above (the same deck writer and the same alternating timing); no deflection comparison and
no pass/fail.  Exits 0.

    OMP_WAIT_POLICY=passive python verification/verify_wall_calculix.py --report-wall 1 2 \
        --end-time 10 --repeat 3

(``OMP_WAIT_POLICY=passive``: on an oversubscribed machine numba's spin-waiting OpenMP threads
slowed the wall solver 50-fold; the deflections do not depend on it.)

Needs ``ccx`` (Debian/Ubuntu: ``apt-get install calculix-ccx``; tested with 2.20).  Prints a
table and exits 0 when the permanent deflections on the first mesh agree within 5 %, 1
otherwise.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

THREADS_DEFAULT = 2
if "--threads" in sys.argv:  # numba reads its thread count when it is first imported
    try:
        os.environ.setdefault("NUMBA_NUM_THREADS", sys.argv[sys.argv.index("--threads") + 1])
    except IndexError:
        pass
os.environ.setdefault("NUMBA_NUM_THREADS", str(THREADS_DEFAULT))

import numba  # noqa: E402
import numpy as np  # noqa: E402

from impactdyn import wall  # noqa: E402
from impactdyn.materials import AL_6061_T6_MAT13, Mat13Card  # noqa: E402
from impactdyn.wallgrid import WallGrid  # noqa: E402

#: Plate: half model x ∈ [0, HALF_WIDTH] (x = 0 the symmetry plane), z ∈ [−HALF_WIDTH, HALF_WIDTH].
HALF_WIDTH = 1.0
THICKNESS = 0.16
#: The report's type-13 card with failure switched off.
CARD = replace(AL_6061_T6_MAT13, failure_strain=0.0, failure_pressure=-1.0e30)


# --- the problem -----------------------------------------------------------------------------------

def plate_mesh(h: float, layers: int) -> wall.WallMesh:
    """The clamped half plate with in-plane elements of ``h`` cm and ``layers`` through the thickness."""
    n = int(round(HALF_WIDTH / h))
    if n < 2 or abs(n * h - HALF_WIDTH) > 1e-9:
        raise SystemExit(f"--mesh {h}: must divide {HALF_WIDTH} cm into at least 2 elements")
    grid = WallGrid.uniform((0.0, HALF_WIDTH), (0.0, THICKNESS), (-HALF_WIDTH, HALF_WIDTH),
                            (n + 1, layers + 1, 2 * n + 1))
    return wall.build_mesh(grid, CARD.density, 1, 1, "clamped")


def initial_velocity(mesh: wall.WallMesh, v0: float, a: float) -> np.ndarray:
    """Nodal velocities (n_nodes, 3): V0 ŷ times the share of each node's mass from patch elements."""
    x = mesh.coordinates
    centre = x[mesh.connectivity].mean(axis=1)
    in_patch = (centre[:, 0] < a) & (np.abs(centre[:, 2]) < a)
    patch_mass = np.zeros(mesh.n_nodes)
    np.add.at(patch_mass, mesh.connectivity[in_patch].ravel(), np.repeat(mesh.element_mass[in_patch] / 8.0, 8))
    v = np.zeros((mesh.n_nodes, 3))
    v[:, 1] = v0 * patch_mass / mesh.node_mass
    v[mesh.fixed] = 0.0
    return v


def centre_node(mesh: wall.WallMesh) -> int:
    """The rear-face node at the plate's centre (x = 0, z = 0, y = thickness; the largest y of the mesh)."""
    x = mesh.coordinates
    hit = np.flatnonzero((np.abs(x[:, 0]) < 1e-9) & (np.abs(x[:, 2]) < 1e-9) & (np.abs(x[:, 1] - x[:, 1].max()) < 1e-9))
    return int(hit[0])


def report_wall_mesh(refinement: int) -> wall.WallMesh:
    """The report's wall (the wall grid of ``examples/whipple/table2_7a.toml``, its front face at y = 0) refined
    ``refinement`` times, every edge clamped."""
    from impactdyn.whipple import load_whipple_case

    w = load_whipple_case(Path(__file__).resolve().parents[1] / "examples" / "whipple" / "table2_7a.toml").wall
    grid = WallGrid.uniform(tuple(w.x_cm), (0.0, w.thickness_cm), tuple(w.z_cm), tuple(w.nodes))
    return wall.build_mesh(grid, CARD.density, refinement, refinement, "clamped")


def permanent(t: np.ndarray, u: np.ndarray, t_end: float) -> tuple[float, float, float]:
    """(mean, min, max) of the deflection over the second half of the run."""
    w = t >= 0.5 * t_end
    return float(u[w].mean()), float(u[w].min()), float(u[w].max())


# --- impactdyn ------------------------------------------------------------------------------------

def run_impactdyn(mesh, v, t_end, options: wall.WallOptions, sample_us: float = 0.25) -> dict:
    """The deflection history of the centre node, the energies and the plastic strain."""
    model = wall.wall_model("mat13", CARD)
    solver = wall.WallSolver(mesh, model, options, velocity=v)
    solver.energies()  # the initial kinetic energy is taken at the first call
    c = centre_node(mesh)
    ts, us, wp = [0.0], [0.0], [0.0]
    while solver.time < t_end - 1e-12:
        solver.advance(min(solver.time + sample_us, t_end))
        ts.append(solver.time)
        us.append(solver.x[c, 1] - solver.x0[c, 1])
        if len(ts) % 8 == 0:
            wp.append(solver.energies()["plastic"])
    t, u = np.array(ts), np.array(us)
    en = solver.energies()
    mean, lo, hi = permanent(t, u, t_end)
    from impactdyn.wall._state import EPS_P  # state column (no public accessor)
    out = {"t": t, "u": u, "deflection": mean, "min": lo, "max": hi, "peak": float(u.max()),
           "steps": solver.steps, "dt": t_end / solver.steps, "energy": en,
           "eps_p_max": float(solver.es[:, EPS_P].max()),
           "hourglass_fraction": en["hourglass"] / en["internal"] if en["internal"] > 0 else 0.0}
    settled = solver.settle()  # after the measures above: the settling does not keep the energy balance
    return out | {"settled": solver.x[c, 1] - solver.x0[c, 1], "settle_steps": settled["settle_steps"]}


def time_impactdyn(mesh, v, t_end, options: wall.WallOptions, driver: str) -> tuple[float, int]:
    """(wall seconds, steps) of one run: ``run`` (WallSolver.run) or ``compiled`` (one advance call)."""
    model = wall.wall_model("mat13", CARD)
    solver = wall.WallSolver(mesh, model, options, velocity=v)
    t0 = time.perf_counter()
    if driver == "run":
        solver.run()
    else:
        solver.advance(t_end)
    return time.perf_counter() - t0, solver.steps


# --- CalculiX -------------------------------------------------------------------------------------

def write_deck(path: str, mesh: wall.WallMesh, v: np.ndarray, t_end: float, dt_guess: float,
               print_every: int, title: str = "clamped Al 6061-T6 plate") -> None:
    """The CalculiX input of the same problem (module docstring): ``mesh``'s nodes, C3D8R elements and
    fixed translations, the card without failure, the nodal velocities ``v``; prints the centre node."""
    card: Mat13Card = CARD
    x = mesh.coordinates
    out = ["*HEADING", f"impactdyn verify_wall_calculix: {title}, impulsive patch load (cm g us Mbar)",
           "*NODE, NSET=NALL"]
    out += [f"{i + 1}, {a:.12g}, {b:.12g}, {c:.12g}" for i, (a, b, c) in enumerate(x)]
    out.append("*ELEMENT, TYPE=C3D8R, ELSET=EALL")
    out += [f"{e + 1}, " + ", ".join(str(n + 1) for n in nodes) for e, nodes in enumerate(mesh.connectivity)]
    out += ["*NSET, NSET=NCENTRE", str(centre_node(mesh) + 1), "*BOUNDARY"]
    for n, d in zip(*np.nonzero(mesh.fixed)):
        out.append(f"{n + 1}, {d + 1}, {d + 1}")
    y0 = card.yield_stress
    out += ["*MATERIAL, NAME=AL6061T6", "*ELASTIC", f"{card.youngs_modulus:.12g}, {card.poisson_ratio:.12g}",
            "*PLASTIC", f"{y0:.12g}, 0.", f"{y0 + 10.0 * card.hardening_modulus:.12g}, 10.",
            "*DENSITY", f"{card.density:.12g}",
            "*SOLID SECTION, ELSET=EALL, MATERIAL=AL6061T6",
            "*INITIAL CONDITIONS, TYPE=VELOCITY"]
    for n in np.flatnonzero(np.any(v != 0.0, axis=1)):
        for d in range(3):
            if v[n, d] != 0.0:
                out.append(f"{n + 1}, {d + 1}, {v[n, d]:.15g}")
    out += ["*STEP, NLGEOM, INC=100000000",
            "*DYNAMIC, EXPLICIT",
            f"{dt_guess:.6g}, {t_end:.6g}, {dt_guess * 1e-4:.6g}, {dt_guess:.6g}",
            f"*NODE PRINT, NSET=NCENTRE, FREQUENCY={print_every}", "U",
            "*END STEP"]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


_PRINT = re.compile(r"displacements \(vx,vy,vz\) for set NCENTRE and time\s+(\S+)\s+(\d+)\s+(\S+)\s+(\S+)\s+(\S+)")
_INC = re.compile(r"SELECTED time increment:\s*(\S+)")


def run_ccx(ccx: str, workdir: str, job: str, threads: int) -> dict:
    """Run ccx on ``workdir/job.inp``; the centre node's history, the increment and the wall time."""
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), CCX_NPROC_RESULTS=str(threads))
    with open(os.path.join(workdir, job + ".log"), "w") as log:
        t0 = time.perf_counter()
        proc = subprocess.run([ccx, "-i", job], cwd=workdir, stdout=log, stderr=subprocess.STDOUT, env=env)
        elapsed = time.perf_counter() - t0
    text = open(os.path.join(workdir, job + ".log")).read()
    if proc.returncode != 0 or "Job finished" not in text:
        raise SystemExit(f"ccx failed (exit {proc.returncode}); see {workdir}/{job}.log:\n{text[-2000:]}")
    if re.search(r"mass scaling", text, re.I) and not re.search(r"no mass scaling", text, re.I):
        print("warning: CalculiX reports mass scaling", file=sys.stderr)
    rows = _PRINT.findall(open(os.path.join(workdir, job + ".dat")).read())
    t = np.array([0.0] + [float(r[0]) for r in rows])
    u = np.array([0.0] + [float(r[3]) for r in rows])
    dt = float(_INC.search(text).group(1))
    return {"t": t, "u": u, "dt": dt, "wall_s": elapsed}


# --- speed ----------------------------------------------------------------------------------------

def speed(mesh, v, T, options: wall.WallOptions, steps_to_end: int, cx_inc: int, args, workdir: str, job: str,
          pairs: int, first_ccx_s: float | None = None, indent: str = "  ") -> dict:
    """Element-steps/s of both codes on ``workdir/job.inp``'s problem, ``pairs`` alternating runs (medians).

    impactdyn from a fresh solver (kernels compiled), through WallSolver.run and one compiled advance;
    CalculiX the ccx process's wall time × ``cx_inc`` increments.  ``first_ccx_s``: a ccx time already
    measured, used for the first pair instead of running ccx again.  Prints the result; returns its dict.
    """
    load0 = os.getloadavg()[0]
    rates = {"run": [], "compiled": [], "calculix": []}
    for i in range(pairs):
        for driver in ("run", "compiled"):
            el, steps = time_impactdyn(mesh, v, T, options, driver)
            rates[driver].append(mesh.n_elements * steps / el)
        wall_s = first_ccx_s if (i == 0 and first_ccx_s is not None) else \
            run_ccx(args.ccx, workdir, job, args.threads)["wall_s"]
        rates["calculix"].append(mesh.n_elements * cx_inc / wall_s)
    load1 = os.getloadavg()[0]
    med = {key: statistics.median(val) for key, val in rates.items()}
    ratios = [a / b for a, b in zip(rates["run"], rates["calculix"])]
    t_imp = mesh.n_elements * steps_to_end / med["run"]
    t_cx = mesh.n_elements * cx_inc / med["calculix"]
    out = {"runs": rates, "median": med, "ratio_run_median": statistics.median(ratios),
           "ratio_compiled_median": statistics.median(a / b for a, b in zip(rates["compiled"], rates["calculix"])),
           "time_to_end_s": {"impactdyn_run": t_imp, "calculix": t_cx}, "loadavg_1min": [load0, load1],
           "hourglass": options.hourglass}
    print(f"{indent}speed ({pairs} alternating run(s), median; 1-min load average {load0:.1f} -> {load1:.1f} on "
          f"{os.cpu_count()} cores; impactdyn hourglass {options.hourglass}): impactdyn {med['run'] / 1e6:.3f} M "
          f"element-steps/s (WallSolver.run; one compiled advance {med['compiled'] / 1e6:.3f} M), CalculiX "
          f"{med['calculix'] / 1e6:.3f} M; ratio {out['ratio_run_median']:.1f}x (compiled "
          f"{out['ratio_compiled_median']:.1f}x); time to {T:g} us: impactdyn {t_imp:.2f} s, CalculiX {t_cx:.2f} s "
          f"({t_cx / t_imp:.1f}x)")
    print(f"{indent}  runs, M element-steps/s: impactdyn run " + ", ".join(f"{r / 1e6:.3f}" for r in rates["run"])
          + "; compiled " + ", ".join(f"{r / 1e6:.3f}" for r in rates["compiled"])
          + "; CalculiX " + ", ".join(f"{r / 1e6:.3f}" for r in rates["calculix"]))
    return out


def speed_report_wall(args, workdir: str) -> dict:
    """``--report-wall``: both codes' speed on the report's wall (module docstring), per refinement."""
    T = args.end_time
    options = wall.WallOptions(supports="clamped", end_time_us=T, output_interval_us=None, material_model="mat13")
    results = []
    for k, r in enumerate(args.report_wall):
        mesh = report_wall_mesh(r)
        v = initial_velocity(mesh, args.v0, args.patch)
        _, steps = time_impactdyn(mesh, v, T, options, "compiled")  # warm-up (compiles), and the step count
        job = f"report_wall_r{r}"
        write_deck(os.path.join(workdir, job + ".inp"), mesh, v, T, T / steps, print_every=10,
                   title=f"the report's wall x{r}, clamped")
        cx = run_ccx(args.ccx, workdir, job, args.threads)  # also the first timed CalculiX run
        cx_inc = int(np.ceil(T / cx["dt"] - 1e-9))
        print(f"\nreport wall x{r}: {mesh.n_elements} elements, {mesh.n_nodes} nodes; impactdyn {steps} steps "
              f"(mean {T / steps:.5f} us), CalculiX {cx_inc} increments of {cx['dt']:.5f} us, to {T:g} us")
        sp = speed(mesh, v, T, options, steps, cx_inc, args, workdir, job,
                   pairs=args.repeat if k == 0 else 1, first_ccx_s=cx["wall_s"])
        results.append({"refinement": r, "elements": mesh.n_elements, "nodes": mesh.n_nodes, "steps": steps,
                        "dt_us": T / steps, "calculix_increments": cx_inc, "calculix_dt_us": cx["dt"], "speed": sp})
    return {"report_wall": results}

# --- driver ---------------------------------------------------------------------------------------

def finish(args, workdir: str, results: dict) -> None:
    """Write the numbers (``--json``), remove the work folder unless ``--keep``, name numba's threading layer."""
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1, default=float)
    if not args.keep:
        shutil.rmtree(workdir, ignore_errors=True)
    print(f"numba threading layer: {numba.threading_layer()}")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesh", type=float, nargs="+", default=[0.1, 0.05],
                    help="in-plane element sizes, cm (the first is the acceptance mesh and the timed one)")
    ap.add_argument("--layers", type=int, default=4, help="elements through the 0.16-cm thickness")
    ap.add_argument("--v0", type=float, default=0.025, help="patch velocity, cm/us")
    ap.add_argument("--patch", type=float, default=0.5, help="half-width a of the central patch, cm")
    ap.add_argument("--end-time", type=float, default=100.0, help="end of both runs, us")
    ap.add_argument("--repeat", type=int, default=3, help="timed runs of each code on the first mesh")
    ap.add_argument("--threads", type=int, default=THREADS_DEFAULT)
    ap.add_argument("--ccx", default="ccx")
    ap.add_argument("--keep", default=None, help="keep the CalculiX files in this folder")
    ap.add_argument("--no-diagnostics", action="store_true", help="skip the impactdyn hourglass/mesh diagnostics")
    ap.add_argument("--json", default=None, help="write the numbers here")
    ap.add_argument("--report-wall", type=int, nargs="+", default=None, metavar="R",
                    help="speed only, on the report's wall refined R times (e.g. 1 2; use --end-time 5..10)")
    args = ap.parse_args()
    if shutil.which(args.ccx) is None:
        print(f"{args.ccx}: not found (apt-get install calculix-ccx)", file=sys.stderr)
        return 2
    numba.set_num_threads(min(args.threads, numba.config.NUMBA_NUM_THREADS))
    ccx_version = subprocess.run([args.ccx, "-v"], capture_output=True, text=True).stdout.strip().splitlines()
    workdir = args.keep or tempfile.mkdtemp(prefix="verify_wall_ccx_")
    os.makedirs(workdir, exist_ok=True)
    T = args.end_time
    if args.report_wall:
        print(f"speed on the report's wall (table2_7a grid, clamped), Al 6061-T6 type 13 without failure, V0 "
              f"{args.v0} cm/us on |x|,|z| <= {args.patch} cm, {T} us; {args.threads} threads; "
              f"{ccx_version[-1] if ccx_version else args.ccx}; numba {numba.__version__}; "
              f"OMP_WAIT_POLICY={os.environ.get('OMP_WAIT_POLICY', '(unset)')}; 1-min load average "
              f"{os.getloadavg()[0]:.2f}")
        finish(args, workdir, {"setup": vars(args), **speed_report_wall(args, workdir)})
        return 0
    defaults = wall.WallOptions(supports="clamped", end_time_us=T, output_interval_us=None,  # acceptance: defaults
                                material_model="mat13")                                   # (the card CalculiX runs)
    print(f"clamped plate 2 x 2 x {THICKNESS} cm (half model), Al 6061-T6 type 13 without failure "
          f"(E {CARD.youngs_modulus:.4f} Mbar, nu {CARD.poisson_ratio:.4f}, sigma_y {CARD.yield_stress}, "
          f"E_h {CARD.hardening_modulus}), V0 {args.v0} cm/us on |x|,|z| <= {args.patch} cm, {T} us; "
          f"{args.threads} threads; {ccx_version[-1] if ccx_version else args.ccx}; numba {numba.__version__}; "
          f"OMP_WAIT_POLICY={os.environ.get('OMP_WAIT_POLICY', '(unset)')}")
    results: dict = {"setup": vars(args), "meshes": []}
    first = None
    for k, h in enumerate(args.mesh):
        mesh = plate_mesh(h, args.layers)
        v = initial_velocity(mesh, args.v0, args.patch)
        momentum = float((mesh.node_mass[:, None] * v).sum(axis=0)[1])
        kinetic = float(0.5 * (mesh.node_mass[:, None] * v * v).sum())
        imp = run_impactdyn(mesh, v, T, defaults)
        job = f"plate_h{h:g}_l{args.layers}"
        write_deck(os.path.join(workdir, job + ".inp"), mesh, v, T, imp["dt"], print_every=10)
        cx = run_ccx(args.ccx, workdir, job, args.threads)
        cx_inc = int(np.ceil(T / cx["dt"] - 1e-9))
        cmean, clo, chi = permanent(cx["t"], cx["u"], T)
        rel = imp["deflection"] / cmean - 1.0
        row = {"h_cm": h, "layers": args.layers, "elements": mesh.n_elements, "nodes": mesh.n_nodes,
               "momentum_y": momentum, "kinetic": kinetic,
               "impactdyn": {"deflection_cm": imp["deflection"], "min": imp["min"], "max": imp["max"],
                             "peak_cm": imp["peak"], "steps": imp["steps"], "dt_us": imp["dt"],
                             "eps_p_max": imp["eps_p_max"], "hourglass_fraction": imp["hourglass_fraction"],
                             "settled_cm": imp["settled"], "settle_steps": imp["settle_steps"],
                             "plastic_over_initial_kinetic": imp["energy"]["plastic"] / kinetic},
               "calculix": {"deflection_cm": cmean, "min": clo, "max": chi, "peak_cm": float(cx["u"].max()),
                            "increments": cx_inc, "dt_us": cx["dt"]},
               "relative_difference": rel}
        print(f"\nmesh h = {h} cm x {args.layers} layers: {mesh.n_elements} elements, {mesh.n_nodes} nodes; "
              f"momentum {momentum:.6g} g cm/us, kinetic energy {kinetic:.6g} g cm^2/us^2")
        print(f"  impactdyn : permanent centre deflection {imp['deflection']:.5f} cm (oscillation "
              f"{imp['min']:.5f}..{imp['max']:.5f}, peak {imp['peak']:.5f}); {imp['steps']} steps, mean "
              f"{imp['dt']:.5f} us; hourglass/internal {imp['hourglass_fraction']:.3f}; "
              f"max eps_p {imp['eps_p_max']:.3f}")
        print(f"  impactdyn brought to rest after the run (WallSolver.settle): {imp['settled']:.5f} cm in "
              f"{imp['settle_steps']} steps, {(imp['settled'] / imp['deflection'] - 1.0) * 100:+.2f} % of its own mean, "
              f"{(imp['settled'] / cmean - 1.0) * 100:+.2f} % of CalculiX's")
        print(f"  CalculiX  : permanent centre deflection {cmean:.5f} cm (oscillation {clo:.5f}..{chi:.5f}, "
              f"peak {cx['u'].max():.5f}); {cx_inc} increments of {cx['dt']:.5f} us")
        print(f"  impactdyn / CalculiX - 1 = {rel * 100:+.2f} %  ({'within' if abs(rel) <= 0.05 else 'outside'} 5 %)")
        # speed: the same problem; the two codes alternate so that both see the same load on a shared machine
        row["speed"] = speed(mesh, v, T, defaults, imp["steps"], cx_inc, args, workdir, job,
                             pairs=args.repeat if k == 0 else 1, first_ccx_s=cx["wall_s"] if k > 0 else None)
        if k == 0:
            first = row
        results["meshes"].append(row)
        np.savetxt(os.path.join(workdir, job + "_impactdyn.txt"), np.c_[imp["t"], imp["u"]], header="t_us u_y_cm")
        np.savetxt(os.path.join(workdir, job + "_calculix.txt"), np.c_[cx["t"], cx["u"]], header="t_us u_y_cm")

    if not args.no_diagnostics:
        print("\ndiagnostics (impactdyn only; defaults unchanged): permanent centre deflection, cm")
        diag = []
        h0 = args.mesh[0]
        forms = [{"hourglass": f} for f in wall.HOURGLASS_FORMS if f != defaults.hourglass]
        cases = [(h0, {}), (h0, {"hourglass_coefficient": 0.03}), (h0, {"hourglass_coefficient": 0.01}),
                 (h0, {"q1": 0.0, "q2": 0.0})] + [(h0, f) for f in forms]
        for h in args.mesh[1:] + [min(args.mesh) / 2]:
            cases += [(h, {}), (h, {"hourglass_coefficient": 0.01})] + [(h, f) for f in forms]
        for h, change in cases:
            mesh = plate_mesh(h, args.layers)
            v = initial_velocity(mesh, args.v0, args.patch)
            opt = defaults.replaced(**change)
            r = run_impactdyn(mesh, v, T, opt, sample_us=0.5)
            label = (f"{opt.hourglass} QH {opt.hourglass_coefficient:g}"
                     + (f", Q1 {opt.q1:g} Q2 {opt.q2:g}" if (opt.q1, opt.q2) != (defaults.q1, defaults.q2) else ""))
            diag.append({"h_cm": h, "hourglass": opt.hourglass, "qh": opt.hourglass_coefficient, "q1": opt.q1,
                         "q2": opt.q2, "deflection_cm": r["deflection"], "peak_cm": r["peak"],
                         "hourglass_fraction": r["hourglass_fraction"], "eps_p_max": r["eps_p_max"]})
            print(f"  h {h:<6g} {label:32s}: {r['deflection']:.5f} (peak {r['peak']:.5f}; hourglass/internal "
                  f"{r['hourglass_fraction']:.3f}, max eps_p {r['eps_p_max']:.3f})")
        results["diagnostics"] = diag
    finish(args, workdir, results)
    ok = abs(first["relative_difference"]) <= 0.05
    print(f"\nacceptance (mesh h = {args.mesh[0]} cm): |impactdyn/CalculiX - 1| = "
          f"{abs(first['relative_difference']) * 100:.2f} % {'<=' if ok else '>'} 5 %: {'PASS' if ok else 'FAIL'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
