"""Beam case files: the TOML schema, defaults and cross-field checks (SI units).

A case is problem setup only; the solver lives in ``_simulate``. Keys carry their
unit in the name. See ``examples/beam/*.toml`` for the two recorded sample runs.
"""

from __future__ import annotations

from typing import Annotated, ClassVar, Literal, Union

import numpy as np
from pydantic import Field, model_validator

from impactdyn._config import NonNegative, Positive, Section
from impactdyn._limits import check_fits
from impactdyn.beam._modes import eigenvalues, shapes


MAX_LENGTH_M = 1e61
"""Beyond the longest beam the model can take: it divides by L⁵ (the coupled model's EI/L⁵), which
is a floating-point number only below 1.6e61 m."""


class BeamSection(Section):
    """The uniform beam, clamped to the hub at its root, and the hub.

    mass_per_length_kg_m : the beam's mass per length ρ.
    EI_N_m2 : the beam's flexural rigidity EI (Young's modulus times the section's second moment
        of area); with ρ and L it sets the modal stiffnesses Kᵢ = EI βᵢ⁴/L³.
    length_m : the beam's length L, from the hub's surface to the tip.
    hub_radius_m : the hub's radius A: the beam's root lies at A from the axis (0: the beam
        starts at the axis, as in the report's sample runs).
    """

    mass_per_length_kg_m: Positive
    EI_N_m2: Positive
    length_m: Annotated[float, Field(gt=0, le=MAX_LENGTH_M)]
    hub_radius_m: NonNegative = 0.0
    inertia_ratio: NonNegative = 0.0
    """Hub inertia over the beam's inertia about the hub axis (IR)."""
    strain_radius_m: Positive = 0.001
    """Distance R₁ from the neutral axis at which strain R₁·w'' is reported."""


class TorqueSection(Section):
    """Torque pulse τ₀ for t ≤ T, 0 until (1+f)T, −τ₀ until (2+f)T, 0 after.

    amplitude_N_m : τ₀, the torque on the hub during the first pulse (its sign the direction:
        positive increases θ); 0: no drive.
    pulse_duration_s : T, the length of each of the two pulses.
    zero_fraction : f, the pause between the pulses in units of T.
    """

    amplitude_N_m: float = 0.0
    pulse_duration_s: NonNegative = 0.0
    zero_fraction: NonNegative = 0.0


class DampingSection(Section):
    """Damping of the joint and of the beam's modes (none by default).

    joint_N_m_s : the viscous damping c of the hub's joint: a torque −c θ̇.
    modal_ratio : the damping ratio ζ of every mode: a modal force −2ζ √(Kᵢ ρL) q̇ᵢ.
    """

    joint_N_m_s: NonNegative = 0.0
    modal_ratio: NonNegative = 0.0


class ModelSection(Section):
    """The discretisation of the beam and the field it moves in.

    n_modes : the clamped–free modes kept in the deflection w = Σ φᵢ qᵢ (0: a rigid beam; up to
        50; the listings' modal integrals were for 7, the report's sample runs take 3).
    gravity_m_s2 : the acceleration of gravity, which acts in the plane of the motion (the
        moment ρLg(A + L/2) cos θ on the hub, θ = 0 horizontal); 0: a beam turning in a
        horizontal plane.
    """

    n_modes: Annotated[int, Field(ge=0, le=50)] = 3
    gravity_m_s2: NonNegative = 9.81
    coupled: bool = False
    """The large-deflection model: the consistent Lagrangian with the foreshortening, complete to
    fourth order in the elastic motion, instead of the 1988 linearised one (see ``_model``)."""


class LegacySection(Section):
    """Behaviour of the 1988 listings where it departs from the model (docs/theory/beam.md, the listing's errata).

    Every flag is off by default (the model); each switches one erratum of the 1988 listings
    back on, to reproduce their numbers or to measure what the erratum changes.

    diagonal_centrifugal : the listings keep only the diagonals of the modal integrals k and h in
        the centrifugal stiffening term, dropping the coupling of the modes by the rotation;
        off: the full matrices.
    modal_damping_sqrt_2km : the listings damp mode i with ζ √(2 Kᵢ ρL) q̇ᵢ; off: the viscous
        damping ratio's 2ζ √(Kᵢ ρL).
    moment_arms_ignore_hub : the listings' gravity and contact moments on the hub take their arms
        from the beam's root, ignoring the hub's radius A (L/2 and x_p); off: A + L/2 and A + x_p.
        Nothing changes with A = 0.
    impact_inertia_drops_AL : the momentum balance of IMPACTC's impacts uses an M₀₀ without the
        A·L term, ρL(A² + L²/3)(1 + IR); off: the equations' M₀₀.  Nothing changes with A = 0.
    sr7_typo : the listing's coupling term of mode 7 takes the integral a₇ (.004796) where b₇
        (.097942) belongs; off: b₇.  Only with 7 modes or more and A > 0.
    """

    diagonal_centrifugal: bool = False
    modal_damping_sqrt_2km: bool = False
    moment_arms_ignore_hub: bool = False
    impact_inertia_drops_AL: bool = False
    sr7_typo: bool = False


