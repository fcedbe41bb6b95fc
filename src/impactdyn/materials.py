"""Material library of the impact stages, with a source for every number.

Units are the impact stages' (cm, g, µs; :mod:`impactdyn.units`): density g/cm³,
velocity cm/µs, moduli and stresses Mbar, specific heat cm²/(µs²·K). The
literature values are entered in their own units (km/s, GPa, MPa, J/(g·K)) and
converted here through :mod:`impactdyn.units`.

Equation of state: Mie–Grüneisen about a linear shock-velocity–particle-velocity
Hugoniot ``Us = c₀ + s·up`` with ``Γρ = Γ₀ρ₀`` (see :mod:`impactdyn.constitutive`).
Strength: shear modulus G and yield stress Y₀ (elastic–perfectly-plastic), and
optionally Johnson–Cook flow-stress parameters. Failure: spall strength (a
particle fails when its pressure falls below −p_spall) and a plastic-strain
limit.

Sources
-------
[S91]  D. J. Steinberg, *Equation of state and strength properties of selected
       materials*, LLNL UCRL-MA-106439 (1991, rev. 1996): ρ₀, c₀, s, Γ₀, G₀, Y₀
       (the Steinberg–Guinan ``Y0``, the yield stress at zero plastic strain and
       pressure), as tabulated in docs/theory/shield.md for the aluminium alloys.
[JC83] G. R. Johnson, W. H. Cook, *A constitutive model and data for metals
       subjected to large strains, high strain rates and high temperatures*,
       Proc. 7th Int. Symp. Ballistics, The Hague (1983), Table 1 (2024-T351, OFHC copper).
[L01]  D. R. Lesuer, G. J. Kay, M. M. LeBlanc, *Modeling large-strain,
       high-rate deformation in metals*, LLNL UCRL-JC-134118 (2001) (6061-T6).
[JC85] G. R. Johnson, W. H. Cook, *Fracture characteristics of three metals
       subjected to various strains, strain rates, temperatures and pressures*,
       Eng. Fract. Mech. 21 (1985) 31–48 (OFHC copper damage constants).
[TW06] X. Teng, T. Wierzbicki, *Evaluation of six fracture models in high velocity
       perforation*, Eng. Fract. Mech. 73 (2006) 1653–1678 (2024-T351 plates).
[K04]  G. I. Kanel, S. V. Razorenov, V. E. Fortov, *Shock-wave phenomena and the
       properties of condensed matter*, Springer (2004), ch. 7: spall strengths of
       aluminium alloys 1.0–1.7 GPa and of copper 1.2–1.6 GPa at microsecond
       load durations. The values below are representative values inside those
       ranges, not measurements of the particular temper.
[B52]  P. W. Bridgman, *Studies in large plastic flow and fracture*, McGraw-Hill
       (1952): the stress triaxiality at the centre of a notched round bar,
       σ_m/σ_eq = 1/3 + ln(1 + a/2R) (a the neck radius, R the notch radius).
[TB68] F. R. Tuler, B. M. Butcher, *A criterion for the time dependence of dynamic
       fracture*, Int. J. Fract. Mech. 4 (1968) 431–437: the cumulative spall law
       ∫ max(0, σ − σ₀)^λ dt ≥ K (the form only: the paper's constants could not be read here).
[GK80] D. E. Grady, M. E. Kipp, *Continuum modelling of explosive fracture in oil
       shale*, Int. J. Rock Mech. Min. Sci. 17 (1980) 147–157: tensile damage from
       Weibull-distributed flaws n(ε) = k εᵐ.
[BA94] W. Benz, E. Asphaug, *Impact simulations with fracture. I. Method and tests*,
       Icarus 107 (1994) 98–116: the SPH form, crack growth at 0.4 c_L.
[G82]  D. E. Grady, *Local inertial effects in dynamic fragmentation*, J. Appl. Phys. 53 (1982)
       322–325: the fragment size s = (24 Γ / (ρ ε̇²))^{1/3} of a body breaking while it stretches at
       ε̇, Γ the fracture energy (written with Γ = K_Ic²/E as in F. Zhou, J. F. Molinari, K. T. Ramesh,
       Int. J. Solids Struct. 42 (2005) 5181–5207, who compare it with resolved cohesive fragmentation).
[MMPDS] Metallic Materials Properties Development and Standardization, MMPDS-14 (2019): 2024-T351 plate
       K_Ic, average 34.06 MPa√m (minimum 29.66), as quoted by P. Iyengar, J. Mardaras, S. Soe,
       Procedia Struct. Integrity 68 (2025) 446–452, Table 1.
[C07]  W. D. Callister, *Materials science and engineering*, 7th ed. (2007), App. B, Table B.5:
       room-temperature plane-strain K_Ic of 7075-T651, 24 MPa√m.
[ASM]  ASM Handbook vol. 2 (aluminium, copper) and vol. 1 (steel): specific heat,
       elongation at break, and the alloys' melting ranges (solidus–liquidus: 6061 582–652 °C,
       2024 502–638 °C, 7075 477–635 °C, 304 stainless steel 1400–1455 °C). The elongation is used as the plastic-strain
       failure limit — a simple, conservative (early-failing) choice.
[CRC]  *CRC Handbook of Chemistry and Physics*, 97th ed. (2016), §6 "Enthalpy of fusion" and
       "Enthalpy of vaporization" and §4 "Melting, boiling … points of the elements": aluminium
       T_m 933.47 K, ΔH_fus 10.71 kJ/mol (397 J/g), T_b 2792 K, ΔH_vap 294 kJ/mol (10.9 kJ/g); copper
       T_m 1357.77 K, 13.26 kJ/mol (209 J/g), T_b 2835 K, 300 kJ/mol (4.72 kJ/g); iron 13.81 kJ/mol
       (247 J/g), T_b 3134 K, 340 kJ/mol (6.09 kJ/g).  The alloys take their base metal's latent heats
       and boiling point (the alloying elements move them by a few per cent, below what the constant
       specific heat already misses).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Annotated

from pydantic import AfterValidator

from impactdyn._errors import InputError
from impactdyn.units import CM_US_PER_KM_S, MBAR_PER_GPA

_MBAR_PER_MPA = 1.0e-3 * MBAR_PER_GPA

#: Crack-growth speed over the longitudinal sound speed, c_g = 0.4 c_L ([BA94]).
CRACK_SPEED_FRACTION = 0.4
_CM2_US2_PER_J_G = 1.0e-5  # 1 J/g = 1e3 J/kg = 1e-5 cm²/µs² (1 cm²/µs² = 1e8 J/kg)


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

    A, B in Mbar; ε̇₀ in 1/µs (1 s⁻¹ = 1e-6 µs⁻¹); temperatures in K.
    """

    A: float
    B: float
    n: float
    C: float
    m: float
    t_melt: float
    t_room: float = 294.0
    reference_strain_rate: float = 1.0e-6

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
class Material:
    """One material of the shield stage (units cm, g, µs, Mbar, K).

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
    johnson_cook : JohnsonCook | None
    phase : PhaseChange | None
        Melting range, boiling point and latent heats; None: melt is not judged (never melted).
    source : str
        Where the numbers come from (keys of the module docstring).
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

    def __post_init__(self) -> None:
        for field in ("rho0", "c0", "s", "gamma0", "shear_modulus", "specific_heat"):
            value = getattr(self, field)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise InputError(f"material {self.name!r}: {field} must be a positive number, got {value!r}")
        if not (math.isfinite(self.yield_stress) and self.yield_stress >= 0):
            raise InputError(f"material {self.name!r}: yield_stress must be ≥ 0, got {self.yield_stress!r}")
        for field in ("spall_strength", "failure_strain"):
            value = getattr(self, field)
            if value is not None and not (math.isfinite(value) and value > 0):
                raise InputError(f"material {self.name!r}: {field} must be positive or None, got {value!r}")

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


def _gpa(x: float) -> float:
    return x * MBAR_PER_GPA


def _km_s(x: float) -> float:
    return x * CM_US_PER_KM_S


def _phase(solidus_c: float, liquidus_c: float, fusion_j_g: float, boiling_k: float, vaporisation_j_g: float,
           source: str) -> PhaseChange:
    return PhaseChange(solidus=solidus_c + 273.15, liquidus=liquidus_c + 273.15,
                       latent_fusion=fusion_j_g * _CM2_US2_PER_J_G, boiling=boiling_k,
                       latent_vaporisation=vaporisation_j_g * _CM2_US2_PER_J_G, source=source)


_ALUMINIUM_LATENT = dict(fusion_j_g=397.0, boiling_k=2792.0, vaporisation_j_g=10.9e3)


def _jc(a_mpa: float, b_mpa: float, n: float, c: float, m: float, t_melt: float) -> JohnsonCook:
    return JohnsonCook(A=a_mpa * _MBAR_PER_MPA, B=b_mpa * _MBAR_PER_MPA, n=n, C=c, m=m, t_melt=t_melt)


AL_6061_T6 = Material(
    name="al6061-t6", rho0=2.703, c0=_km_s(5.24), s=1.40, gamma0=1.97,
    shear_modulus=_gpa(27.6), yield_stress=_gpa(0.29), specific_heat=0.896 * _CM2_US2_PER_J_G,
    spall_strength=_gpa(1.2), failure_strain=0.12,
    johnson_cook=_jc(324.0, 114.0, 0.42, 0.002, 1.34, 925.0),
    phase=_phase(582.0, 652.0, **_ALUMINIUM_LATENT, source="[ASM] melting range; [CRC] aluminium latent heats, T_b"),
    source="[S91] EOS, G, Y0; [L01] Johnson-Cook; [K04] spall; [ASM] c_v, elongation 12 %",
)
AL_2024_T4 = Material(
    name="al2024-t4", rho0=2.785, c0=_km_s(5.328), s=1.338, gamma0=2.00,
    shear_modulus=_gpa(28.6), yield_stress=_gpa(0.26), specific_heat=0.875 * _CM2_US2_PER_J_G,
    spall_strength=_gpa(1.2), failure_strain=0.20,
    johnson_cook=_jc(265.0, 426.0, 0.34, 0.015, 1.0, 775.0),
    phase=_phase(502.0, 638.0, **_ALUMINIUM_LATENT, source="[ASM] melting range; [CRC] aluminium latent heats, T_b"),
    source="[S91] EOS, G, Y0; [JC83] Johnson-Cook of 2024-T351; [K04] spall; [ASM] c_v, elongation 20 %",
)
AL_7075_T6 = Material(
    name="al7075-t6", rho0=2.803, c0=_km_s(5.20), s=1.36, gamma0=2.20,
    shear_modulus=_gpa(26.7), yield_stress=_gpa(0.42), specific_heat=0.960 * _CM2_US2_PER_J_G,
    spall_strength=_gpa(1.2), failure_strain=0.11,
    phase=_phase(477.0, 635.0, **_ALUMINIUM_LATENT, source="[ASM] melting range; [CRC] aluminium latent heats, T_b"),
    source="[S91] EOS, G, Y0; [K04] spall; [ASM] c_v, elongation 11 %",
)
CU_OFHC = Material(
    name="cu-ofhc", rho0=8.93, c0=_km_s(3.94), s=1.489, gamma0=2.02,
    shear_modulus=_gpa(47.7), yield_stress=_gpa(0.12), specific_heat=0.385 * _CM2_US2_PER_J_G,
    spall_strength=_gpa(1.4), failure_strain=0.45,
    johnson_cook=_jc(90.0, 292.0, 0.31, 0.025, 1.09, 1356.0),
    phase=_phase(1084.62, 1084.62, 209.0, 2835.0, 4.72e3, source="[CRC] copper"),
    source="[S91] EOS, G, Y0; [JC83] Johnson-Cook; [K04] spall; [ASM] c_v, elongation 45 %",
)
SS_304 = Material(
    name="ss304", rho0=7.90, c0=_km_s(4.57), s=1.49, gamma0=1.93,
    shear_modulus=_gpa(77.0), yield_stress=_gpa(0.34), specific_heat=0.500 * _CM2_US2_PER_J_G,
    failure_strain=0.40,
    phase=_phase(1400.0, 1455.0, 247.0, 3134.0, 6.09e3, source="[ASM] melting range; [CRC] iron latent heats, T_b"),
    source="[S91] EOS, G, Y0 (304 stainless steel); [ASM] c_v, elongation 40 %; no spall data entered",
)

#: Registry by name; look names up with :func:`get_material` (case and separators ignored).
MATERIALS: dict[str, Material] = {m.name: m for m in (AL_6061_T6, AL_2024_T4, AL_7075_T6, CU_OFHC, SS_304)}


def _key(name: str) -> str:
    return "".join(ch for ch in name.lower() if ch.isalnum())


def get_material(name: str | Material) -> Material:
    """The registered material called ``name`` ("Al6061-T6", "al_6061_t6", ... all match).

    A :class:`Material` passes through. Unknown names raise :class:`InputError`
    listing the known ones.
    """
    if isinstance(name, Material):
        return name
    if isinstance(name, str):
        for known, material in MATERIALS.items():
            if _key(known) == _key(name):
                return material
    raise InputError(f"unknown material {name!r}; known materials: {', '.join(MATERIALS)}")


def _known_material(name: str) -> str:
    try:
        return get_material(name).name
    except InputError as err:
        raise ValueError(str(err)) from None


MaterialName = Annotated[str, AfterValidator(_known_material)]
"""A name of :data:`impactdyn.materials.MATERIALS`, stored as its canonical name."""
REPORT_MATERIAL = "al6061-t6"
"""Projectile, bumper and wall material by default: the report's Al 6061-T6."""


