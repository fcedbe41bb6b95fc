"""The wall solver's driver: state set-up, the run loop over compiled steps, histories, verdict.

The time loop is the compiled step loop of the model (:func:`impactdyn.wall._step.step_kernels`), called once per history
sample (``history_interval_us``): between calls Python samples the energies, updates the
node categories of :mod:`._verdict` (only when the set of failed elements changed), takes
output frames and checks the end of the run.  With the report's wall the compiled loop
runs one or a few steps per call; the Python part costs well under a millisecond per call
(benchmarks/bench_wall.py measures both ways of driving the steps).

Energy balance (g·cm²/µs²), from the work of every force (:mod:`._step`)::

    E_in = W_load + K₀ = K + W_σ + W_hg + W_q + E_eroded + error

K₀ the initial kinetic energy, K the kinetic energy ½ Σ m |v^{n+½}|² of the nodes that are not
orphans, W_σ the stress work of the elements not eroded (= internal energy: elastic + plastic;
plastic = Σ σ_eq Δεₚ V), W_hg and W_q their hourglass and bulk-viscous work, E_eroded the work
done on eroded elements plus the kinetic energy of orphan nodes (eroded material keeps its
mass and momentum on its nodes).  Every work is taken over the interval its force acts
(:mod:`._step`), so the balance closes to round-off: ``balance_error`` = error / E_in is a
check of the bookkeeping (of erosion included), not a measure of discretisation error.

Momentum: the impulse applied to free translations plus the impulse taken by fixed ones
equals the deposited impulse (:mod:`._load`); both are reported.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numba
import numpy as np

from impactdyn._errors import InputError
from impactdyn.materials import Mat13Card, Material
from impactdyn.units import CM_US_PER_KM_S, KM_S_PER_CM_US
from impactdyn.wall import _settle, _step
from impactdyn.wall._blocks import hourglass_stress_array, work_arrays
from impactdyn.wall._diagnostics import energy_sums, nodal_energy
from impactdyn.wall._load import NodalLoad, nodal_load
from impactdyn.wall._grading import solver_mesh
from impactdyn.wall._mesh import WallMesh
from impactdyn.wall._models import MODELS, WallModel
from impactdyn.wall._options import WallOptions, WallSolverError
from impactdyn.wall._result import (
    ENDED_AT_CEILING, ENDED_AT_END_TIME, ENDED_BY_DECAY, ENDED_BY_PERFORATION, HISTORY_KEYS, WallFrame, WallResult)
from impactdyn.wall._state import (
    C, DAMAGE, EPS_P, ERODED, FAILED, N_ES, N_SHG, P, VOL, Controls, Elements, MaterialConstants, Nodes)
from impactdyn.wall._verdict import WALL, classify, failed_mass_by_cause, measures, node_categories, through_path
from impactdyn.wallgrid import WallDeposition, WallGrid

_BREAKDOWN = {_step.BAD_VOLUME: "non-positive volume", _step.BAD_STEP: "time step collapsed",
              _step.BAD_FORCE: "non-finite force"}


def resolve_model(model: Any, options: WallOptions) -> WallModel:
    """The model instance: ``model`` itself, or ``options.material_model`` built from a material with the
    options' settings the model takes (its ``option_keys``)."""
    if isinstance(model, WallModel):
        if model.name != options.material_model:
            raise InputError(f"material_model: {options.material_model!r} does not match the model given "
                             f"({model.name!r})")
        return model
    if isinstance(model, (str, Material, Mat13Card)):
        kind = MODELS[options.material_model]
        return kind.from_material(model, **{key: getattr(options, key) for key in kind.option_keys})
    raise InputError(f"model: expected a wall model, a library material name, Material or Mat13Card, got {model!r}")


