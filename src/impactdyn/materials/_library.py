"""The material library of the impact stages: one :class:`Material` record per alloy, with a source for
every number, registered at the bottom of this module (:func:`register_material`).

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
       failure limit — a simple, conservative (early-failing) choice.  Typical tensile yield
       stresses (0.2 % offset), the σ_y of the JSC ballistic-limit equations: 6061-T6 40 ksi
       (276 MPa, also the equations' nominal wall), 2024-T4 47 ksi (324 MPa), 7075-T6 73 ksi
       (503 MPa); copper and steel have none here (their yield depends on the temper: a case with
       such a wall gives ``wall.yield_stress_ksi``).
[CRC]  *CRC Handbook of Chemistry and Physics*, 97th ed. (2016), §6 "Enthalpy of fusion" and
       "Enthalpy of vaporization" and §4 "Melting, boiling … points of the elements": aluminium
       T_m 933.47 K, ΔH_fus 10.71 kJ/mol (397 J/g), T_b 2792 K, ΔH_vap 294 kJ/mol (10.9 kJ/g); copper
       T_m 1357.77 K, 13.26 kJ/mol (209 J/g), T_b 2835 K, 300 kJ/mol (4.72 kJ/g); iron 13.81 kJ/mol
       (247 J/g), T_b 3134 K, 340 kJ/mol (6.09 kJ/g).  The alloys take their base metal's latent heats
       and boiling point (the alloying elements move them by a few per cent, below what the constant
       specific heat already misses).
"""

from __future__ import annotations

import dataclasses
import math

from impactdyn.materials._records import (
    FractureToughness, JohnsonCook, JohnsonCookDamage, Material, PhaseChange, TulerButcher, WeibullFlaws)
from impactdyn.materials._registry import register_material
from impactdyn.units import (CM2_US2_PER_J_G, MBAR_PER_MPA, MBAR_SQRT_CM_PER_MPA_SQRT_M, gpa_to_mbar, km_s_to_cm_us,
                             ksi_to_mbar, mbar_to_gpa)


def _phase(solidus_c: float, liquidus_c: float, fusion_j_g: float, boiling_k: float, vaporisation_j_g: float,
           source: str) -> PhaseChange:
    return PhaseChange(solidus=solidus_c + 273.15, liquidus=liquidus_c + 273.15,
                       latent_fusion=fusion_j_g * CM2_US2_PER_J_G, boiling=boiling_k,
                       latent_vaporisation=vaporisation_j_g * CM2_US2_PER_J_G, source=source)


_ALUMINIUM_LATENT = dict(fusion_j_g=397.0, boiling_k=2792.0, vaporisation_j_g=10.9e3)
_ALUMINIUM_PHASE_SOURCE = "[ASM] melting range; [CRC] aluminium latent heats, T_b"


def _jc(a_mpa: float, b_mpa: float, n: float, c: float, m: float, t_melt: float, source: str) -> JohnsonCook:
    return JohnsonCook(A=a_mpa * MBAR_PER_MPA, B=b_mpa * MBAR_PER_MPA, n=n, C=c, m=m, t_melt=t_melt, source=source)


#: Spall strengths p_spall, Mbar: representative values inside [K04]'s ranges at microsecond load durations
#: (aluminium alloys 1.0–1.7 GPa, copper 1.2–1.6 GPa), not measurements of the particular temper; the top
#: of each range is where the Tuler–Butcher and Weibull fallbacks below put failure at a typical rate.
ALUMINIUM_SPALL_STRENGTH, ALUMINIUM_SPALL_RANGE = gpa_to_mbar(1.2), (gpa_to_mbar(1.0), gpa_to_mbar(1.7))
COPPER_SPALL_STRENGTH, COPPER_SPALL_TOP = gpa_to_mbar(1.4), gpa_to_mbar(1.6)


# --- Johnson–Cook damage (the wall stage's ductile-failure model) -------------------------------

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


# --- Tuler–Butcher spall (the wall stage's default spall law) -----------------------------------

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
TB_STRESS_RATE = gpa_to_mbar(10.0)


def _tuler_butcher_from_spall(spall_strength: float, spall_strength_high: float, alloy: str) -> TulerButcher:
    """The fallback constants (above) from p_spall and the top of [K04]'s range σ_hi (Mbar)."""
    lam = TB_EXPONENT
    k = (spall_strength_high - spall_strength) ** (lam + 1.0) / ((lam + 1.0) * TB_STRESS_RATE)
    return TulerButcher(sigma0=spall_strength, lam=lam, K=k,
                        source=f"fallback scaled from [K04] spall strengths of {alloy} (sigma0 = p_spall, "
                               f"failure at {mbar_to_gpa(spall_strength_high):.1f} GPa under 10 GPa/us, "
                               f"lambda = 2); not [TB68]'s fit, uncertain")