# --- The wall card: DYNA3D material type 13 / LS-DYNA *MAT_013 -----------------------------

@dataclass(frozen=True)
class Mat13Card:
    """Isotropic elastic–plastic wall material with failure, cm-g-µs units.

    The parameters of DYNA3D material 13 (isotropic elastic–plastic with failure),
    the wall material of the report's deck (App. D).

    Attributes: density (g/cm³); shear_modulus, bulk_modulus, yield_stress and
    hardening_modulus (plastic hardening modulus E_h, Mbar); failure_strain
    (effective plastic strain at failure, 0 = none); failure_pressure (Mbar, ≤ 0).
    """

    density: float
    shear_modulus: float
    bulk_modulus: float
    yield_stress: float
    hardening_modulus: float
    failure_strain: float
    failure_pressure: float

    def __post_init__(self) -> None:
        _require_numbers(self, ("density", "shear_modulus", "bulk_modulus", "yield_stress"), positive=True)
        _require_numbers(self, ("hardening_modulus", "failure_strain"), positive=False)
        if not (math.isfinite(self.failure_pressure) and self.failure_pressure <= 0):
            raise InputError(f"Mat13Card.failure_pressure: must be <= 0, got {self.failure_pressure!r}")

    @property
    def youngs_modulus(self) -> float:
        """E = 9KG / (3K + G), Mbar."""
        k, g = self.bulk_modulus, self.shear_modulus
        return 9.0 * k * g / (3.0 * k + g)

    @property
    def poisson_ratio(self) -> float:
        """ν = (3K − 2G) / (2 (3K + G))."""
        k, g = self.bulk_modulus, self.shear_modulus
        return (3.0 * k - 2.0 * g) / (2.0 * (3.0 * k + g))

    @property
    def tangent_modulus(self) -> float:
        """Slope E_t of the bilinear stress–strain curve, E E_h / (E + E_h), Mbar."""
        e, eh = self.youngs_modulus, self.hardening_modulus
        return e * eh / (e + eh)


