"""Beam case files: the TOML schema, defaults and cross-field checks (SI units).

A case is problem setup only; the solver lives in ``_simulate``. Keys carry their
unit in the name. See ``examples/beam/*.toml`` for the two recorded sample runs.
"""

from __future__ import annotations

from typing import Annotated, Literal, Union

import numpy as np
from pydantic import Field, model_validator

from impactdyn._config import NonNegative, Positive, Section
from impactdyn._limits import check_fits
from impactdyn.beam._modes import eigenvalues, shapes


MAX_LENGTH_M = 1e61
"""Beyond the longest beam the model can take: it divides by L⁵ (the coupled model's EI/L⁵), which
is a floating-point number only below 1.6e61 m."""


class BeamSection(Section):
    mass_per_length_kg_m: Positive
    EI_N_m2: Positive
    length_m: Annotated[float, Field(gt=0, le=MAX_LENGTH_M)]
    hub_radius_m: NonNegative = 0.0
    inertia_ratio: NonNegative = 0.0
    """Hub inertia over the beam's inertia about the hub axis (IR)."""
    strain_radius_m: Positive = 0.001
    """Distance R₁ from the neutral axis at which strain R₁·w'' is reported."""


class TorqueSection(Section):
    """Torque pulse τ₀ for t ≤ T, 0 until (1+f)T, −τ₀ until (2+f)T, 0 after."""

    amplitude_N_m: float = 0.0
    pulse_duration_s: NonNegative = 0.0
    zero_fraction: NonNegative = 0.0


class DampingSection(Section):
    joint_N_m_s: NonNegative = 0.0
    modal_ratio: NonNegative = 0.0


class ModelSection(Section):
    n_modes: Annotated[int, Field(ge=0, le=50)] = 3
    gravity_m_s2: NonNegative = 9.81
    coupled: bool = False
    """The large-deflection model: the consistent Lagrangian with the foreshortening, complete to
    fourth order in the elastic motion, instead of the 1988 linearised one (see ``_model``)."""


class LegacySection(Section):
    """Behaviour of the 1988 listings where it departs from the model (docs/theory/beam.md, the listing's errata)."""

    diagonal_centrifugal: bool = False
    modal_damping_sqrt_2km: bool = False
    moment_arms_ignore_hub: bool = False
    impact_inertia_drops_AL: bool = False
    sr7_typo: bool = False


class StopSection(Section):
    x_m: Positive
    """Distance of the stop point from the beam root."""
    y_m: float = 0.0
    """Offset of the stop surface from the line θ = 0 (the gap at rest)."""


class MomentumContact(Section):
    model: Literal["momentum"]
    restitution_law: Literal["listing", "constant"] = "listing"
    restitution: Annotated[float, Field(ge=0, le=1)] = 0.5
    rest_velocity_m_s: Positive = 5e-3
    """Approach speeds below this end a chattering sequence in resting contact."""
    max_impacts: Annotated[int, Field(ge=1)] = 100000


class HertzContact(Section):
    model: Literal["hertz"]
    stiffness_N_m1_5: Positive
    damping_s_m: NonNegative = 0.0


class DissipativePowerContact(Section):
    model: Literal["hunt_crossley", "lankarani_nikravesh"]
    stiffness_N_m_n: Positive
    exponent: Positive = 1.5
    restitution: Annotated[float, Field(gt=0, le=1)] = 0.8


ContactSection = Annotated[
    Union[MomentumContact, HertzContact, DissipativePowerContact], Field(discriminator="model")
]


class InitialSection(Section):
    theta_rad: float = 0.0
    theta_dot_rad_s: float = 0.0
    q_m: list[float] | None = None
    q_dot_m_s: list[float] | None = None
    tip_deflection_m: float = 0.0
    """IMPACTB-style: put this tip deflection into mode 1 (q₁ = w/φ₁(1))."""
    tip_velocity_m_s: float = 0.0


class TimeSection(Section):
    start_s: float = 0.0
    end_s: float
    output_step_s: Positive


class OutputSection(Section):
    response_point_m: NonNegative
    plots: bool = True


class SolverSection(Section):
    """``rosenbrock``: the compiled Rosenbrock 4(3) of ``_integrator`` (default);
    ``Radau``, ``BDF``, ``LSODA``: SciPy's, stepped from Python (for cross-checks)."""

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
