"""A case file's own materials: the ``[materials.NAME]`` tables, validated and registered.

Each table defines one alloy in the literature's units, named in the keys as elsewhere in a case
(``c0_km_s``, ``shear_modulus_GPa``), one sub-table per group of constants, each with the ``source``
its numbers come from::

    [materials.ti6al4v.eos]            # required: Mie–Grüneisen about Us = c0 + s up
    [materials.ti6al4v.strength]       # required: G and Y0
    [materials.ti6al4v.spall]          # optional groups: spall, plastic_failure, johnson_cook,
    ...                                # johnson_cook_damage, tuler_butcher, weibull_flaws,
                                       # fracture_toughness, phase

:data:`MaterialsTable` is the type of a case's ``materials`` key: once its tables are valid, each
becomes a :class:`~impactdyn.materials.Material` and is registered (:func:`register_material`,
replaceable: the case validated last defines its names), so that ``[projectile]``, ``[bumper]`` and
``[wall]`` can name it like a library material.  A group a stage needs and the material lacks is
refused by the case (:meth:`~impactdyn.materials.Material.require`).
"""

from __future__ import annotations

from typing import Annotated

from pydantic import AfterValidator, Field, ValidationError, model_validator

from impactdyn._config import NonNegative, Positive, Section, field_of
from impactdyn._errors import InputError
from impactdyn.materials._records import (
    FractureToughness, JohnsonCook, JohnsonCookDamage, Material, PhaseChange, TulerButcher, WeibullFlaws)
from impactdyn.materials._registry import register_material
from impactdyn.units import (CM2_US2_PER_J_G, MBAR_PER_MPA, MBAR_SQRT_CM_PER_MPA_SQRT_M, PER_US_PER_PER_S,
                             gpa_to_mbar, km_s_to_cm_us)


def _named_source(text: str) -> str:
    if not text.strip():
        raise ValueError("must say where the constants come from (a reference)")
    return text


Source = Annotated[str, AfterValidator(_named_source)]
"""Where a group's constants come from: a reference a reader can find (required, not blank)."""


class EosGroup(Section):
    """The Mie–Grüneisen equation of state about the linear Hugoniot Us = c₀ + s·up, with Γρ = Γ₀ρ₀.

    density_g_cm3 : the density of the uncompressed material at rest (ρ₀), about which the
        pressure is measured.
    c0_km_s : the Hugoniot's intercept c₀ (the bulk sound speed).
    s : the slope of the linear Hugoniot: the shock speed grows by s km/s for each km/s of particle
        speed (Us = c₀ + s·up).
    gamma0 : the Grüneisen parameter Γ₀ at ρ₀: how much pressure the material's heat adds at a
        given density.
    specific_heat_J_gK : the specific heat at constant volume (c_v), which turns the internal
        energy into the temperature that Johnson–Cook softening and melting read.
    source : the published reference these constants come from, one a reader can find.
    """

    density_g_cm3: Positive
    c0_km_s: Positive
    s: Positive
    gamma0: Positive
    specific_heat_J_gK: Positive
    source: Source


class StrengthGroup(Section):
    """Elastic–perfectly-plastic strength.

    shear_modulus_GPa : the shear modulus (G) of the elastic response to a change of shape.
    yield_stress_GPa : the yield stress at zero plastic strain (Y₀); 0: the material flows like a
        fluid.
    tensile_yield_MPa : the handbook's typical tensile yield stress (0.2 % offset), which the NASA JSC
        ballistic-limit equations take as the wall's σ_y when the case leaves ``wall.yield_stress_ksi``
        out (optional).
    source : the published reference these constants come from, one a reader can find.
    """

    shear_modulus_GPa: Positive
    yield_stress_GPa: NonNegative
    tensile_yield_MPa: Positive | None = None
    source: Source


class SpallGroup(Section):
    """Spall: a particle fails when its pressure falls below −p_spall (the cut-off laws).

    strength_GPa : the spall strength (p_spall): a particle fails when its pressure falls below
        −p_spall, a tension this large.
    source : the published reference the spall strength comes from, one a reader can find.
    """

    strength_GPa: Positive
    source: Source