#: Al 6061-T6 as the report's DYNA3D deck gives it (Fahrenthold 1994, App. D,
#: material 1, type 13: G 0.276, σ_y 2.900e-03, E_h 3.88e-03, ε_f 1.5, p_cut
#: -12.e+33, K 0.720, in that order on the cards).  ρ, G and σ_y are Steinberg's
#: (1991) 6061-T6 values (2.703 g/cm³, 27.6 GPa, Y₀ 0.29 GPa); K = 72 GPa is close
#: to ρ₀c₀² = 74 GPa from his c₀ = 5.24 km/s.  p_cut = -1.2e34 Mbar means no
#: pressure cutoff.  E = 73.4 GPa and ν = 0.330 follow from G and K.
AL_6061_T6_MAT13 = Mat13Card(
    density=2.703,
    shear_modulus=0.276,
    bulk_modulus=0.720,
    yield_stress=2.900e-03,
    hardening_modulus=3.88e-03,
    failure_strain=1.5,
    failure_pressure=-12.0e33,
)



def mat13_card(material: "str | Material") -> Mat13Card:
    """The DYNA3D material-13 card of a library material (:mod:`impactdyn.materials`).

    Al 6061-T6 gets the report's own card (:data:`AL_6061_T6_MAT13`).  Any other
    material: ρ₀, G, K = ρ₀c₀² and Y₀ of the library, no hardening (the
    elastic–perfectly-plastic model of the shield stage), its plastic-strain
    failure limit (0 = none) and failure pressure −p_spall (no cutoff without one).
    """
    m = get_material(material)
    if m.name == "al6061-t6":
        return AL_6061_T6_MAT13
    return Mat13Card(density=m.rho0, shear_modulus=m.shear_modulus, bulk_modulus=m.rho0 * m.c0**2,
                        yield_stress=m.yield_stress, hardening_modulus=0.0, failure_strain=m.failure_strain or 0.0,
                        failure_pressure=-m.spall_strength if m.spall_strength else AL_6061_T6_MAT13.failure_pressure)