class StopSection(Section):
    """The rigid stop the beam strikes."""

    x_m: Positive
    """Distance of the stop point from the beam root."""
    y_m: float = 0.0
    """Offset of the stop surface from the line θ = 0 (the gap at rest)."""


class MomentumContact(Section):
    """IMPACTC's impulsive contact: an instantaneous momentum balance with a coefficient of restitution.

    model : "momentum", which selects this contact law.
    restitution_law : "listing" (default): the listing's velocity-dependent coefficient
        e(v) = 2.578v² − 1.7428v + 1 for an approach speed v < 0.2 m/s, else 0.5014 v^(−1/4);
        "constant": ``restitution`` at every speed.
    restitution : the coefficient of restitution e of the "constant" law (0: plastic, 1: elastic).
    max_impacts : the most impacts a run may have; more stop it with an error (endless chattering).
    """

    model: Literal["momentum"]
    restitution_law: Literal["listing", "constant"] = "listing"
    restitution: Annotated[float, Field(ge=0, le=1)] = 0.5
    rest_velocity_m_s: Positive = 5e-3
    """Approach speeds below this end a chattering sequence in resting contact."""
    max_impacts: Annotated[int, Field(ge=1)] = 100000


class HertzContact(Section):
    """IMPACTB's compliant contact: F = k δ^(3/2) + ¾ c k δ δ̇, F ≥ 0, at a penetration δ = −g.

    model : "hertz", which selects this contact law.
    stiffness_N_m1_5 : the Hertzian stiffness (k): the contact force is k δ^(3/2) at a
        penetration δ into the stop.
    damping_s_m : the damping c of the dashpot term ¾ c k δ δ̇; 0: elastic contact.
    """

    model: Literal["hertz"]
    stiffness_N_m1_5: Positive
    damping_s_m: NonNegative = 0.0
    spring: ClassVar[dict[str, str]] = {"stiffness_N_m1_5": "lower"}
    """The keys that set the spring k δ^(3/2), each with the change that softens it (a run that cannot
    follow the spring names them); ``dashpot`` the same for ¾ c k δ δ̇, the key that removes it first."""
    dashpot: ClassVar[dict[str, str]] = {"damping_s_m": "lower", "stiffness_N_m1_5": "lower"}


class DissipativePowerContact(Section):
    """Compliant contact F = k δⁿ (1 + D δ̇), D from the restitution e and the approach speed v₀ at
    first touch: 3(1 − e)/(2v₀) (Hunt–Crossley) or 3(1 − e²)/(4v₀) (Lankarani–Nikravesh).

    model : "hunt_crossley" or "lankarani_nikravesh", which select this contact law and its damping.
    stiffness_N_m_n : the contact stiffness (k): the elastic contact force is k δⁿ at a
        penetration δ into the stop.
    exponent : the exponent n of the penetration (1.5: Hertz).
    restitution : the coefficient of restitution e the damping is tuned to.
    """

    model: Literal["hunt_crossley", "lankarani_nikravesh"]
    stiffness_N_m_n: Positive
    exponent: Positive = 1.5
    restitution: Annotated[float, Field(gt=0, le=1)] = 0.8
    spring: ClassVar[dict[str, str]] = {"stiffness_N_m_n": "lower", "exponent": "raise"}
    """The keys that set the spring k δⁿ, each with the change that softens it at penetrations below 1 m;
    ``dashpot`` the same for k δⁿ D δ̇, the key that removes it first (as :class:`HertzContact`'s)."""
    dashpot: ClassVar[dict[str, str]] = {"restitution": "raise", "stiffness_N_m_n": "lower", "exponent": "raise"}


ContactSection = Annotated[
    Union[MomentumContact, HertzContact, DissipativePowerContact],
    Field(discriminator="model", description="the law of the contact between the beam and the stop; it "
          "decides which other keys the table takes (each of them names its law)."),
]


class InitialSection(Section):
    """The state at ``time.start_s`` (at rest, θ = 0, by default); the beam must start clear of the stop.

    theta_rad : the hub's angle at the start (θ), from the line θ = 0 (horizontal under gravity;
        the stop's offset ``stop.y_m`` is measured from it), positive where a positive torque
        turns the hub.
    theta_dot_rad_s : the hub's angular velocity at the start (θ̇).
    q_m : the modal amplitudes q₁ … qₙ (one per mode, m: the deflection w = Σ φᵢ qᵢ, with
        φᵢ(1) = ±2 at the tip); none: zero.
    q_dot_m_s : the rates of change q̇₁ … q̇ₙ of the modal amplitudes (one per mode); none: zero.
    tip_velocity_m_s : IMPACTB-style: this tip velocity added into mode 1 (q̇₁ += v/φ₁(1)).
    """

    theta_rad: float = 0.0
    theta_dot_rad_s: float = 0.0
    q_m: list[float] | None = None
    q_dot_m_s: list[float] | None = None
    tip_deflection_m: float = 0.0
    """IMPACTB-style: put this tip deflection into mode 1 (q₁ = w/φ₁(1))."""
    tip_velocity_m_s: float = 0.0