class PlasticFailureGroup(Section):
    """The plastic-strain failure limit (the shield's threshold model, the type-13 wall card).

    strain : the plastic strain at which the material fails (εₚ,f), for example the alloy's
        elongation at break.
    source : the published reference the failure strain comes from, one a reader can find.
    """

    strain: Positive
    source: Source


class JohnsonCookGroup(Section):
    """Johnson–Cook flow stress Y = (A + B εₚⁿ)(1 + C ln ε̇*)(1 − T*ᵐ) (:class:`~impactdyn.materials.JohnsonCook`).

    A_MPa : the yield stress at zero plastic strain, room temperature and the reference strain
        rate (A).
    B_MPa : the strain-hardening modulus (B): the flow stress grows by B εₚⁿ with the plastic
        strain εₚ.
    n : the strain-hardening exponent of the plastic strain (n).
    C : the strain-rate coefficient (C): the flow stress grows by the factor 1 + C ln(ε̇/ε̇₀).
    m : the thermal-softening exponent (m): the flow stress falls by the factor 1 − T*ᵐ.
    melt_temperature_K : the melting temperature (T_melt) at which the flow stress falls to zero
        (T* = 1); above ``room_temperature_K``.
    room_temperature_K : the temperature of the fit's tests (T_room), where there is no thermal
        softening (T* = 0).
    reference_strain_rate_per_s : the strain rate of the fit's quasi-static tests (ε̇₀; often 1 s⁻¹),
        where the rate term vanishes.
    source : the published reference these constants come from, one a reader can find.
    """

    A_MPa: NonNegative
    B_MPa: NonNegative
    n: Positive
    C: NonNegative
    m: Positive
    melt_temperature_K: Positive
    room_temperature_K: Positive = field_of(JohnsonCook, "t_room")
    reference_strain_rate_per_s: Positive
    source: Source

    @model_validator(mode="after")
    def _melts_above_room(self) -> "JohnsonCookGroup":
        if self.melt_temperature_K <= self.room_temperature_K:
            raise ValueError(f"melt_temperature_K = {self.melt_temperature_K} must exceed room_temperature_K = "
                             f"{self.room_temperature_K}")
        return self


class JohnsonCookDamageGroup(Section):
    """Johnson–Cook damage, ε_f = [D1 + D2 exp(D3 σ*)][1 + D4 ln ε̇*][1 + D5 T*]
    (:class:`~impactdyn.materials.JohnsonCookDamage`), in Johnson & Cook's signs (D3 < 0).

    D1 : the constant term of the failure strain's dependence on the stress triaxiality σ* (the
        mean stress over the von Mises stress, positive in tension).
    D2 : the factor of the exponential term D2 exp(D3 σ*) of that dependence.
    D3 : the factor of the triaxiality in that exponential (negative in Johnson & Cook's signs:
        the more tension, the less strain to failure).
    D4 : the strain-rate factor: the failure strain grows by the factor 1 + D4 ln ε̇* with the
        strain rate.
    D5 : the temperature factor: the failure strain grows by the factor 1 + D5 T* with the
        homologous temperature T*.
    failure_strain_floor : the smallest failure strain (ε_f,min) the fit may give, where it falls to
        zero beyond its data; none: no floor.
    failure_strain_floor_source : the reference or reasoning behind the floor (required with a floor).
    source : the published reference these constants come from, one a reader can find.
    """

    D1: float
    D2: float
    D3: float
    D4: float
    D5: float
    failure_strain_floor: Positive | None = None
    failure_strain_floor_source: str = ""
    source: Source

    @model_validator(mode="after")
    def _floor_has_a_source(self) -> "JohnsonCookDamageGroup":
        if self.failure_strain_floor is not None and not self.failure_strain_floor_source.strip():
            raise ValueError("failure_strain_floor needs failure_strain_floor_source (where it comes from)")
        return self