# --- Johnson–Cook damage (the wall stage's ductile-failure model) -------------------------------

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


#: Al 6061-T6, the constants [L01] give with the Johnson–Cook strength above (A 324 MPa,
#: B 114 MPa, n 0.42, C 0.002, m 1.34), in Johnson & Cook's sign convention (D3 < 0: the
#: fracture strain falls as the triaxiality σ* rises).  The report itself could not be read
#: here; the values were checked against two public model inputs that quote them: an
#: Abaqus input for 6061-T6 with the [L01] strength constants giving D1 -0.77, D2 1.45 and
#: d3 = 0.47 in Abaqus's form exp(-d3 σ*) (D4, D5 set to 0 there), and the OpenRadioss
#: /FAIL/JOHNSON defaults of an open deck converter (D1 -0.77, D2 1.45, D3 -0.47, D4 0,
#: D5 1.6; material not named).  D1 < 0 makes ε_f vanish for σ* > ln(0.77/1.45)/(-0.47)
#: = 1.35 (see the wall model's floor on ε_f).
#:
#: The fracture-strain floor ε_f,min: the fit's value at the highest triaxiality round notched bars
#: reach, NOTCHED_BAR_TRIAXIALITY = 1/3 + ln 2 = 1.03 ([B52] with R = a/2, the sharpest notch of the
#: usual series; Bao & Wierzbicki's 2024-T351 notched bars, the reference set of such tests, stay
#: below it), i.e. ε_f is held at D1 + D2 exp(D3 · 1.03) = 0.125 beyond the data instead of
#: falling to zero at σ* = 1.35.  UNCERTAIN: no measured 6061-T6 fracture strain at σ* > 1 could
#: be read here (neither [L01]'s data nor a published LS-DYNA EFMIN for this alloy: LS-DYNA's
#: default EFMIN is the numerical 1e-6); the value rests on the fit and on where notched-bar
#: data end, not on a test at the wall's triaxialities.
NOTCHED_BAR_TRIAXIALITY = 1.0 / 3.0 + math.log(2.0)
AL_6061_T6_JC_DAMAGE = JohnsonCookDamage(
    D1=-0.77, D2=1.45, D3=-0.47, D4=0.0, D5=1.6,
    source="[L01] (Lesuer, Kay & LeBlanc, UCRL-JC-134118, 2001), as quoted in public model inputs",
    efmin=-0.77 + 1.45 * math.exp(-0.47 * NOTCHED_BAR_TRIAXIALITY),
    efmin_source="the [L01] fit at the largest notched-bar triaxiality 1/3 + ln 2 ([B52]); uncertain, no "
                 "measurement at higher triaxiality",
)

