"""Numerical options of the SPH shield stage: the one home of their defaults and bounds.

The Whipple case's ``[shield]`` table declares the options it exposes with these
defaults and bounds (:func:`impactdyn._config.field_of`).
"""

from __future__ import annotations

from typing import Annotated, Literal, get_args

from pydantic import Field

from impactdyn._config import NonNegative, Section

FlowStress = Literal["perfectly_plastic", "johnson_cook"]
"""Flow-stress models: Y = Y₀, or Johnson–Cook (:func:`impactdyn.constitutive.flow_stress`)."""
FLOW_STRESS_MODELS: tuple[str, ...] = get_args(FlowStress)

FailureModel = Literal["threshold", "fragmentation"]
"""Failure models (:mod:`._equations`): a pressure and plastic-strain threshold, or damage that leaves
fragments (:mod:`._damage`)."""
FAILURE_MODELS: tuple[str, ...] = get_args(FailureModel)

ViscositySwitch = Literal["none", "balsara"]
"""Where the artificial viscosity acts (:func:`._equations.viscosity_switch`): everywhere two particles
approach, or only where the flow converges without shear."""
VISCOSITY_SWITCHES: tuple[str, ...] = get_args(ViscositySwitch)


class SPHOptions(Section):
    """Numerical parameters of the SPH stage (:mod:`._equations`).

    alpha : the linear coefficient of the artificial viscosity (α; Monaghan 1992, eq. 4.1), which
        damps the ringing behind a shock (1.0; 0 turns the linear term off).
    beta : the quadratic coefficient of the artificial viscosity (β), which keeps particles from
        passing through each other in a strong shock (2.0; 0 turns the quadratic term off).
    viscosity_switch : "none" (the viscosity acts on every approaching pair) or "balsara" (scaled by
        Balsara's factor, zero where the flow expands: its heating confined to shocks).
    artificial_stress, artificial_stress_power : ε and n of the artificial stress (ε = 0 disables it).
    h_factor : κ in h = κ (m/ρ)^{1/3} (h over the particle spacing).
    h_max_factor : the largest growth of h under expansion.
    cfl : the Courant factor of the time step (C_cfl): the step is at most
        C_cfl h / (c + 1.2 (α c + β max|μ|)) and C_cfl ρ/|ρ̇| over the particles (0.3; a smaller
        factor takes smaller steps).
    force_cfl : the factor of the acceleration's limit on the time step (C_f): the step is at most
        C_f √(h/|a|) over the particles (0.25).
    flow_stress : "perfectly_plastic" (Y = Y₀) or "johnson_cook".
    failure : apply the materials' failure (``failure_model``); false: no particle fails.
    failure_model : "threshold": a particle fails at once when p < −p_spall or εₚ exceeds the
        alloy's elongation at break (compressive flow fails it as readily as tension);
        "fragmentation": tensile damage from Weibull flaws per unit volume growing cracks at a bounded
        speed (Grady–Kipp) and Johnson–Cook ductile damage that compression does not accumulate
        (:mod:`._damage`).
    neighbour_skin : skin ℓ of the reused neighbour list as a fraction of the largest h
        (:mod:`._neighbours`): the list is searched again only after the particles
        have moved (or h grown) by ℓ/2. It changes the cost, not the interacting
        pairs; 0 searches at every step.

    A bad value raises :class:`~impactdyn._errors.InputError` naming it
    (``SPHOptions: cfl: must be less than or equal to 1``).
    """

    alpha: NonNegative = 1.0
    beta: NonNegative = 2.0
    viscosity_switch: ViscositySwitch = "none"
    artificial_stress: NonNegative = 0.3
    artificial_stress_power: Annotated[int, Field(ge=1, le=8)] = 4
    h_factor: Annotated[float, Field(ge=0.8, le=2.5)] = 1.3
    h_max_factor: Annotated[float, Field(ge=1)] = 2.0
    cfl: Annotated[float, Field(gt=0, le=1)] = 0.3
    force_cfl: Annotated[float, Field(gt=0, le=1)] = 0.25
    flow_stress: FlowStress = "perfectly_plastic"
    failure: bool = True
    failure_model: FailureModel = "threshold"
    neighbour_skin: NonNegative = 0.15