class TulerButcherGroup(Section):
    """Tuler–Butcher spall ∫ max(0, σ − σ₀)^λ dt ≥ K (:class:`~impactdyn.materials.TulerButcher`).

    sigma0_GPa : the threshold tension (σ₀) below which no spall damage accumulates.
    exponent : the exponent (λ) of the tension over the threshold in the damage integral.
    K_Mbar_lambda_us : the damage integral at which the material spalls (K), Mbar^λ·µs (the unit
        depends on λ: given in the package's units).
    source : the published reference these constants come from, one a reader can find.
    """

    sigma0_GPa: Positive
    exponent: Positive
    K_Mbar_lambda_us: Positive
    source: Source


class WeibullFlawsGroup(Section):
    """Weibull flaws n(ε) = k εᵐ per unit volume (:class:`~impactdyn.materials.WeibullFlaws`).

    k_per_cm3 : the flaw density factor (k): the number of flaws per cm³ that activate by a
        tensile strain ε is k εᵐ.
    m : the Weibull modulus (m), how steeply the number of active flaws grows with the strain.
    source : the published reference these constants come from, one a reader can find.
    """

    k_per_cm3: Positive
    m: Positive
    source: Source


class FractureToughnessGroup(Section):
    """The plane-strain fracture toughness K_Ic (Grady's fragment size).

    K_Ic_MPa_sqrt_m : the plane-strain fracture toughness (K_Ic), which sets the size of the
        fragments of failed material through Grady's energy balance.
    source : the published reference the toughness comes from, one a reader can find.
    """

    K_Ic_MPa_sqrt_m: Positive
    source: Source


class PhaseGroup(Section):
    """Melting and vaporisation at ambient pressure (:class:`~impactdyn.materials.PhaseChange`).

    solidus_K, liquidus_K : the temperatures where melting starts and ends (equal for a pure
        metal).
    latent_fusion_J_g : the latent heat of fusion (L_f): the energy per gram that melting takes on
        top of the heating, which a particle released from its shock must have to be wholly melted.
    boiling_K : the boiling point (T_b) at ambient pressure, above the liquidus.
    latent_vaporisation_J_g : the latent heat of vaporisation (L_v): the energy per gram that boiling
        takes, which a released particle must have beyond the boiling point to be wholly vapour.
    source : the published reference these constants come from, one a reader can find.
    """

    solidus_K: Positive
    liquidus_K: Positive
    latent_fusion_J_g: Positive
    boiling_K: Positive
    latent_vaporisation_J_g: Positive
    source: Source

    @model_validator(mode="after")
    def _ordered(self) -> "PhaseGroup":
        if not self.solidus_K <= self.liquidus_K < self.boiling_K:
            raise ValueError(f"needs solidus_K <= liquidus_K < boiling_K, got {self.solidus_K}, {self.liquidus_K}, "
                             f"{self.boiling_K}")
        return self