#: Al 2024-T351, the damage set used with the [JC83] strength constants of the library's
#: ``al2024-t4`` (A 265 MPa, B 426 MPa, n 0.34, C 0.015, m 1) in the impact literature on
#: 2024-T351 plates (Teng & Wierzbicki's perforation study [TW06] uses 2024-T351).  The values
#: are the widely quoted ones; neither [TW06] nor a primary table could be read here to check
#: them.  D1, D2 > 0: the fracture strain falls from 0.26 at zero mean stress through 0.21 in
#: uniaxial tension (σ* = ⅓) towards 0.13 at high triaxiality: bounded below by D1 = 0.13 itself,
#: so it needs no fracture-strain floor (``efmin`` None).  Bao & Wierzbicki's notched-bar tests on
#: 2024-T351 (Int. J. Mech. Sci. 46 (2004) 81) are the data such a floor would rest on; they could
#: not be read here to check D1 against them.
AL_2024_T351_JC_DAMAGE = JohnsonCookDamage(
    D1=0.13, D2=0.13, D3=-1.5, D4=0.011, D5=0.0,
    source="2024-T351 as widely quoted (e.g. the 2024-T351 plates of [TW06]); not checked against a primary table",
)

#: OFHC copper, Johnson & Cook's own fit [JC85] (with the [JC83] strength constants above);
#: D1 = 0.54 > 0 bounds it below (no floor needed).
CU_OFHC_JC_DAMAGE = JohnsonCookDamage(
    D1=0.54, D2=4.89, D3=-3.03, D4=0.014, D5=1.12,
    source="[JC85] (Johnson & Cook, Eng. Fract. Mech. 21 (1985) 31), OFHC copper",
)