class WallSolver:
    """Explicit FE solver of one wall (module docstring); use :func:`run_wall` for a deposition.

    mesh, model, options : the problem.  load : nodal impulses (:func:`nodal_load`) or None.
    velocity : (n_nodes, 3) initial velocities, cm/µs (zero on fixed translations), or None.
    t_start : initial time, µs.
    """

    def __init__(self, mesh: WallMesh, model: WallModel, options: WallOptions, load: NodalLoad | None = None,
                 velocity: np.ndarray | None = None, t_start: float = 0.0):
        self.mesh, self.model, self.options = mesh, model, options
        nn, ne = mesh.n_nodes, mesh.n_elements
        self.x0 = mesh.coordinates.copy()
        free = (~mesh.fixed).astype(np.float64)
        v = np.zeros((nn, 3))
        if velocity is not None:
            v[:] = np.asarray(velocity, dtype=np.float64) * free
        self.rear_nodes = mesh.face_nodes("rear").ravel()
        self.front_nodes = mesh.face_nodes("front").ravel()
        rear = np.zeros(nn, dtype=np.uint8)
        rear[self.rear_nodes] = 1
        self.nodes = Nodes(x=mesh.coordinates.copy(), v=v, mass=mesh.node_mass, free=free,
                           fixed=np.ascontiguousarray(mesh.fixed), pext=np.zeros((nn, 3)), rear=rear,
                           category=np.zeros(nn, dtype=np.int8))
        F = np.zeros((ne, 8, 3))
        es = np.zeros((ne, N_ES))
        es[:, VOL] = mesh.volume
        es[:, C] = model.wave_speed()
        self.elements = Elements(
            conn=mesh.connectivity, vol0=mesh.volume, mass=mesh.element_mass, S=np.zeros((ne, 6)), es=es,
            flags=np.zeros((ne, 2), dtype=np.uint8), bad=np.zeros(ne, dtype=np.int8), Lbuf=np.zeros((ne, 3, 3)),
            Qhg=np.zeros((ne, 4, 3)),
            # the assumed-strain form's stored hourglass stresses, blocked (:func:`._blocks.hourglass_stress_array`)
            Shg=hourglass_stress_array(ne if options.hourglass == "assumed_strain" else 0),
            F=F, F_flat=F.reshape(ne * 8, 3), node_ptr=mesh.node_element_ptr, node_entry=mesh.node_element_entry)
        bulk, shear = model.reference_moduli()
        self.material = MaterialConstants(
            params=np.ascontiguousarray(model.kernel_params(), dtype=np.float64),
            table=np.ascontiguousarray(model.kernel_table(), dtype=np.float64),
            bulk=float(bulk), shear=float(shear))
        self.controls = Controls(hg_form=options.hourglass_form, qh=float(options.hourglass_coefficient),
                                 q1=float(options.q1), q2=float(options.q2), courant=float(options.courant),
                                 erode_failed=bool(model.erodes), erode_dt=0.0, min_dt=0.0)
        self.kernels = _step.step_kernels(model.update_kernel)
        self.work = work_arrays(numba.config.NUMBA_NUM_THREADS)
        self.acc = np.zeros(_step.N_ACC)
        self.acc[_step.A_REAR_VMAX] = -np.inf
        self.load = load if load is not None else nodal_load_empty()
        status, dtmin = self.element_pass(0.0)
        if status or not math.isfinite(dtmin):
            raise WallSolverError(f"wall solver: the initial mesh is not valid ({_BREAKDOWN.get(status, status)})")
        self.dt_element0 = dtmin
        self.controls = self.controls._replace(erode_dt=options.erosion_step_fraction * dtmin,
                                               min_dt=options.min_step_fraction * dtmin)
        # the settling steps' controls (:mod:`._settle`): a smaller Courant factor, no bulk viscosity
        self.settling_controls = self.controls._replace(q1=0.0, q2=0.0,
                                                        courant=min(options.courant, _settle.SETTLE_COURANT))
        self.clock = np.array([t_start, 0.0, options.courant * dtmin, 0.0, 0.0, 0.0])
        self._damaged_count = 0
        self.through_since: float | None = None
        self.k0 = None

    # -- compiled passes ------------------------------------------------------------------------------
    def element_pass(self, dt: float, dt_full_prev: float = 0.0) -> tuple[int, float]:
        """One element pass over the current x, v (:func:`impactdyn.wall._step.step_kernels`), for
        stepping by hand (verification); returns (status, min Δt_e)."""
        return self.kernels.element_pass(self.nodes, self.elements, self.material, self.controls, self.work, dt,
                                         dt_full_prev)

    def advance(self, t_stop: float, max_steps: int = 2**62, settling: bool = False) -> int:
        """Step until t ≥ ``t_stop`` (or ``max_steps`` steps); returns the steps taken.  ``settling``:
        the steps of :meth:`settle` (Courant factor at most :data:`._settle.SETTLE_COURANT`, no bulk
        viscosity).

        Raises :class:`WallSolverError` on a breakdown.
        """
        m = self.mesh
        status, steps = self.kernels.advance(t_stop, max_steps, self.clock, self.acc, self.nodes, self.elements,
                                             self.material, self.settling_controls if settling else self.controls,
                                             self.load, self.work)
        if status:
            bad = np.flatnonzero(self.elements.bad)
            ijk = m.element_ijk()[bad[0]] if bad.size else None
            raise WallSolverError(
                f"wall solver broke down at t = {self.time:.4g} us: {_BREAKDOWN.get(status, status)} in "
                f"{bad.size} element(s), first element {bad[0] if bad.size else '?'} (i, j, k) = "
                f"{tuple(int(a) for a in ijk) if ijk is not None else '?'}")
        return steps

    # -- state views ----------------------------------------------------------------------------------
    @property
    def x(self) -> np.ndarray:
        return self.nodes.x

    @property
    def v(self) -> np.ndarray:
        return self.nodes.v

    @property
    def category(self) -> np.ndarray:
        return self.nodes.category

    @property
    def S(self) -> np.ndarray:
        return self.elements.S

    @property
    def es(self) -> np.ndarray:
        return self.elements.es

    @property
    def flags(self) -> np.ndarray:
        return self.elements.flags

    @property
    def time(self) -> float:
        return float(self.clock[_step.T_NOW])

    @property
    def steps(self) -> int:
        return int(self.clock[_step.STEPS])

    @property
    def hourglass_stress(self) -> np.ndarray:
        """The assumed-strain form's stored hourglass stresses per element, (n_elements, N_SHG) (a new
        array; columns in :mod:`._state`); (0, N_SHG) with the other forms."""
        return self.elements.Shg.transpose(0, 2, 1).reshape(-1, N_SHG)[:self.mesh.n_elements]

    @property
    def failed(self) -> np.ndarray:
        return self.flags[:, FAILED] != 0

    @property
    def eroded(self) -> np.ndarray:
        return self.flags[:, ERODED] != 0

    @property
    def last_arrival(self) -> float | None:
        """The time of the last deposition record applied so far, µs (None before the first)."""
        applied = int(self.clock[_step.CURSOR])
        return float(self.load.time[applied - 1]) if applied else None

    @property
    def loads_done(self) -> bool:
        return int(self.clock[_step.CURSOR]) >= self.load.time.size

    def unapplied_load(self) -> tuple[int, np.ndarray]:
        """(records, Σ impulse (3,) g·cm/µs) of the deposition not applied yet: at the end of a run
        ended by a settled perforation, the records that arrive after it."""
        rest = self.load.impulse[int(self.clock[_step.CURSOR]):]
        return len(rest), rest.sum(axis=0) if len(rest) else np.zeros(3)

    def update_categories(self) -> None:
        """Node categories of :mod:`._verdict` and the time a through-thickness path of damaged elements
        first appeared (:attr:`through_since`), recomputed when the set of damaged elements changed."""
        n = int(np.count_nonzero(self.flags))
        if n != self._damaged_count:
            self._damaged_count = n
            self.nodes.category[:] = node_categories(self.mesh, self.failed, self.eroded)
            if self.through_since is None and through_path(self.mesh, self.failed | self.eroded).any():
                self.through_since = self.time

    def energies(self) -> dict[str, float]:
        """The energy balance at the current time (module docstring)."""
        dt_full = 0.5 * (self.clock[_step.DT_PREV] + self.clock[_step.DT_NEXT])
        kin, kin_wall, kin_orphan, kin_cross, mom = nodal_energy(self.nodes, self.elements, dt_full)
        if self.k0 is None:
            self.k0 = kin
        live, gone = energy_sums(self.elements)      # (W_σ, W_p, W_hg, W_q)
        out = {
            "load_work": float(self.acc[_step.A_LOAD_WORK]),
            "initial_kinetic": float(self.k0),
            "kinetic": float(kin - kin_orphan),
            "kinetic_wall": float(kin_wall),
            "kinetic_cd": float(kin_cross),
            "internal": float(live[0]),
            "plastic": float(live[1]),
            "hourglass": float(live[2]),
            "bulk_viscous": float(live[3]),
            "eroded": float(gone[0] + gone[2] + gone[3] + kin_orphan),
            "momentum_y": float(mom[1]),
        }
        out["elastic"] = out["internal"] - out["plastic"]
        e_in = out["load_work"] + out["initial_kinetic"]
        held = out["kinetic"] + out["internal"] + out["hourglass"] + out["bulk_viscous"] + out["eroded"]
        out["balance_error"] = (e_in - held) / e_in if e_in > 0 else 0.0
        return out

    def settle(self, progress: Callable[[float, float], None] | None = None) -> dict[str, Any]:
        """Let the wall swing back, bring it to rest by kinetic damping and measure its permanent bulge
        (:func:`impactdyn.wall._settle.settle`, which says how and what it returns)."""
        return _settle.settle(self, progress)

    def frame(self) -> WallFrame:
        """The current state as an output frame."""
        es, S = self.es, self.S
        vm = np.sqrt(1.5 * (S[:, :3] ** 2).sum(axis=1) + 3.0 * (S[:, 3:] ** 2).sum(axis=1))
        f4 = np.float32
        return WallFrame(time=self.time, displacement=(self.x - self.x0).astype(f4), velocity=self.v.astype(f4),
                         plastic_strain=es[:, EPS_P].astype(f4), damage=es[:, DAMAGE].astype(f4),
                         pressure=es[:, P].astype(f4), von_mises=vm.astype(f4),
                         failure_cause=self.flags[:, FAILED].copy(), eroded=self.eroded.copy())

    def surface(self) -> tuple[float, float]:
        """(rear bulge, front dent) of the wall nodes now, cm."""
        out = []
        for nodes in (self.rear_nodes, self.front_nodes):
            nodes = nodes[self.category[nodes] == WALL]
            u = self.x[nodes, 1] - self.x0[nodes, 1]
            out.append(float(max(u.max(), 0.0)) if nodes.size else 0.0)
        return out[0], out[1]

    def perforation_settled(self) -> bool:
        """True once a through-thickness path of damaged elements has held for ``perforation_hold_us``
        and no record has arrived for as long: the later of the path's appearance and the last arrival
        so far, plus the hold.  Failure is for good (:mod:`._verdict`), so from the path's first
        appearance the verdict is "perforation" whatever follows; the hold only lets the hole and the
        failed mass the report shows grow on for a stated time.  Records still to come do not hold the
        run open: a compact fragment may land at any time up to the ceiling (one 0.05 % of the load's
        momentum at 87 µs kept a wall holed at ~25 µs running to 90 µs at a collapsed step); those
        not applied are counted in the measures (``unapplied_records``, ``impulse_unapplied``)."""
        hold = self.options.perforation_hold_us
        if hold is None or self.through_since is None:
            return False
        t_last = self.last_arrival
        return self.time >= (self.through_since if t_last is None else max(self.through_since, t_last)) + hold

    # -- the run --------------------------------------------------------------------------------------
    def run(self, progress: Callable[[float, float], None] | None = None,
            settle_progress: Callable[[float, float], None] | None = None) -> WallResult:
        """Run to the end time of the options (:class:`WallOptions`) and judge the wall; with
        ``settle``, then bring it to rest (:meth:`settle`, reporting to ``settle_progress``)."""
        o = self.options
        t_end = o.end_time_us if o.end_time_us is not None else o.max_time_us
        history: dict[str, list[float]] = {k: [] for k in HISTORY_KEYS}
        frames: list[WallFrame] = []
        peak_wall = 0.0
        rear_peak = -np.inf
        out_dt = o.output_interval_us if o.output_interval_us is not None else math.inf
        next_hist = self.time + o.history_interval_us
        next_out = self.time + out_dt

        def sample() -> dict[str, float]:
            nonlocal rear_peak
            en = self.energies()
            bulge, dent = self.surface()
            vr = float(self.acc[_step.A_REAR_VMAX])
            rear_peak = max(rear_peak, vr)
            self.acc[_step.A_REAR_VMAX] = -np.inf
            row = {**en, "time": self.time, "rear_bulge": bulge, "front_dent": dent,
                   "rear_velocity": vr if math.isfinite(vr) else 0.0}
            for k in HISTORY_KEYS:
                history[k].append(row[k])
            return row

        self.update_categories()
        sample()
        frames.append(self.frame())
        while True:
            t_stop = min(next_hist, next_out, t_end)
            if t_stop > self.time:
                self.advance(t_stop)
            self.update_categories()
            row = sample()
            peak_wall = max(peak_wall, row["kinetic_wall"])
            if self.time >= next_hist:
                next_hist = self.time + o.history_interval_us
            if self.time >= next_out:
                frames.append(self.frame())
                next_out = self.time + out_dt
            if progress is not None:
                progress(self.time, t_end)
            if self.time >= t_end:
                ended_by = ENDED_AT_END_TIME if o.end_time_us is not None else ENDED_AT_CEILING
                break
            if o.end_time_us is None:
                if self.loads_done and row["kinetic_wall"] <= o.decay_fraction * peak_wall:
                    ended_by = ENDED_BY_DECAY
                    break
                if self.perforation_settled():
                    ended_by = ENDED_BY_PERFORATION
                    break
        if frames[-1].time != self.time:
            frames.append(self.frame())
        kinetic_left = row["kinetic_wall"] / peak_wall if peak_wall > 0.0 else 0.0
        result = self._result(history, tuple(frames), rear_peak, ended_by, kinetic_left)
        if o.settle:
            result.measures.update(self.settle(settle_progress))
        return result

    def _result(self, history: dict[str, list[float]], frames: tuple[WallFrame, ...], rear_peak: float,
                ended_by: str, kinetic_left: float) -> WallResult:
        o = self.options
        final = frames[-1]
        verdict, evidence = classify(self.mesh, final.failed, final.eroded, self.v,
                                     o.escape_velocity_km_s * CM_US_PER_KM_S)
        meas = measures(self.mesh, final.failed, final.eroded, self.x - self.x0)
        meas["failed_mass_by_cause_g"] = failed_mass_by_cause(self.mesh, final.failure_cause)
        en = self.energies()
        hist = {k: np.asarray(v, dtype=np.float64) for k, v in history.items()}
        wall_thickness = self.mesh.thickness
        t_last = self.last_arrival if self.last_arrival is not None else float(hist["time"][0])
        unapplied, impulse_unapplied = self.unapplied_load()
        t = hist["time"]
        window = t >= t_last + 0.75 * (t[-1] - t_last)
        i_peak = int(np.argmax(hist["rear_bulge"]))
        meas.update({
            "rear_bulge_cm": float(hist["rear_bulge"][window].mean()) if window.any() else meas["rear_bulge_end_cm"],
            "wall_thickness_cm": wall_thickness,
            "deposition_depth_cm": self.load.depth,
            "peak_rear_bulge_cm": float(hist["rear_bulge"][i_peak]),
            "peak_rear_bulge_time_us": float(t[i_peak]),
            "end_time_us": self.time,
            "ended_by": ended_by,
            "perforated_at_us": self.through_since,
            "kinetic_left_fraction": kinetic_left,
            "steps": self.steps,
            "peak_rear_velocity_km_s": (rear_peak if math.isfinite(rear_peak) else 0.0) * KM_S_PER_CM_US,
            "peak_kinetic_energy": float(hist["kinetic"].max()) if hist["kinetic"].size else 0.0,
            "energy": {k: en[k] for k in ("load_work", "initial_kinetic", "kinetic", "internal", "elastic", "plastic",
                                         "hourglass", "bulk_viscous", "eroded", "balance_error")},
            "hourglass_to_internal": en["hourglass"] / en["internal"] if en["internal"] > 0 else 0.0,
            "impulse_deposited": self.load.total_impulse.tolist(),
            "unapplied_records": unapplied,
            "impulse_unapplied": impulse_unapplied.tolist(),
            "impulse_applied": self.acc[_step.A_APPLIED:_step.A_APPLIED + 3].tolist(),
            "impulse_supports": self.acc[_step.A_SUPPORT:_step.A_SUPPORT + 3].tolist(),
        })
        return WallResult(verdict=verdict, evidence=evidence, measures=meas, history=hist, frames=frames,
                          mesh=self.mesh, options=o, model=self.model.describe())


