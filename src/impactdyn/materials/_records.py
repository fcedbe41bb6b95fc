"""The material record: one :class:`Material` per alloy, holding everything the stages read.

The equation of state and strength are fields of the record; the failure and phase data are optional
sub-records (:data:`OPTIONAL_GROUPS`), each with the source of its constants.  A stage that needs a
group the material lacks refuses it through :meth:`Material.require`, naming the material and the
group.  Units: cm, g, µs, Mbar, K (:mod:`impactdyn.units`).  The source keys in brackets ([JC83],
[BA94], …) are those of the library, :mod:`impactdyn.materials._library`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from impactdyn._errors import InputError

#: Crack-growth speed over the longitudinal sound speed, c_g = 0.4 c_L ([BA94]).
CRACK_SPEED_FRACTION = 0.4


def _require_numbers(obj: object, fields: tuple[str, ...], positive: bool) -> None:
    """InputError naming ``Class.field`` for the first of ``fields`` of ``obj`` that is not a finite
    number > 0 (``positive``) or >= 0."""
    for field in fields:
        value = getattr(obj, field)
        if not (isinstance(value, (int, float)) and math.isfinite(value) and (value > 0 if positive else value >= 0)):
            raise InputError(f"{type(obj).__name__}.{field}: must be {'>' if positive else '>='} 0, got {value!r}")


@dataclass(frozen=True)
class JohnsonCook:
    """Johnson–Cook flow stress [JC83]::

        Y = (A + B εₚⁿ) (1 + C ln ε̇*) (1 − T*ᵐ),
        ε̇* = max(ε̇ₚ/ε̇₀, 1),   T* = clip((T − T_room)/(T_melt − T_room), 0, 1)

    A, B in Mbar; ε̇₀ in 1/µs (1 s⁻¹ = 1e-6 µs⁻¹); temperatures in K; ``source`` says where the
    constants come from.
    """

    A: float
    B: float
    n: float
    C: float
    m: float
    t_melt: float
    t_room: float = 294.0
    reference_strain_rate: float = 1.0e-6
    source: str = ""

    def __post_init__(self) -> None:
        _require_numbers(self, ("n", "m", "t_melt", "reference_strain_rate"), positive=True)
        _require_numbers(self, ("A", "B", "C", "t_room"), positive=False)
        if self.t_melt <= self.t_room:
            raise InputError(f"JohnsonCook.t_melt: must exceed t_room ({self.t_room!r}), got {self.t_melt!r}")


@dataclass(frozen=True)
class PhaseChange:
    """Melting and vaporisation at ambient pressure, what melt on release is judged by
    (:mod:`impactdyn.constitutive._phase`): K and cm²/µs² ([ASM], [CRC]).

    solidus, liquidus : the melting range (equal for a pure metal);
    latent_fusion : the latent heat of fusion L_f;
    boiling : the boiling point T_b;
    latent_vaporisation : the latent heat of vaporisation L_v.
    """

    solidus: float
    liquidus: float
    latent_fusion: float
    boiling: float
    latent_vaporisation: float
    source: str = ""

    def __post_init__(self) -> None:
        _require_numbers(self, ("solidus", "liquidus", "latent_fusion", "boiling", "latent_vaporisation"),
                         positive=True)
        if not self.solidus <= self.liquidus < self.boiling:
            raise InputError(f"PhaseChange: needs solidus <= liquidus < boiling, got {self.solidus!r}, "
                             f"{self.liquidus!r}, {self.boiling!r}")


@dataclass(frozen=True)
class JohnsonCookDamage:
    """Johnson–Cook cumulative damage (Johnson & Cook, Eng. Fract. Mech. 21 (1985) 31)::

        D = Σ Δεₚ / ε_f,   ε_f = [D1 + D2 exp(D3 σ*)] [1 + D4 ln ε̇*] [1 + D5 T*]

    σ* = σ_m/σ_eq (mean stress over von Mises stress, positive in tension), ε̇* and T* as
    in :class:`JohnsonCook`; the material fails at D = 1.  Dimensionless constants;
    ``source`` says where they come from.

    ``efmin`` is the floor ε_f,min on the bracket D1 + D2 exp(D3 σ*) where the fit falls towards
    zero beyond the triaxialities of its data (LS-DYNA's EFMIN of *MAT_JOHNSON_COOK), with its
    basis in ``efmin_source``; None where the fit is bounded below by a positive D1 by itself
    (D2 > 0, D3 < 0: the bracket decreases towards D1), so no floor beyond it is needed.
    """

    D1: float
    D2: float
    D3: float
    D4: float
    D5: float
    source: str = ""
    efmin: float | None = None
    efmin_source: str = ""

    def __post_init__(self) -> None:
        for field in ("D1", "D2", "D3", "D4", "D5"):
            value = getattr(self, field)
            if not (isinstance(value, (int, float)) and math.isfinite(value)):
                raise InputError(f"JohnsonCookDamage.{field}: must be a finite number, got {value!r}")
        if self.efmin is not None:
            _require_numbers(self, ("efmin",), positive=True)


@dataclass(frozen=True)
class TulerButcher:
    """Tuler–Butcher cumulative spall damage [TB68]::

        ∫ max(0, σ_t − σ₀)^λ dt ≥ K   fails the material

    σ_t the tensile stress (the wall model uses the mean tension −p), σ₀ (Mbar) the threshold
    below which no damage accumulates, λ the exponent, K (Mbar^λ·µs) the damage at failure.
    Under a constant-rate ramp σ_t = σ̇t the material fails at σ_f = σ₀ + ((λ+1) σ̇ K)^{1/(λ+1)}.
    ``source`` says where the constants come from.
    """

    sigma0: float
    lam: float
    K: float
    source: str = ""

    def __post_init__(self) -> None:
        _require_numbers(self, ("sigma0", "lam", "K"), positive=True)

    def failure_stress(self, stress_rate: float) -> float:
        """σ_f (Mbar) under the ramp σ_t = σ̇t, σ̇ = ``stress_rate`` (Mbar/µs)."""
        return self.sigma0 + ((self.lam + 1.0) * stress_rate * self.K) ** (1.0 / (self.lam + 1.0))


@dataclass(frozen=True)
class WeibullFlaws:
    """The flaws of a brittle-damage model [GK80]: the number of flaws per unit volume that activate at
    a tensile strain ≤ ε is n(ε) = k εᵐ.

    k in cm⁻³, m dimensionless; ``source`` says where they come from.  The shield stage's tensile damage
    grows cracks from these flaws per unit volume (:func:`impactdyn.constitutive.grady_kipp_damage`), so
    the particle's size does not enter it.
    """

    k: float
    m: float
    source: str = ""

    def __post_init__(self) -> None:
        _require_numbers(self, ("k", "m"), positive=True)

    def fracture_time(self, strain_rate: float, crack_speed: float) -> float:
        """The time t_f at which the damage reaches 1 under the ramp ε = ε̇t, µs ([GK80])::

            D(t) = 8π c_g³ k ε̇ᵐ t^{m+3} / ((m+1)(m+2)(m+3))

        ``strain_rate`` ε̇ in µs⁻¹, ``crack_speed`` c_g in cm/µs.
        """
        m = self.m
        return ((m + 1.0) * (m + 2.0) * (m + 3.0) / (8.0 * math.pi * crack_speed ** 3 * self.k * strain_rate ** m)
                ) ** (1.0 / (m + 3.0))


@dataclass(frozen=True)
class FractureToughness:
    """Plane-strain fracture toughness K_Ic, Mbar·cm^½: what sizes the fragments of failed material
    through Grady's energy balance [G82] (:func:`impactdyn.shield.grady_fragments`); ``source`` says
    where it comes from."""

    K_Ic: float
    source: str = ""

    def __post_init__(self) -> None:
        _require_numbers(self, ("K_Ic",), positive=True)


#: The optional groups of a :class:`Material` (its attributes), what each holds and which stage reads
#: it: what :meth:`Material.require` names when a stage needs one the material lacks.
OPTIONAL_GROUPS: dict[str, str] = {
    "johnson_cook": "Johnson-Cook flow stress (shield flow_stress = \"johnson_cook\", the johnson_cook wall)",
    "johnson_cook_damage": "Johnson-Cook ductile damage (the johnson_cook wall, the fragmentation model)",
    "tuler_butcher": "Tuler-Butcher spall (the johnson_cook wall's default spall law)",
    "weibull_flaws": "Weibull flaws (the shield's fragmentation model)",
    "fracture_toughness": "fracture toughness (Grady's fragments of failed material)",
    "phase": "melting and vaporisation (melt on release; without it, never melted)",
}


@dataclass(frozen=True)
class Material:
    """One material of the impact stages (units cm, g, µs, Mbar, K): all the stages read of an alloy.

    Attributes
    ----------
    name : str
    rho0 : float
        Reference density ρ₀, g/cm³.
    c0, s, gamma0 : float
        Hugoniot intercept c₀ (cm/µs), slope s, Grüneisen parameter Γ₀.
    shear_modulus, yield_stress : float
        G and Y₀, Mbar (elastic–perfectly-plastic strength).
    specific_heat : float
        c_v, cm²/(µs²·K); used only for the temperature estimate of the shield stage.
    spall_strength : float | None
        p_spall > 0, Mbar: the particle fails when p < −p_spall. None: no spall.
    failure_strain : float | None
        Plastic-strain limit εₚ,f: the particle fails when εₚ > εₚ,f. None: none.
    tensile_yield : float | None
        The handbook's typical tensile yield stress (0.2 % offset), Mbar: the wall's σ_y in the NASA
        JSC ballistic-limit equations when a case does not give it (``wall.yield_stress_ksi``), a
        quasi-static coupon value unlike the shock-fitted Y₀.  None: the case must give it.
    johnson_cook : JohnsonCook | None
    phase : PhaseChange | None
        Melting range, boiling point and latent heats; None: melt is not judged (never melted).
    source : str
        Where the numbers of the fields above come from (keys of the library's docstring).
    johnson_cook_damage : JohnsonCookDamage | None
        The wall's ductile failure and the shield's ductile damage; None: none (a Johnson–Cook wall
        fails by spall alone).
    tuler_butcher : TulerButcher | None
        The wall's cumulative spall law; None: only the cut-off spall law.
    weibull_flaws : WeibullFlaws | None
        The shield's tensile damage; None: the fragmentation model refuses the material.
    fracture_toughness : FractureToughness | None
        Grady's fragment size; None: no fragments of failed material can be given.
    """

    name: str
    rho0: float
    c0: float
    s: float
    gamma0: float
    shear_modulus: float
    yield_stress: float
    specific_heat: float
    spall_strength: float | None = None
    failure_strain: float | None = None
    johnson_cook: JohnsonCook | None = None
    phase: PhaseChange | None = None
    source: str = ""
    johnson_cook_damage: JohnsonCookDamage | None = None
    tuler_butcher: TulerButcher | None = None
    weibull_flaws: WeibullFlaws | None = None
    fracture_toughness: FractureToughness | None = None
    tensile_yield: float | None = None

    def __post_init__(self) -> None:
        for field in ("rho0", "c0", "s", "gamma0", "shear_modulus", "specific_heat"):
            value = getattr(self, field)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise InputError(f"material {self.name!r}: {field} must be a positive number, got {value!r}")
        if not (math.isfinite(self.yield_stress) and self.yield_stress >= 0):
            raise InputError(f"material {self.name!r}: yield_stress must be ≥ 0, got {self.yield_stress!r}")
        for field in ("spall_strength", "failure_strain", "tensile_yield"):
            value = getattr(self, field)
            if value is not None and not (math.isfinite(value) and value > 0):
                raise InputError(f"material {self.name!r}: {field} must be positive or None, got {value!r}")

    def require(self, group: str, needed_by: str) -> None:
        """An :class:`InputError` naming the material and ``group`` (one of :data:`OPTIONAL_GROUPS`)
        if the material lacks it; ``needed_by`` says what needs it (a case key and value)."""
        if getattr(self, group) is None:
            raise InputError(f"{needed_by} needs the {OPTIONAL_GROUPS[group]} constants of material "
                             f"{self.name!r}, which has none (the group {group!r} of its record)")

    @property
    def young_modulus(self) -> float:
        """E = 9KG/(3K + G), Mbar, with the bulk modulus K = ρ₀c₀²."""
        bulk = self.rho0 * self.c0 ** 2
        return 9.0 * bulk * self.shear_modulus / (3.0 * bulk + self.shear_modulus)

    @property
    def crack_speed(self) -> float:
        """c_g = 0.4 c_L, cm/µs, c_L = √((K + 4G/3)/ρ₀) the longitudinal sound speed: the speed at which a
        crack grows in the damage models ([BA94], after Lawn & Wilshaw, *Fracture of brittle solids*, 1975)."""
        return CRACK_SPEED_FRACTION * math.sqrt((self.rho0 * self.c0 ** 2 + 4.0 * self.shear_modulus / 3.0)
                                                / self.rho0)

    def hugoniot(self, up: float) -> tuple[float, float, float]:
        """Shock state for particle velocity ``up`` (cm/µs) into material at rest.

        Rankine–Hugoniot jump conditions with Us = c₀ + s·up::

            Us = c₀ + s up,   p = ρ₀ Us up,   ρ = ρ₀ Us / (Us − up)

        Returns (Us cm/µs, p Mbar, ρ g/cm³).
        """
        us = self.c0 + self.s * up
        return us, self.rho0 * us * up, self.rho0 * us / (us - up)