#: Johnson–Cook damage constants by library material name; materials without an entry
#: have no ductile-damage data here (their Johnson–Cook wall fails by spall alone).
JOHNSON_COOK_DAMAGE: dict[str, JohnsonCookDamage] = {
    "al6061-t6": AL_6061_T6_JC_DAMAGE, "al2024-t4": AL_2024_T351_JC_DAMAGE, "cu-ofhc": CU_OFHC_JC_DAMAGE}


# --- Tuler–Butcher spall (the wall stage's default spall law) -----------------------------------

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


#: The constants below are a documented FALLBACK, not published Tuler–Butcher constants: Tuler &
#: Butcher's 6061-T6 fit [TB68] (to the plate-impact data of Butcher, Barker, Munson & Lundergan,
#: AIAA J. 2 (1964) 977) and the tabulations in the textbooks (Zukas; Meyers; Antoun et al.) could
#: not be read here, and no 2024 constants were found.  They scale from the spall strengths of [K04]:
#: σ₀ = the library's spall strength p_spall (the onset of spall in microsecond experiments, so no
#: damage below it), λ = TB_EXPONENT, and K such that at the stress rate of a typical spall
#: experiment, TB_STRESS_RATE, the material fails at the top of [K04]'s range for the alloy family
#: (aluminium alloys 1.7 GPa, copper 1.6 GPa): K = (σ_hi − σ₀)^{λ+1} / ((λ+1) σ̇_ref).  UNCERTAIN:
#: λ, the reference rate and hence K; σ₀ is as good as p_spall (a representative value of [K04]).
#:
#: λ = 2: the quadratic (energy-like) form most used with Tuler–Butcher for metals; not checked
#: against [TB68]'s fit.
TB_EXPONENT = 2.0
#: σ̇_ref = 10 GPa/µs: the unloading rate ρ₀c_L² ε̇ of a plate-impact spall test at ε̇ ≈ 10⁵ /s (the
#: middle of [K04]'s 10⁴–10⁶ /s) in aluminium (ρ₀c_L² ≈ 110 GPa); in Mbar/µs.
TB_STRESS_RATE = _gpa(10.0)


