"""Event-driven integration of the beam with impacts (IMPACTC / IMPACTB, modernised).

The run is a hybrid system with three modes. Each smooth segment is integrated by
the compiled Rosenbrock 4(3) method of ``_integrator`` with the model's analytic
Jacobian (the default, ``solver.method = "rosenbrock"``), or, for cross-checks, by
SciPy's Radau, BDF or LSODA stepped one step at a time with the compiled right-hand
side:

* **free** — no contact force. Event: the gap g crosses zero downward.
* **contact** (compliant laws) — the law's force acts while δ = −g > 0. Events:
  g crosses zero upward (leaves the stop), the law's release indicator crosses
  zero (the force would turn tensile: it is clipped to zero, and the contact's
  force phase ends there; it may resume while δ > 0, which opens a new contact).
* **resting** (impulsive law) — the stop point slides along the stop with g = ġ = 0,
  held by the multiplier λ ≥ 0. Event: λ crosses zero (the stop would pull).

Events are located on the cubic Hermite interpolant of the step, the dense output
every solver path shares (``_integrator.process_step``), by Brent's method and then
bisection to the first float of time past the crossing; the solver restarts at every
event and at the torque-pulse corners, so no step straddles a discontinuity. Each step is sampled at
interior points so a crossing and recrossing inside one step is not missed, and a
restart just after an impact brackets the next crossing from the first instant the
stop point is clear.

**Chattering (momentum law).** The hub is light (IR = 0.002), so after the first
strike the hub–beam motion rings against the stop in a rapid sequence of ever
smaller impacts; with the listing's restitution law e → 1 as v → 0, so the sequence
would not end by itself. An impact whose approach speed is below
``rest_velocity_m_s`` (default 5e-3 m/s, the listing's EPSV) is treated as plastic
(e = 0); if the stop then pushes (λ > 0) the contact becomes *resting* until λ
changes sign. Every impact, micro or not, is reported, and ``max_impacts`` stops a
run that would otherwise never end, with a clear error rather than a silent stop.
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import BDF, LSODA, Radau
from scipy.optimize import brentq

from impactdyn._errors import SimulationError
from impactdyn.beam._case import BeamCase, MomentumContact
from impactdyn.beam._contact import CONTACT_LAWS, ContactLaw, force_kernel
from impactdyn.beam._integrator import (
    EVENT, SAMPLES_PER_STEP, STEP_UNDERFLOW, TOO_MANY_STEPS, Outputs, Step, event_scan, hermite, process_step,
    record_outputs, rosenbrock_segment, track_peak)
from impactdyn.beam._model import IN_CONTACT, BeamModel, _law_slopes, event_kernel, rhs_kernel
from impactdyn.beam._modes import modal_integrals, shapes
from impactdyn.beam._step_control import StepControl, least_step

_SOLVERS = {"Radau": Radau, "BDF": BDF, "LSODA": LSODA}
FREE, CONTACT, RESTING = "free", "contact", "resting"
_MODE_CODES = {FREE: 0.0, CONTACT: 1.0, RESTING: 2.0}


@dataclass(frozen=True)
class Impact:
    """One contact event (SI).

    For impulsive impacts ``t_start == t_end``, ``peak_force`` is None and
    ``impulse`` is the momentum-balance impulse P; for compliant contacts
    ``impulse`` is ∫F dt over the force phase.
    """

    t_start: float
    t_end: float
    v_approach: float
    v_separation: float
    restitution: float
    peak_force: float | None
    impulse: float
    kind: str

    def as_dict(self) -> dict:
        return dict(self.__dict__)


@dataclass(frozen=True)
class Result:
    """Outcome of :func:`simulate`.

    Attributes
    ----------
    t : (m,) output times, s.
    y : (m, 2n + 7) states at the output times (layout in ``impactdyn.beam._model``).
    contact_force : (m,) contact force at the output times, N (0 at impulsive impacts).
    impacts : every contact, in order.
    resting : (k, 2) start and end times of resting-contact intervals.
    stats : solver statistics (steps, rhs evaluations, restarts).
    """

    case: BeamCase
    model: BeamModel
    t: np.ndarray
    y: np.ndarray
    contact_force: np.ndarray
    impacts: list[Impact]
    resting: np.ndarray
    stats: dict
    wall_time_s: float

    @property
    def theta(self) -> np.ndarray:
        return self.model.split(self.y)[0]

    @property
    def theta_dot(self) -> np.ndarray:
        return self.model.split(self.y)[2]

    @property
    def energy(self) -> np.ndarray:
        return self.model.energy(self.y)

    def energy_terms(self) -> dict[str, np.ndarray]:
        """Energy E, torque work, the three losses, and the balance residual, each (m,)."""
        base = 2 * self.model.n + 2
        e = self.energy
        w_tau, d_joint, d_modal, w_contact = (self.y[:, base + i] for i in range(4))
        return {
            "energy": e,
            "work_torque": w_tau,
            "dissipated_joint": d_joint,
            "dissipated_modal": d_modal,
            "work_contact": w_contact,
            "residual": e - e[0] - (w_tau - d_joint - d_modal + w_contact),
        }

    def summary(self) -> dict:
        th, q, thd, qd = self.model.split(self.y[-1])
        terms = {k: float(v[-1]) for k, v in self.energy_terms().items()}
        return {
            "n_impacts": len(self.impacts),
            "impacts": [i.as_dict() for i in self.impacts],
            "resting_contact": self.resting.tolist(),
            "final_state": {
                "t": float(self.t[-1]),
                "theta": float(th),
                "theta_dot": float(thd),
                "q": q.tolist(),
                "q_dot": qd.tolist(),
            },
            "energy": {
                "initial": float(self.energy[0]),
                "final": terms["energy"],
                "work_torque": terms["work_torque"],
                "dissipated": terms["dissipated_joint"] + terms["dissipated_modal"] - terms["work_contact"],
                "dissipated_joint": terms["dissipated_joint"],
                "dissipated_modal": terms["dissipated_modal"],
                "dissipated_contact": -terms["work_contact"],
                "balance_residual": terms["residual"],
            },
            "solver": self.stats,
            "wall_time_s": self.wall_time_s,
        }


def contact_law(case: BeamCase) -> ContactLaw:
    """The registered contact law object configured by ``case.contact``."""
    c = case.contact
    cls = CONTACT_LAWS[c.model]
    if isinstance(c, MomentumContact):
        return cls(restitution=c.restitution if c.restitution_law == "constant" else None)
    if c.model == "hertz":
        return cls(stiffness=c.stiffness_N_m1_5, damping=c.damping_s_m)
    return cls(stiffness=c.stiffness_N_m_n, exponent=c.exponent, restitution=c.restitution)


def torque_schedule(case: BeamCase) -> tuple[np.ndarray, np.ndarray]:
    """Corner times (k,) and the torque on each interval (k + 1,) of the pulse (listing EQNS)."""
    tq = case.torque
    T, f, tau = tq.pulse_duration_s, tq.zero_fraction, tq.amplitude_N_m
    corners = np.array([T, (1 + f) * T, (2 + f) * T])
    return corners, np.array([tau, 0.0, -tau, 0.0])


def initial_state(case: BeamCase, model: BeamModel) -> np.ndarray:
    """y(t₀): θ, θ̇, modal amplitudes (explicit, or IMPACTB's tip values put into mode 1)."""
    n = model.n
    y = np.zeros(model.n_state)
    ic = case.initial
    y[0], y[n + 1] = ic.theta_rad, ic.theta_dot_rad_s
    if ic.q_m is not None:
        y[1 : n + 1] = ic.q_m
    if ic.q_dot_m_s is not None:
        y[n + 2 : 2 * n + 2] = ic.q_dot_m_s
    if n:
        tip = float(shapes(modal_integrals(n).beta[:1], np.float64(1.0))[0])
        y[1] += ic.tip_deflection_m / tip
        y[n + 2] += ic.tip_velocity_m_s / tip
    return y


@dataclass
class _Run:
    """Mutable bookkeeping of one simulation (private to :func:`simulate`)."""

    model: BeamModel
    law: ContactLaw
    control: StepControl
    out: Outputs
    k_out: int = 0
    impacts: list = field(default_factory=list)
    resting: list = field(default_factory=list)
    counts: np.ndarray = field(default_factory=lambda: np.zeros(4))  # steps, rejected, rhs, Jacobian evaluations
    n_restarts: int = 0
    h_next: float = 1e-4


@dataclass
class _Mode:
    """The hybrid system's discrete state."""

    kind: str = FREE
    force_on: bool = False
    v0: float = 1.0
    contact: dict | None = None  # the open compliant contact
    rest_start: float | None = None

    def code(self) -> float:
        return _MODE_CODES[self.kind]


def _event_directions(mode: _Mode) -> np.ndarray:
    """Crossing directions of the two event slots of ``event_kernel`` in this mode."""
    if mode.kind == FREE:
        return np.array([-1, 0])  # strike: g falls through 0
    if mode.kind == RESTING:
        return np.array([-1, 0])  # lift-off: λ falls through 0
    return np.array([+1, -1 if mode.force_on else +1])  # leave; release / re-engage


_FIRST_EVENT = {FREE: "strike", RESTING: "lift_off", CONTACT: "leave"}


def _event_name(mode: _Mode, e: int) -> str:
    """Name of event slot e (0 or 1) in the current mode."""
    if e == 0:
        return _FIRST_EVENT[mode.kind]
    return "release" if mode.force_on else "reengage"


def _first_step(model: BeamModel, y: np.ndarray, f: np.ndarray, h: float) -> float:
    """Limit the first step after a restart on the stop (g ≈ 0) to the flight time of a
    possible micro-hop, 2|ġ|/|g̈| when ġ and g̈ have opposite signs, so that its
    interior samples see the hop."""
    n = model.n
    gd = model.gap_rate(y)
    gdd = model.jacobian_row() @ f[n + 1 : 2 * n + 2]
    if gd * gdd < 0 and abs(model.gap(y)) < 1e-9:
        return min(h, 2.0 * abs(gd) / abs(gdd))
    return h


class _Segment:
    """One smooth segment's parameters, bound for the kernels."""

    def __init__(self, run: "_Run", mode: _Mode, sc: np.ndarray):
        self.run, self.mode = run, mode
        self.model = run.model.segment(sc, run.law.kernel_id, run.law.params())
        self.coupled = run.model.coupled_terms()
        self.events = event_scan(_event_directions(mode), run.model.n_state)

    def rhs(self, t, y):
        return rhs_kernel(t, y, self.model, self.coupled)

    def event_values(self, y):
        return event_kernel(y, self.model, self.coupled)

    def locate(self, step: Step, j, e) -> tuple[float, np.ndarray]:
        """The first instant on the far side of event e inside sample bracket j of the step, and the state
        there: Brent's method on the interpolant, then bisection down to adjacent floats.  Brent stops within
        its tolerance on either side of the root, and a strike located on the near side starts the contact
        outside the stop (by 5e-19 m at t = 2.5e-4 s), where the Jacobian holds no contact force: the first
        steps then meet a stiff contact explicitly."""
        ta, tb = step.ta, step.tb
        k = SAMPLES_PER_STEP
        a, b = ta + (tb - ta) * (j - 1) / k, ta + (tb - ta) * j / k
        g = lambda t: self.event_values(hermite(step, t))[e]
        far = (lambda t: g(t) <= 0.0) if self.events.dirs[e] < 0 else (lambda t: g(t) >= 0.0)
        if far(a):
            return a, hermite(step, a)
        root = brentq(g, a, b, xtol=1e-15, rtol=4 * np.finfo(float).eps)
        near, beyond = (a, root) if far(root) else (root, b)
        while np.nextafter(near, beyond) < beyond:
            middle = 0.5 * (near + beyond)
            near, beyond = (near, middle) if far(middle) else (middle, beyond)
        return beyond, hermite(step, beyond)

    def finish_partial_step(self, step: Step, t_ev, peak):
        run = self.run
        run.k_out = record_outputs(step, t_ev, self.model, self.coupled, run.out, run.k_out)
        if self.mode.kind == CONTACT:
            track_peak(step, t_ev, self.model, self.coupled, peak)


def _integrate_segment(run: "_Run", case: BeamCase, mode: _Mode, sc, t, t_seg, y):
    """Integrate one smooth segment until an event or t_seg: (event name or None, t, y)."""
    seg = _Segment(run, mode, sc)
    peak = np.array([mode.contact["peak"], 0.0]) if mode.contact is not None else np.zeros(2)
    f0 = seg.rhs(t, y)
    h0 = min(_first_step(run.model, y, f0, run.h_next), t_seg - t)
    if case.solver.method == "rosenbrock":
        status, run.k_out, run.h_next, j, e, step = rosenbrock_segment(
            t, y, t_seg, h0, run.control, seg.model, seg.coupled, seg.events, run.out, run.k_out, peak, run.counts)
        if status in (STEP_UNDERFLOW, TOO_MANY_STEPS) and mode.kind == CONTACT:
            raise SimulationError(_contact_failure(run, case, mode, status, step.tb, step.yb))
        if status == STEP_UNDERFLOW:
            raise SimulationError(f"step size underflow at t = {step.tb:.9g} s")
        if status == TOO_MANY_STEPS:
            raise SimulationError(f"more than solver.max_steps = {case.solver.max_steps} steps by t = {step.tb:.9g} s")
        event = status == EVENT
    else:
        solver = _SOLVERS[case.solver.method](seg.rhs, t, y, t_seg, rtol=case.solver.rtol,
                                              atol=case.solver.atol, first_step=h0)
        event = False
        while solver.status == "running" and not event:
            try:
                msg = solver.step()
            except (ArithmeticError, ValueError) as err:   # SciPy's steppers on a force that overflows
                msg, solver.status = f"{type(err).__name__}: {err}", "failed"
            if solver.status != "failed" and not (solver.t > solver.t_old and np.isfinite(solver.y).all()):
                msg, solver.status = "a step of no length or to a state that is not finite", "failed"   # LSODA's
            if solver.status == "failed" and mode.kind == CONTACT:
                raise SimulationError(_contact_failure(run, case, mode, STEP_UNDERFLOW, solver.t, solver.y, msg))
            if solver.status == "failed":
                raise SimulationError(f"integrator failed at t = {solver.t:.9g} s: {msg}")
            f1 = seg.rhs(solver.t, solver.y)
            step = Step(solver.t_old, y, f0, solver.t, solver.y.copy(), f1)
            j, e, run.k_out = process_step(step, seg.model, seg.coupled, seg.events, run.out, run.k_out, peak)
            run.counts[0] += 1
            event = j >= 0
            y, f0 = step.yb, f1
        run.counts[2] += solver.nfev
        run.counts[3] += solver.njev
        run.h_next = solver.h_abs if hasattr(solver, "h_abs") else run.h_next
    if mode.contact is not None:
        mode.contact["peak"] = max(mode.contact["peak"], peak[0])
    if not event:
        return None, step.tb, step.yb.copy()
    t_ev, y_ev = seg.locate(step, j, e)
    seg.finish_partial_step(step, t_ev, peak)
    if mode.contact is not None:
        mode.contact["peak"] = max(mode.contact["peak"], peak[0])
    return _event_name(mode, e), t_ev, y_ev


@dataclass(frozen=True)
class _ContactTerm:
    """The term of a compliant law's force that sets the pace of a contact phase at one state
    (:func:`_pacing_term`), for the message of a run that cannot follow it.

    name : "spring" or "dashpot".
    keys : its ``[contact]`` keys, each with the change that softens it (the section's ``spring`` or ``dashpot``).
    time_s : its time scale.      delta_m : the penetration δ it was taken at.
    damping_N_s_m : the dashpot's damping ∂F/∂δ̇ there.
    holds : the dashpot holds the stop point and would let it go only at ``release_m_s``, below the
        round-off ``round_off_m_s`` of the gap rate.
    """

    name: str
    keys: dict[str, str]
    time_s: float
    delta_m: float
    damping_N_s_m: float
    holds: bool
    release_m_s: float
    round_off_m_s: float


def _pacing_term(run: _Run, case: BeamCase, mode: _Mode, t: float, y: np.ndarray) -> _ContactTerm:
    """The term of the contact law's force with the shorter time scale at (t, y) in a compliant contact phase.

    Each term's time scale on the stop point's effective mass m = 1/(J M⁻¹ Jᵀ), at the penetration δ of the
    state or, at first touch, the one a least step (:func:`._step_control.least_step`) reaches, is
    √(m/|∂F/∂δ|) of its stiffness, and for the dashpot also m/|∂F/∂δ̇| of its damping.  A dashpot holds the
    stop point when |δ̇| lies within the error the step control admits in ġ = J·v; if it would let it go
    only at a separation speed F(δ, 0)/(∂F/∂δ̇) below the round-off of ġ ((n + 1) ε Σ|Jᵢvᵢ| for its n + 1
    terms and the half unit of each vᵢ: Higham, *Accuracy and Stability of Numerical Algorithms*, 2nd ed.,
    §4.2), the end of the contact is left to round-off: the release and re-engage events fire on noise,
    and the restarts after them ask for steps shorter than the time resolves.
    """
    model, law, contact, solver = run.model, run.law, case.contact, case.solver
    n, p, v0 = model.n, law.params(), mode.v0
    J, v = model.jacobian_row(), y[n + 1 : 2 * n + 2]
    mass = 1.0 / (J @ np.linalg.solve(model.mass_matrix(y), J))
    rate = float(-model.gap_rate(y))
    delta = max(float(-model.gap(y)), abs(rate) * least_step(run.control, t))
    spring = force_kernel(law.kernel_id, delta, 0.0, v0, p)
    stiffness, damping = _law_slopes(law.kernel_id, delta, rate, v0, p, force_kernel(law.kernel_id, delta, rate, v0, p))
    spring_stiffness = _law_slopes(law.kernel_id, delta, 0.0, v0, p, spring)[0]
    with np.errstate(divide="ignore"):
        spring_time = np.sqrt(mass / abs(spring_stiffness))
        dashpot_time = min(np.sqrt(mass / abs(stiffness - spring_stiffness)), mass / abs(damping))
        release = spring / np.float64(damping)
    round_off = (n + 1) * np.finfo(float).eps * np.abs(J * v).sum()
    if spring_time <= dashpot_time:
        return _ContactTerm("spring", contact.spring, spring_time, delta, damping, False, release, round_off)
    holds = abs(rate) <= np.abs(J) @ (solver.atol + solver.rtol * np.abs(v)) and release < round_off
    return _ContactTerm("dashpot", contact.dashpot, dashpot_time, delta, damping, holds, release, round_off)


def _held_message(case: BeamCase, term: _ContactTerm, t: float) -> str:
    """The message of a dashpot that holds the stop point and lets it go only below the round-off of the gap
    rate (:func:`_pacing_term`), named by the key that removes the dashpot, which alone sets that speed
    (√δ/(¾c) of ``hertz``, v₀/D of the power laws)."""
    contact, key = case.contact, next(iter(term.keys))
    return (f"contact.{key} = {getattr(contact, key):g}: the contact phase cannot go on at t = {t:.9g} s: its dashpot "
            f"({term.damping_N_s_m:.2g} N·s/m at a penetration of {term.delta_m:.2g} m) holds the stop point and would "
            f"let it go only at a separation speed of {term.release_m_s:.2g} m/s, below the round-off of the gap rate "
            f"({term.round_off_m_s:.2g} m/s), so the end of the contact is left to round-off; {term.keys[key]} it")


def _check_release(run: _Run, case: BeamCase, mode: _Mode, t: float, y: np.ndarray) -> None:
    """Stop the run at a release or re-engagement of a compliant contact whose dashpot holds the stop point
    and would let it go only below the round-off of the gap rate (:func:`_pacing_term`): the event fired on
    round-off, as would each after it, and the restarts on them ask for steps shorter than the time resolves."""
    term = _pacing_term(run, case, mode, t, y)
    if term.holds:
        raise SimulationError(_held_message(case, term, t))


def _contact_failure(run: _Run, case: BeamCase, mode: _Mode, status: int, t: float, y: np.ndarray,
                     scipy_failure: str | None = None) -> str:
    """The message of a compliant contact phase that the steps could not follow (``STEP_UNDERFLOW``; with
    ``scipy_failure``, what a SciPy method said when it failed there) or that spent the step budget
    (``TOO_MANY_STEPS``) at (t, y): the ``[contact]`` keys of the term of the force that sets its pace
    (:func:`_pacing_term`), and what it does."""
    contact, solver = case.contact, case.solver
    term = _pacing_term(run, case, mode, t, y)
    keys = ", ".join(f"contact.{key} = {getattr(contact, key):g}" for key in term.keys)
    softer = " or ".join(f"{way} contact.{key}" for key, way in term.keys.items())
    pace = (f"{term.name} moves the stop point on a time scale of {term.time_s:.2g} s at a penetration of "
            f"{term.delta_m:.2g} m")
    if status == TOO_MANY_STEPS:
        return (f"more than solver.max_steps = {solver.max_steps} steps by t = {t:.9g} s, in a contact phase whose "
                f"{pace} ({keys}); raise solver.max_steps, or {softer}")
    if term.holds:
        return _held_message(case, term, t)
    if scipy_failure is not None:
        return (f"{keys}: the contact phase cannot go on at t = {t:.9g} s: its {pace}, and SciPy's "
                f"solver.method = \"{solver.method}\" failed on it ({scipy_failure}); {softer}")
    return (f"{keys}: the contact phase cannot go on at t = {t:.9g} s: its {pace}, and the steps that follow it to "
            f"solver.rtol = {solver.rtol:g} fell below the solver's least step there "
            f"({least_step(run.control, t):.2g} s); {softer}")


def _impulse(model: BeamModel, y: np.ndarray) -> float:
    return float(y[2 * model.n + 6])


def _open_contact(model, t, y, v_app):
    return {"t_start": t, "v_approach": v_app, "peak": 0.0, "impulse_at_start": _impulse(model, y)}


def _close_contact(model: BeamModel, contact: dict, t: float, y: np.ndarray) -> Impact:
    v_sep = float(model.gap_rate(y))
    v_app = contact["v_approach"]
    return Impact(t_start=contact["t_start"], t_end=t, v_approach=v_app, v_separation=v_sep,
                  restitution=v_sep / v_app if v_app > 0 else float("nan"), peak_force=contact["peak"],
                  impulse=_impulse(model, y) - contact["impulse_at_start"], kind="compliant")


def _impulsive_impact(run: _Run, case: BeamCase, mode: _Mode, sc, t, y) -> np.ndarray:
    """Momentum-balance impact at t; sets the next mode (free or resting)."""
    model, law = run.model, run.law
    c = case.contact
    v_app = float(-model.gap_rate(y))
    plastic = v_app < c.rest_velocity_m_s
    e = 0.0 if plastic else law.e(v_app)
    y_new, P = model.impact(y, e)
    y_new[2 * model.n + 5] += model.energy(y_new) - model.energy(y)  # the impact's (negative) work
    y_new[2 * model.n + 6] += P
    v_sep = float(model.gap_rate(y_new))
    run.impacts.append(Impact(t_start=t, t_end=t, v_approach=v_app, v_separation=v_sep,
                              restitution=v_sep / v_app if v_app > 0 else 0.0, peak_force=None,
                              impulse=P, kind="plastic" if plastic else "impulsive"))
    if len(run.impacts) > c.max_impacts:
        raise SimulationError(
            f"more than contact.max_impacts = {c.max_impacts} impacts by t = {t:.9g} s (endless chattering?); "
            "raise contact.rest_velocity_m_s or contact.max_impacts")
    mode.kind = FREE
    if plastic:
        sc_rest = sc.copy()
        sc_rest[IN_CONTACT] = _MODE_CODES[RESTING]
        if model.contact_force(y_new, sc_rest) > 0.0:
            mode.kind, mode.rest_start = RESTING, t
    return y_new


def simulate(case: BeamCase) -> Result:
    """Integrate a beam case from ``time.start_s`` to ``time.end_s`` (the Python API).

    Returns a :class:`Result` with the output-step time series, every impact and
    the energy balance.
    """
    wall0 = _time.perf_counter()
    model = BeamModel.from_case(case)
    law = contact_law(case)
    t0, t_end, dt = case.time.start_s, case.time.end_s, case.time.output_step_s
    n_out = int(np.floor((t_end - t0) / dt + 1e-9)) + 1
    out = Outputs(t=t0 + dt * np.arange(n_out), y=np.full((n_out, model.n_state), np.nan), force=np.zeros(n_out))
    control = StepControl(rtol=case.solver.rtol, atol=case.solver.atol, max_steps=case.solver.max_steps)
    run = _Run(model, law, control, out)
    corners, torques = torque_schedule(case)

    y = initial_state(case, model)  # clear of the stop: BeamCase checks it (initial_gap)
    t = t0
    mode = _Mode()
    run.out.y[0] = y
    run.k_out = 1
    while t < t_end:
        k = int(np.searchsorted(corners, t, side="right"))
        t_seg = min(t_end, corners[k]) if k < len(corners) else t_end
        sc = model.params(torques[k], v0=mode.v0)
        sc[IN_CONTACT] = mode.code()
        event, t, y = _integrate_segment(run, case, mode, sc, t, t_seg, y)
        run.n_restarts += 1
        if event in ("release", "reengage"):
            _check_release(run, case, mode, t, y)
        if event == "strike":
            v_app = float(-model.gap_rate(y))
            if law.impulsive:
                y = _impulsive_impact(run, case, mode, sc, t, y)
            else:
                mode.kind, mode.force_on, mode.v0 = CONTACT, True, max(v_app, 1e-12)
                mode.contact = _open_contact(model, t, y, v_app)
        elif event in ("leave", "release"):
            if mode.force_on:
                run.impacts.append(_close_contact(model, mode.contact, t, y))
            mode.contact, mode.force_on = None, False
            if event == "leave":
                mode.kind = FREE
        elif event == "reengage":
            mode.force_on = True
            mode.contact = _open_contact(model, t, y, float(-model.gap_rate(y)))
        elif event == "lift_off":
            run.resting.append((mode.rest_start, t))
            mode.kind, mode.rest_start = FREE, None
    if mode.rest_start is not None:
        run.resting.append((mode.rest_start, t))
    if mode.contact is not None:
        run.impacts.append(_close_contact(model, mode.contact, t, y))

    wall = _time.perf_counter() - wall0
    stats = {"method": case.solver.method, "rtol": case.solver.rtol, "atol": case.solver.atol,
             "steps": int(run.counts[0]), "rejected_steps": int(run.counts[1]),
             "rhs_evaluations": int(run.counts[2]), "jacobian_evaluations": int(run.counts[3]),
             "restarts": run.n_restarts}
    return Result(case=case, model=model, t=run.out.t, y=run.out.y, contact_force=run.out.force,
                  impacts=run.impacts, resting=np.array(run.resting, dtype=float).reshape(-1, 2),
                  stats=stats, wall_time_s=wall)