class MaterialTable(Section):
    """One alloy of a case file, ``[materials.NAME]``: the groups of constants, each with its source.

    eos : the equation of state (required).
    strength : the strength (required).
    spall, plastic_failure : the failure limits of the threshold model; none: that failure is off.
    johnson_cook, johnson_cook_damage, tuler_butcher, weibull_flaws, fracture_toughness, phase :
        the optional groups a stage may need; a case whose stages need one the material lacks is
        refused, naming the material and the group.
    """

    eos: EosGroup
    strength: StrengthGroup
    spall: SpallGroup | None = None
    plastic_failure: PlasticFailureGroup | None = None
    johnson_cook: JohnsonCookGroup | None = None
    johnson_cook_damage: JohnsonCookDamageGroup | None = None
    tuler_butcher: TulerButcherGroup | None = None
    weibull_flaws: WeibullFlawsGroup | None = None
    fracture_toughness: FractureToughnessGroup | None = None
    phase: PhaseGroup | None = None

    def material(self, name: str) -> Material:
        """The :class:`~impactdyn.materials.Material` of this table, in the package's units."""
        e, st, sp, pf = self.eos, self.strength, self.spall, self.plastic_failure
        jc, d, tb, w, k, ph = (self.johnson_cook, self.johnson_cook_damage, self.tuler_butcher, self.weibull_flaws,
                               self.fracture_toughness, self.phase)
        sources = [f"EOS: {e.source}", f"strength: {st.source}"] + (
            [f"spall: {sp.source}"] if sp else []) + ([f"plastic failure: {pf.source}"] if pf else [])
        return Material(
            name=name, rho0=e.density_g_cm3, c0=km_s_to_cm_us(e.c0_km_s), s=e.s, gamma0=e.gamma0,
            shear_modulus=gpa_to_mbar(st.shear_modulus_GPa), yield_stress=gpa_to_mbar(st.yield_stress_GPa),
            specific_heat=e.specific_heat_J_gK * CM2_US2_PER_J_G,
            spall_strength=gpa_to_mbar(sp.strength_GPa) if sp else None,
            failure_strain=pf.strain if pf else None,
            tensile_yield=None if st.tensile_yield_MPa is None else st.tensile_yield_MPa * MBAR_PER_MPA,
            johnson_cook=None if jc is None else JohnsonCook(
                A=jc.A_MPa * MBAR_PER_MPA, B=jc.B_MPa * MBAR_PER_MPA, n=jc.n, C=jc.C, m=jc.m,
                t_melt=jc.melt_temperature_K, t_room=jc.room_temperature_K,
                reference_strain_rate=jc.reference_strain_rate_per_s * PER_US_PER_PER_S, source=jc.source),
            phase=None if ph is None else PhaseChange(
                solidus=ph.solidus_K, liquidus=ph.liquidus_K, latent_fusion=ph.latent_fusion_J_g * CM2_US2_PER_J_G,
                boiling=ph.boiling_K, latent_vaporisation=ph.latent_vaporisation_J_g * CM2_US2_PER_J_G,
                source=ph.source),
            source="; ".join(sources),
            johnson_cook_damage=None if d is None else JohnsonCookDamage(
                D1=d.D1, D2=d.D2, D3=d.D3, D4=d.D4, D5=d.D5, source=d.source, efmin=d.failure_strain_floor,
                efmin_source=d.failure_strain_floor_source),
            tuler_butcher=None if tb is None else TulerButcher(
                sigma0=gpa_to_mbar(tb.sigma0_GPa), lam=tb.exponent, K=tb.K_Mbar_lambda_us, source=tb.source),
            weibull_flaws=None if w is None else WeibullFlaws(k=w.k_per_cm3, m=w.m, source=w.source),
            fracture_toughness=None if k is None else FractureToughness(
                K_Ic=k.K_Ic_MPa_sqrt_m * MBAR_SQRT_CM_PER_MPA_SQRT_M, source=k.source),
        )


def _registered(tables: dict[str, MaterialTable] | None) -> dict[str, MaterialTable] | None:
    """Register each table's material (a name clash with the library is an error naming it)."""
    for name, table in (tables or {}).items():
        try:
            register_material(table.material(name), replaceable=True)
        except InputError as err:
            raise ValueError(f"{name}: {err}") from None
    return tables


def without_material_echoes(err: ValidationError) -> ValidationError:
    """``err`` without the errors "unknown material NAME" of the keys that name a material whose own table
    failed: the table's error says what is wrong, the unknown name would only echo it."""
    errors = err.errors()
    failed = {e["loc"][1] for e in errors if len(e["loc"]) > 1 and e["loc"][0] == "materials"}
    kept = [e for e in errors if not (e["loc"][-1:] == ("material",) and isinstance(e["input"], str)
                                      and e["input"] in failed)]
    return err if len(kept) == len(errors) else ValidationError.from_exception_data(err.title, kept)


MaterialsTable = Annotated[dict[str, MaterialTable], Field(min_length=1), AfterValidator(_registered)]
"""A case's ``[materials.NAME]`` tables, registered once valid (module docstring)."""