def _tuler_butcher_from_spall(spall_strength: float, spall_strength_high: float, alloy: str) -> TulerButcher:
    """The fallback constants (above) from p_spall and the top of [K04]'s range σ_hi (Mbar)."""
    lam = TB_EXPONENT
    k = (spall_strength_high - spall_strength) ** (lam + 1.0) / ((lam + 1.0) * TB_STRESS_RATE)
    return TulerButcher(sigma0=spall_strength, lam=lam, K=k,
                        source=f"fallback scaled from [K04] spall strengths of {alloy} (sigma0 = p_spall, "
                               f"failure at {spall_strength_high / _gpa(1.0):.1f} GPa under 10 GPa/us, "
                               f"lambda = 2); not [TB68]'s fit, uncertain")


#: Tuler–Butcher constants by library material name (the fallback above; materials without an
#: entry have only the cut-off spall law).
TULER_BUTCHER: dict[str, TulerButcher] = {
    "al6061-t6": _tuler_butcher_from_spall(AL_6061_T6.spall_strength, _gpa(1.7), "aluminium alloys"),
    "al2024-t4": _tuler_butcher_from_spall(AL_2024_T4.spall_strength, _gpa(1.7), "aluminium alloys"),
    "cu-ofhc": _tuler_butcher_from_spall(CU_OFHC.spall_strength, _gpa(1.6), "copper"),
}


# --- Weibull flaws (the shield stage's tensile damage, Grady–Kipp / Benz–Asphaug) -----------------

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


#: Spheral's aluminium: k = 7×10¹¹/2.63^2.55 cm⁻³ (5.9×10¹⁰), m = 2.55, as LLNL's Spheral material
#: library enters "aluminum" (its note: read from the plots of DOI 10.1007/s11661-010-0364-6, a paper
#: not identified here).  Not the library's default: under the Grady–Kipp law of the shield stage it
#: spalls aluminium at 0.18, 0.64 and 2.2 GPa at 10⁴, 10⁵ and 10⁶ s⁻¹ (:meth:`WeibullFlaws.fracture_time`),
#: below [K04]'s 1.0–1.7 GPa for aluminium alloys at the lower rates; kept for comparison.
SPHERAL_ALUMINIUM_WEIBULL = WeibullFlaws(
    k=7.0e11 / 2.63 ** 2.55, m=2.55,
    source="LLNL Spheral material library, 'aluminum' (from plots of DOI 10.1007/s11661-010-0364-6); "
           "the paper not identified here",
)


def weibull_from_spall(material: Material, low: tuple[float, float], high: tuple[float, float]) -> WeibullFlaws:
    """The Weibull constants that give ``material`` the spall strengths σ at the strain rates ε̇ of
    ``low`` and ``high`` ((σ Mbar, ε̇ µs⁻¹) each) under the Grady–Kipp damage of the shield stage.

    Under the uniaxial-strain ramp ε = ε̇t the damage reaches 1 at t_f (:meth:`WeibullFlaws.fracture_time`),
    so σ_f = E ε̇ t_f ∝ ε̇^{3/(m+3)} (Grady & Kipp's rate dependence of the fragmentation strength):
    m = 3/s − 3 with s the logarithmic slope of σ over ε̇ between the two points, and k from σ_f at their
    geometric mean.  E and c_g: :attr:`Material.young_modulus`, :attr:`Material.crack_speed`.
    """
    (s_lo, r_lo), (s_hi, r_hi) = low, high
    slope = math.log(s_hi / s_lo) / math.log(r_hi / r_lo)
    m = 3.0 / slope - 3.0
    young, growth = material.young_modulus, material.crack_speed
    rate, sigma = math.sqrt(r_lo * r_hi), math.sqrt(s_lo * s_hi)
    t_f = sigma / (young * rate)
    k = (m + 1.0) * (m + 2.0) * (m + 3.0) / (8.0 * math.pi * growth ** 3 * rate ** m * t_f ** (m + 3.0))
    return WeibullFlaws(k=k, m=m, source=(
        f"FALLBACK calibrated to [K04] spall strengths of aluminium alloys ({s_lo / _gpa(1.0):.1f} GPa at "
        f"{r_lo * 1e6:.0e}/s, {s_hi / _gpa(1.0):.1f} GPa at {r_hi * 1e6:.0e}/s) under the Grady-Kipp law; "
        "not a measured flaw distribution, uncertain"))