class TimeSection(Section):
    """The time span of the run and its output sampling.

    start_s : the time of the initial state (the torque pulse starts at t = 0).
    end_s : the end of the run; after ``start_s``.
    output_step_s : the interval of the output samples (``timeseries.csv``, the plots); the
        solver chooses its own steps, and impacts are located to about 1e-14 s whatever the
        sampling.
    """

    start_s: float = 0.0
    end_s: float
    output_step_s: Positive


class OutputSection(Section):
    """What the run reports besides the hub and the stop.

    response_point_m : the distance x from the beam's root at which the deflection w(x) and the
        strain R₁ w''(x) are reported (the listing's response point); at most the beam's length.
    plots : write the PNG figures into the run folder's ``plots/``.
    """

    response_point_m: NonNegative
    plots: bool = True


class SolverSection(Section):
    """``rosenbrock``: the compiled Rosenbrock 4(3) of ``_integrator`` (default);
    ``Radau``, ``BDF``, ``LSODA``: SciPy's, stepped from Python (for cross-checks).

    method : "rosenbrock" (default), "Radau", "BDF" or "LSODA".
    rtol, atol : the relative and absolute tolerances of the step control (atol in the states'
        SI units: rad, m, rad/s, m/s).
    max_steps : the most accepted steps of the "rosenbrock" method over the run; more stop it with an error
        (SciPy's methods have no such budget).
    """

    method: Literal["rosenbrock", "Radau", "BDF", "LSODA"] = "rosenbrock"
    rtol: Annotated[float, Field(gt=0, lt=1)] = 1e-8
    atol: Positive = 1e-11
    max_steps: Annotated[int, Field(ge=1)] = 20_000_000


class BeamCase(Section):
    """A complete rotating-beam case (every table of the TOML file)."""

    beam: BeamSection
    torque: TorqueSection = TorqueSection()
    damping: DampingSection = DampingSection()
    model: ModelSection = ModelSection()
    legacy: LegacySection = LegacySection()
    stop: StopSection
    contact: ContactSection
    initial: InitialSection = InitialSection()
    time: TimeSection
    output: OutputSection
    solver: SolverSection = SolverSection()

    @model_validator(mode="after")
    def _cross_checks(self) -> "BeamCase":
        L = self.beam.length_m
        if self.stop.x_m > L:
            raise ValueError(f"stop.x_m = {self.stop.x_m} lies beyond the beam tip (beam.length_m = {L})")
        if self.output.response_point_m > L:
            raise ValueError(
                f"output.response_point_m = {self.output.response_point_m} lies beyond the beam tip "
                f"(beam.length_m = {L})"
            )
        if self.time.end_s <= self.time.start_s:
            raise ValueError("time.end_s must be greater than time.start_s")
        n = self.model.n_modes
        t = self.time  # the output grid: time, the 2n + 7 states and the contact force at each step
        check_fits(f"time.end_s - time.start_s = {t.end_s - t.start_s:g} s at time.output_step_s = "
                   f"{t.output_step_s:g} s", (t.end_s - t.start_s) / t.output_step_s + 1, 8 * (2 * n + 9),
                   "output steps")
        for key in ("q_m", "q_dot_m_s"):
            val = getattr(self.initial, key)
            if val is not None and len(val) != n:
                raise ValueError(f"initial.{key} has {len(val)} entries, model.n_modes is {n}")
        if n == 0 and (self.initial.tip_deflection_m or self.initial.tip_velocity_m_s):
            raise ValueError("initial.tip_* needs at least one mode (model.n_modes = 0)")
        gap = initial_gap(self)
        if gap < 0:
            raise ValueError(
                f"the beam starts inside the stop: initial.theta_rad, initial.q_m and initial.tip_deflection_m put "
                f"the point stop.x_m = {self.stop.x_m} (beam.hub_radius_m = {self.beam.hub_radius_m}, "
                f"beam.length_m = {L}) {-gap:.6g} m past the stop surface stop.y_m = {self.stop.y_m}; "
                "start the beam clear of it")
        return self


def initial_gap(case: BeamCase) -> float:
    """The gap (A + x_p) θ + Σ qᵢ φᵢ(x_p/L) − y_p between the beam and the stop at ``time.start_s`` (m), with
    IMPACTB's tip deflection put into mode 1; the model's ``gap`` of its initial state, before the model is built."""
    n, ic, x_p = case.model.n_modes, case.initial, case.stop.x_m
    beta = eigenvalues(n)
    q = np.zeros(n) if ic.q_m is None else np.array(ic.q_m, dtype=float)
    if n:
        q[0] += ic.tip_deflection_m / float(shapes(beta[:1], np.float64(1.0))[0])
    phi_p = shapes(beta, np.float64(x_p / case.beam.length_m)).reshape(n)
    return (case.beam.hub_radius_m + x_p) * ic.theta_rad + q @ phi_p - case.stop.y_m
