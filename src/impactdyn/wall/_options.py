"""Options of the wall solver, checked when made, and its breakdown error."""

from __future__ import annotations

import math
from dataclasses import dataclass

from impactdyn._errors import InputError, SimulationError
from impactdyn.wall._load import SPREADS
from impactdyn.wall._mesh import SUPPORTS
from impactdyn.wall._models import check_model_name

HOURGLASS_FORMS = ("viscous", "stiffness", "assumed_strain")
#: LS-DYNA's hourglass type (IHQ) of each form: Flanagan–Belytschko viscous 2 and stiffness 4,
#: Belytschko–Bindeman assumed strain 6 (whose QH is 1: the form has no coefficient; LS-DYNA's
#: type 6 keeps the elastic moduli, this solver's follows the material's tangent, :mod:`._step`).
LSDYNA_HOURGLASS_TYPE = {"viscous": 2, "stiffness": 4, "assumed_strain": 6}


class WallSolverError(SimulationError):
    """The wall solver broke down: a non-finite state, an element of non-positive volume that
    had not failed, or a collapsing time step.  The message names the element and the time.
    The CLI reports it as "simulation failed" with exit code 1 (:mod:`impactdyn._errors`).
    """


@dataclass(frozen=True)
class WallOptions:
    """Numerical and physical options of :func:`impactdyn.wall.run_wall` (units µs, km/s).

    refinement_thickness, refinement_plane : elements per parent element through the
        thickness and along each in-plane axis (:mod:`._mesh`).
    material_model : a registered model name (:data:`impactdyn.wall.MODELS`): "johnson_cook"
        (default: Johnson–Cook strength, Mie–Grüneisen EOS, JC damage, spall and erosion) or
        "mat13" (the report's DYNA3D type 13).  Why the default: chosen by a rule fixed before
        the runs, on a second set of 12 test shots disjoint from the first (validation set 2,
        benchmarks/select_validation_shots.py): right on 7 of 12 with 5 perforations called
        safe, against 6 of 12 and all 6 perforations called safe with the type-13 card, whose
        only failure criterion (an effective plastic strain of 1.5) no element reached on
        either set (BENCHMARKS.md, "validation set 2").
    supports : "dyngen" (DYNGEN's edge codes), "clamped", "free" or "uniaxial" (:mod:`._mesh`).
    hourglass : "assumed_strain" (default; Belytschko–Bindeman: the element's own bending and
        twisting stiffness, loaded at the material's tangent, unloaded elastically, bounded by
        the flow stress in yielding elements, :mod:`._step`) or the Flanagan–Belytschko forms
        "stiffness" and "viscous".  Why the default (benchmarks/BENCHMARKS.md, wall sections):
        on the clamped-plate check it is mesh-converged (0.244 / 0.249 / 0.251 cm at h 0.1 /
        0.05 / 0.025) and within 5 % of CalculiX (+0.2 % at h 0.1), where the stiffness form
        with QH 0.1 gave 0.117 / 0.226 / 0.241 (−52 % against CalculiX): its κ ∝ ΣB²/V grows
        with the largest face and over-stiffens the bending of elements flat in the thickness.
        On the ``table2_7a`` wall both forms give the same bulge within 1 % (0.353 / 0.349 cm);
        on the 0.16-cm wall of test shot A1603 (elements 4:1 flat) the hourglass work is 6 % of
        the internal energy against the stiffness form's 29 %.  What it costs: it keeps 21
        stresses per element and is ~30 % slower per step; its hourglass work — the element's
        own bending energy, not a spurious mode's: in bending with n elements through the
        thickness 1/(n² − 1) of the stress work, 6.7 % at the report's n = 4 (tested) — is 5.8 %
        of the internal energy on 7a with the type-13 card (stiffness 2.1 %), 13 % with
        Johnson–Cook (whose erosion leaves ligaments of 1–3 elements bending) and 17 % on the
        synthetic 7-km/s-like load of benchmarks/bench_wall.py at 40 µs (stiffness 11 %).  The
        viscous form took 55–75 % there.
    hourglass_coefficient : QH of the Flanagan–Belytschko forms (LS-DYNA's default 0.1); the
        assumed-strain form has no coefficient.
    q1, q2 : quadratic and linear bulk-viscosity coefficients (LS-DYNA's 1.5, 0.06).
    courant : safety factor on the smallest element step (0.9).
    end_time_us : end of the run; None: run until the kinetic energy of the wall (nodes of
        intact material connected to the supports, :mod:`._verdict`) has fallen below
        ``decay_fraction`` of its peak after the last arrival, or ``max_time_us``.  The solver has
        no structural damping, so a supported wall rings elastically and its kinetic energy
        seldom decays that far: all 40 Table 2 and validation runs of 2026-11-27 ended at the
        ceiling with 4–54 % of the load's work still kinetic; ``measures["ended_by"]`` says
        which end a run met (BENCHMARKS.md, "when a wall run ends").
    decay_fraction : the fraction of the peak kinetic energy that ends a run (0.05).
    max_time_us : ceiling of the run's end time (absolute time, µs).
    output_interval_us : time between output frames; None: the first and last frames only.
    history_interval_us : time between history samples (energies, bulge).
    spread : how a record's impulse is shared among the front-face nodes (:mod:`._load`):
        "area" by default — DYNA3D's equal quarters on the corners at in-plane refinement 1,
        the tributary areas of the sub-faces when refined ("corners" keeps the quarters on
        the parent's corners, which on a refined mesh leaves the nodes between them unloaded
        and crushed the loaded ones: failed mass 0 → 0.41 g at 2× refinement on a synthetic
        7-km/s-like load).
    deposition_depth_cm : the depth δ (cm) below the front face over which each record's
        impulse is spread as a uniform body force (:mod:`._load`).  None (default): half the
        first element layer of the case's grid, which at refinement 1 is DYNA3D's nodal load
        on the front face exactly and on a refined mesh the same load over the same depth;
        0: the front-face nodes alone at every refinement (the load's energy then grows with
        the refinement through the thickness).  Must not exceed the wall's thickness.
    settle : after the run, let the wall swing back once and bring it to rest by kinetic damping,
        and report its permanent rear bulge (:meth:`impactdyn.wall.WallSolver.settle`); off by
        default: it takes 15–50 times the run's steps (Table 2, 14,300–44,800 against 840–960;
        7a's wall stage about 1 min instead of ~8 s on a 2-core Zen 5 VM, 4.5 min on a slower
        Xeon VM; on a wall of twice the span and four times the elements roughly 16 times that).
        Without it no run measures a permanent set: a supported wall still rings when the run
        ends (BENCHMARKS.md, "when a wall run ends").
    settle_tolerance : the settling stops at rest with the out-of-balance force on the wall's free
        nodes below this fraction of the element forces that balance there (Euclidean norms;
        1e-3: the 7a bulge to 0.01 %, BENCHMARKS.md).
    max_settle_steps : the most steps the settling may take; if reached, ``settled`` is false.
    escape_velocity_km_s : the speed above which rear-face material attached to failed
        material is leaving the wall (verdict, :mod:`._verdict`).
    erosion_step_fraction : a failed element is eroded when its step falls below this
        fraction of the initial step.
    min_step_fraction : a step of an element that has not failed below this fraction of
        the initial step is a breakdown (:class:`WallSolverError`).
    """

    refinement_thickness: int = 1
    refinement_plane: int = 1
    material_model: str = "johnson_cook"
    supports: str = "dyngen"
    hourglass: str = "assumed_strain"
    hourglass_coefficient: float = 0.1
    q1: float = 1.5
    q2: float = 0.06
    courant: float = 0.9
    end_time_us: float | None = None
    decay_fraction: float = 0.05
    max_time_us: float = 100.0
    output_interval_us: float | None = 1.0
    history_interval_us: float = 0.2
    spread: str = "area"
    deposition_depth_cm: float | None = None
    settle: bool = False
    settle_tolerance: float = 1.0e-3
    max_settle_steps: int = 200_000
    escape_velocity_km_s: float = 1.0
    erosion_step_fraction: float = 0.1
    min_step_fraction: float = 1.0e-3

    def __post_init__(self) -> None:
        for name in ("refinement_thickness", "refinement_plane", "max_settle_steps"):
            r = getattr(self, name)
            if isinstance(r, bool) or not isinstance(r, int) or r < 1:
                raise InputError(f"{name}: must be a positive integer, got {r!r}")
        check_model_name(self.material_model)
        if not isinstance(self.settle, bool):
            raise InputError(f"settle: must be true or false, got {self.settle!r}")
        _check("settle_tolerance", self.settle_tolerance, lo=0.0, lo_open=True, hi=1.0)
        if self.supports not in SUPPORTS:
            raise InputError(f"supports: {self.supports!r}, expected one of {SUPPORTS}")
        if self.hourglass not in HOURGLASS_FORMS:
            raise InputError(f"hourglass: {self.hourglass!r}, expected one of {HOURGLASS_FORMS}")
        if self.spread not in SPREADS:
            raise InputError(f"spread: {self.spread!r}, expected one of {SPREADS}")
        for name in ("hourglass_coefficient", "q1", "q2"):
            _check(name, getattr(self, name), lo=0.0)
        _check("courant", self.courant, lo=0.0, lo_open=True, hi=1.0)
        _check("decay_fraction", self.decay_fraction, lo=0.0, lo_open=True, hi=1.0)
        _check("max_time_us", self.max_time_us, lo=0.0, lo_open=True)
        _check("history_interval_us", self.history_interval_us, lo=0.0, lo_open=True)
        _check("escape_velocity_km_s", self.escape_velocity_km_s, lo=0.0, lo_open=True)
        _check("erosion_step_fraction", self.erosion_step_fraction, lo=0.0, hi=1.0)
        _check("min_step_fraction", self.min_step_fraction, lo=0.0, lo_open=True, hi=1.0)
        if self.end_time_us is not None:
            _check("end_time_us", self.end_time_us, lo=0.0, lo_open=True)
        if self.deposition_depth_cm is not None:
            _check("deposition_depth_cm", self.deposition_depth_cm, lo=0.0)
        if self.output_interval_us is not None:
            _check("output_interval_us", self.output_interval_us, lo=0.0, lo_open=True)

    @property
    def hourglass_form(self) -> int:
        """The kernels' code of the hourglass form (its index in :data:`HOURGLASS_FORMS`)."""
        return HOURGLASS_FORMS.index(self.hourglass)

    @property
    def lsdyna_hourglass(self) -> tuple[int, float]:
        """(IHQ, QH) of LS-DYNA's *CONTROL_HOURGLASS for these options (:data:`LSDYNA_HOURGLASS_TYPE`)."""
        ihq = LSDYNA_HOURGLASS_TYPE[self.hourglass]
        return ihq, 1.0 if ihq == 6 else self.hourglass_coefficient


def _check(name: str, value, lo: float | None = None, hi: float | None = None, lo_open: bool = False) -> None:
    ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
    if ok and lo is not None:
        ok = value > lo if lo_open else value >= lo
    if ok and hi is not None:
        ok = value <= hi
    if not ok:
        rng = f"{'(' if lo_open else '['}{lo if lo is not None else '-inf'}, {hi if hi is not None else 'inf'}]"
        raise InputError(f"{name}: must be a finite number in {rng}, got {value!r}")