def nodal_load_empty() -> NodalLoad:
    """A load with no records."""
    return NodalLoad(time=np.zeros(0), impulse=np.zeros((0, 3)), stencil=np.zeros(0, dtype=np.int64),
                     ptr=np.zeros(1, dtype=np.int64),
                     node=np.zeros(0, dtype=np.int64), weight=np.zeros(0))


def check_end_times(options: WallOptions, deposition: WallDeposition, key_prefix: str = "") -> None:
    """Refuse an ``end_time_us`` or ``max_time_us`` before the deposition's last arrival, naming the key
    as the caller's input spells it (``key_prefix``: "wall_solver." in a Whipple case)."""
    last = float(deposition.time.max()) if deposition.time.size else 0.0
    for key, value in (("end_time_us", options.end_time_us), ("max_time_us", options.max_time_us)):
        if value is not None and value < last:
            raise InputError(f"{key_prefix}{key} = {value:g} us is before the last arrival on the wall, "
                             f"at {last:.6g} us")


def run_wall(wall: WallGrid, deposition: WallDeposition, model: Any = "al6061-t6",
             options: WallOptions | None = None,
             progress: Callable[[float, float], None] | None = None,
             settle_progress: Callable[[float, float], None] | None = None) -> WallResult:
    """The rear wall's response to the deposited momentum, its verdict and measures.

    wall : the case's wall grid (front face y = y[0]); deposition : the records on its face grid.
    model : a wall model (:func:`impactdyn.wall.wall_model`), or the material the model named by
        ``options.material_model`` is built from (a library name, Material, or for "mat13" a
        :class:`~impactdyn.materials.Mat13Card`).
    options : :class:`WallOptions` (defaults when None).
    progress : called as ``progress(t_us, t_end_us)`` after every history sample.
    settle_progress : with ``options.settle``, called as ``progress(done, 1)`` while the wall is
        brought to rest (:meth:`WallSolver.settle`).

    The run starts at the first arrival (nothing moves before it).  Raises
    :class:`~impactdyn._errors.InputError` naming the key for bad input (an end time before the
    last arrival included) and :class:`WallSolverError` on a breakdown.
    """
    return wall_solver(wall, deposition, model, options).run(progress, settle_progress)


def wall_solver(wall: WallGrid, deposition: WallDeposition, model: Any = "al6061-t6",
                options: WallOptions | None = None) -> WallSolver:
    """The solver :func:`run_wall` runs, set up at the first arrival and not yet stepped (its arguments):
    the case's solver mesh, the deposition as nodal impulses, the model.  For stepping it otherwise than
    :meth:`WallSolver.run` does (a study sampling the run, a probe)."""
    options = options if options is not None else WallOptions()
    if not isinstance(options, WallOptions):
        raise InputError(f"options: expected WallOptions, got {type(options).__name__}")
    m = resolve_model(model, options)
    if wall.thickness <= 0:
        raise InputError("wall: thickness must be > 0")
    mesh = solver_mesh(wall, deposition, m.density, **options.mesh_settings())
    load = nodal_load(mesh, deposition, options.spread, options.deposition_depth_cm)
    t_start = float(load.time.min()) if load.time.size else 0.0
    check_end_times(options, deposition)
    return WallSolver(mesh, m, options, load=load, t_start=t_start)