#: The library's aluminium flaws: a documented FALLBACK, not a measured flaw distribution.  No
#: Weibull constants measured for 6061-T6 or 2024 could be found (searched: Spheral's library, whose
#: aluminium set is above; Benz & Asphaug's tables are for rock; miluphcuda's material files hold
#: basalt and ice).  They are calibrated, by :func:`weibull_from_spall`, to the spall strengths of [K04]
#: (the same data the library's p_spall and the wall's Tuler–Butcher fallback rest on), the range
#: 1.0–1.7 GPa read as the strength at 10⁴ and 10⁶ s⁻¹: m = 23.0, a spall strength of 1.3 GPa at
#: 10⁵ s⁻¹.  UNCERTAIN: reading [K04]'s spread across alloys as a rate dependence sets m; a factor 2 in
#: the rate slope moves m between 10 and 50.  These constants decide where the tensile damage begins,
#: and so the shield stage's break-up onset.
AL_WEIBULL = weibull_from_spall(AL_6061_T6, (_gpa(1.0), 1.0e-2), (_gpa(1.7), 1.0))

#: Weibull flaw constants by library material name; the shield stage's fragmentation model refuses
#: a material without an entry (naming it).
WEIBULL_FLAWS: dict[str, WeibullFlaws] = {
    "al6061-t6": AL_WEIBULL, "al2024-t4": AL_WEIBULL, "al7075-t6": AL_WEIBULL}


# --- Fracture toughness (the fragments of failed material, Grady's energy balance) -----------------

def _mpa_sqrt_m(x: float) -> float:
    """MPa·m^½ → Mbar·cm^½ (1 MPa·√m = 10⁶ Pa · 10 √cm = 10⁻⁴ Mbar·√cm)."""
    return x * 1.0e-4


#: Plane-strain fracture toughness K_Ic, Mbar·cm^½, by library material name: what sizes the fragments
#: of failed material through Grady's energy balance [G82] (:func:`impactdyn.shield.grady_fragments`).
#: Room-temperature, quasi-static handbook values; the dynamic toughness at 10⁵–10⁷ s⁻¹ is not known
#: for these alloys, and the size goes as K_Ic^{2/3} (±20 % in K_Ic moves it ±13 %).  al2024-t4 (the
#: library's 2024-T351/2017-T4): 34 MPa√m, the [MMPDS] average for 2024-T351 plate.  al7075-t6:
#: 24 MPa√m, [C07] (7075-T651).  al6061-t6: 29 MPa√m, the value commonly tabulated for 6061-T651
#: (ASM/Aluminum Association typical properties); UNCERTAIN: not read from a primary table here.  A
#: material without an entry (copper, steel: ductile beyond the K_Ic test's validity) cannot be given
#: fragments of failed material; the shield stage refuses it, naming it.
FRACTURE_TOUGHNESS: dict[str, float] = {
    "al6061-t6": _mpa_sqrt_m(29.0), "al2024-t4": _mpa_sqrt_m(34.0), "al7075-t6": _mpa_sqrt_m(24.0)}