# --- Weibull flaws (the shield stage's tensile damage, Grady–Kipp / Benz–Asphaug) -----------------

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
        f"FALLBACK calibrated to [K04] spall strengths of aluminium alloys ({mbar_to_gpa(s_lo):.1f} GPa at "
        f"{r_lo * 1e6:.0e}/s, {mbar_to_gpa(s_hi):.1f} GPa at {r_hi * 1e6:.0e}/s) under the Grady-Kipp law; "
        "not a measured flaw distribution, uncertain"))


# --- Fracture toughness (the fragments of failed material, Grady's energy balance) -----------------

def _mpa_sqrt_m(x: float, source: str) -> FractureToughness:
    return FractureToughness(K_Ic=x * MBAR_SQRT_CM_PER_MPA_SQRT_M, source=source)


#: Plane-strain fracture toughness K_Ic (the alloys' ``fracture_toughness``): what sizes the fragments
#: of failed material through Grady's energy balance [G82] (:func:`impactdyn.shield.grady_fragments`).
#: Room-temperature, quasi-static handbook values; the dynamic toughness at 10⁵–10⁷ s⁻¹ is not known
#: for these alloys, and the size goes as K_Ic^{2/3} (±20 % in K_Ic moves it ±13 %).  al2024-t4 (the
#: library's 2024-T351/2017-T4): 34 MPa√m, the [MMPDS] average for 2024-T351 plate.  al7075-t6:
#: 24 MPa√m, [C07] (7075-T651).  al6061-t6: 29 MPa√m, the value commonly tabulated for 6061-T651
#: (ASM/Aluminum Association typical properties); UNCERTAIN: not read from a primary table here.  A
#: material without one (copper, steel: ductile beyond the K_Ic test's validity) cannot be given
#: fragments of failed material; the case is refused, naming it.
_ALUMINIUM_KIC_SOURCE = "room-temperature, quasi-static handbook value; the dynamic toughness is not known"


# --- The alloys -----------------------------------------------------------------------------------

_AL_6061_T6_WITHOUT_FLAWS = Material(
    name="al6061-t6", rho0=2.703, c0=km_s_to_cm_us(5.24), s=1.40, gamma0=1.97,
    shear_modulus=gpa_to_mbar(27.6), yield_stress=gpa_to_mbar(0.29), specific_heat=0.896 * CM2_US2_PER_J_G,
    spall_strength=ALUMINIUM_SPALL_STRENGTH, failure_strain=0.12,
    johnson_cook=_jc(324.0, 114.0, 0.42, 0.002, 1.34, 925.0, source="[L01]"),
    phase=_phase(582.0, 652.0, **_ALUMINIUM_LATENT, source=_ALUMINIUM_PHASE_SOURCE),
    source="[S91] EOS, G, Y0; [L01] Johnson-Cook; [K04] spall; [ASM] c_v, elongation 12 %, tensile yield 40 ksi",
    tensile_yield=ksi_to_mbar(40.0),
    johnson_cook_damage=AL_6061_T6_JC_DAMAGE,
    tuler_butcher=_tuler_butcher_from_spall(ALUMINIUM_SPALL_STRENGTH, ALUMINIUM_SPALL_RANGE[1], "aluminium alloys"),
    fracture_toughness=_mpa_sqrt_m(29.0, "6061-T651 as commonly tabulated (ASM/Aluminum Association typical "
                                         "properties), not read from a primary table; " + _ALUMINIUM_KIC_SOURCE),
)
#: The library's aluminium flaws: a documented FALLBACK, not a measured flaw distribution.  No
#: Weibull constants measured for 6061-T6 or 2024 could be found (searched: Spheral's library, whose
#: aluminium set is above; Benz & Asphaug's tables are for rock; miluphcuda's material files hold
#: basalt and ice).  They are calibrated, by :func:`weibull_from_spall`, to the spall strengths of [K04]
#: (the same data the library's p_spall and the wall's Tuler–Butcher fallback rest on), the range
#: 1.0–1.7 GPa read as the strength at 10⁴ and 10⁶ s⁻¹: m = 23.0, a spall strength of 1.3 GPa at
#: 10⁵ s⁻¹.  UNCERTAIN: reading [K04]'s spread across alloys as a rate dependence sets m; a factor 2 in
#: the rate slope moves m between 10 and 50.  These constants decide where the tensile damage begins,
#: and so the shield stage's break-up onset.
AL_WEIBULL = weibull_from_spall(_AL_6061_T6_WITHOUT_FLAWS, (ALUMINIUM_SPALL_RANGE[0], 1.0e-2),
                                (ALUMINIUM_SPALL_RANGE[1], 1.0))
AL_6061_T6 = dataclasses.replace(_AL_6061_T6_WITHOUT_FLAWS, weibull_flaws=AL_WEIBULL)
AL_2024_T4 = Material(
    name="al2024-t4", rho0=2.785, c0=km_s_to_cm_us(5.328), s=1.338, gamma0=2.00,
    shear_modulus=gpa_to_mbar(28.6), yield_stress=gpa_to_mbar(0.26), specific_heat=0.875 * CM2_US2_PER_J_G,
    spall_strength=ALUMINIUM_SPALL_STRENGTH, failure_strain=0.20,
    johnson_cook=_jc(265.0, 426.0, 0.34, 0.015, 1.0, 775.0, source="[JC83] 2024-T351"),
    phase=_phase(502.0, 638.0, **_ALUMINIUM_LATENT, source=_ALUMINIUM_PHASE_SOURCE),
    source="[S91] EOS, G, Y0; [JC83] Johnson-Cook of 2024-T351; [K04] spall; [ASM] c_v, elongation 20 %, "
           "tensile yield 47 ksi",
    tensile_yield=ksi_to_mbar(47.0),
    johnson_cook_damage=AL_2024_T351_JC_DAMAGE,
    tuler_butcher=_tuler_butcher_from_spall(ALUMINIUM_SPALL_STRENGTH, ALUMINIUM_SPALL_RANGE[1], "aluminium alloys"),
    weibull_flaws=AL_WEIBULL,
    fracture_toughness=_mpa_sqrt_m(34.0, "[MMPDS] 2024-T351 plate average; " + _ALUMINIUM_KIC_SOURCE),
)
AL_7075_T6 = Material(
    name="al7075-t6", rho0=2.803, c0=km_s_to_cm_us(5.20), s=1.36, gamma0=2.20,
    shear_modulus=gpa_to_mbar(26.7), yield_stress=gpa_to_mbar(0.42), specific_heat=0.960 * CM2_US2_PER_J_G,
    spall_strength=ALUMINIUM_SPALL_STRENGTH, failure_strain=0.11,
    phase=_phase(477.0, 635.0, **_ALUMINIUM_LATENT, source=_ALUMINIUM_PHASE_SOURCE),
    source="[S91] EOS, G, Y0; [K04] spall; [ASM] c_v, elongation 11 %, tensile yield 73 ksi",
    tensile_yield=ksi_to_mbar(73.0),
    weibull_flaws=AL_WEIBULL,
    fracture_toughness=_mpa_sqrt_m(24.0, "[C07] 7075-T651; " + _ALUMINIUM_KIC_SOURCE),
)
CU_OFHC = Material(
    name="cu-ofhc", rho0=8.93, c0=km_s_to_cm_us(3.94), s=1.489, gamma0=2.02,
    shear_modulus=gpa_to_mbar(47.7), yield_stress=gpa_to_mbar(0.12), specific_heat=0.385 * CM2_US2_PER_J_G,
    spall_strength=COPPER_SPALL_STRENGTH, failure_strain=0.45,
    johnson_cook=_jc(90.0, 292.0, 0.31, 0.025, 1.09, 1356.0, source="[JC83]"),
    phase=_phase(1084.62, 1084.62, 209.0, 2835.0, 4.72e3, source="[CRC] copper"),
    source="[S91] EOS, G, Y0; [JC83] Johnson-Cook; [K04] spall; [ASM] c_v, elongation 45 %",
    johnson_cook_damage=CU_OFHC_JC_DAMAGE,
    tuler_butcher=_tuler_butcher_from_spall(COPPER_SPALL_STRENGTH, COPPER_SPALL_TOP, "copper"),
)
SS_304 = Material(
    name="ss304", rho0=7.90, c0=km_s_to_cm_us(4.57), s=1.49, gamma0=1.93,
    shear_modulus=gpa_to_mbar(77.0), yield_stress=gpa_to_mbar(0.34), specific_heat=0.500 * CM2_US2_PER_J_G,
    failure_strain=0.40,
    phase=_phase(1400.0, 1455.0, 247.0, 3134.0, 6.09e3, source="[ASM] melting range; [CRC] iron latent heats, T_b"),
    source="[S91] EOS, G, Y0 (304 stainless steel); [ASM] c_v, elongation 40 %; no spall data entered",
)

for _alloy in (AL_6061_T6, AL_2024_T4, AL_7075_T6, CU_OFHC, SS_304):
    register_material(_alloy)
