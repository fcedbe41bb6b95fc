r"""NASA JSC Whipple-shield equations as Christiansen published them in 1993 (``"jsc1993"``).

Sources
-------
* E.L. Christiansen, "Design and performance equations for advanced meteoroid and
  debris shields", Int. J. Impact Eng. 14 (1993) 145–156 — the Whipple equations.
* E.L. Christiansen et al., "Handbook for designing MMOD protection",
  NASA/TM-2009-214785 (2009), §4, Whipple shield ballistic limit equations
  (same three regimes and coefficients; also E.L. Christiansen, "Meteoroid/debris
  shielding", NASA/TP-2003-210788, and Christiansen & Kerr, Int. J. Impact Eng. 26
  (2001) 93–104).

The equation numbers of those reports are not repeated here (the texts could not be
checked line by line where this module was written); the three regime equations are
labelled (W1)–(W3) below and in the functions that evaluate them.  The regime structure,
(W1) and the 65° obliquity cap are shared with the 2011 form, see
:mod:`impactdyn.ble._equation`; this module holds (W3) and registers the equation.

Units are the literature's: lengths in cm, densities in g/cm³, velocity in km/s,
the rear-wall yield stress σ in ksi; θ is the angle from the target normal.

The equations (critical projectile diameter d_c, the largest aluminium-like sphere
that does not perforate or detach spall from the rear wall)::

    V_n = V cos θ                                   normal velocity component

    (W1) ballistic, V_n ≤ 3 km/s:
         d_c = [ (t_w (σ/40)^{1/2} + t_b) / (0.6 (cos θ)^{5/3} ρ_p^{1/2} V^{2/3}) ]^{18/19}

    (W3) hypervelocity, V_n ≥ 7 km/s:
         d_c = 3.918 t_w^{2/3} ρ_p^{-1/3} ρ_b^{-1/9} (V cos θ)^{-2/3} S^{1/3} (σ/70)^{1/3}

    (W2) shatter, 3 < V_n < 7 km/s: linear in V between (W1) at V_lo = 3/cos θ and
         (W3) at V_hi = 7/cos θ,
         d_c = d_c^{W1}(V_lo) (V_hi − V)/(V_hi − V_lo) + d_c^{W3}(V_hi) (V − V_lo)/(V_hi − V_lo)

Obliquity conventions, checked against the sources: the regime boundaries are on
V cos θ (cos to the first power: V_lo = 3/cos θ, V_hi = 7/cos θ); (W1) carries
(cos θ)^{5/3} = (cos θ)^{2/3}·cos θ with V^{2/3}; (W3) carries (V cos θ)^{-2/3}, i.e.
(cos θ)^{-2/3} and V^{-2/3}.  The handbook prints (W2) with rounded coefficients,

    d_c = [ (t_w (σ/40)^{1/2} + t_b) / (1.248 ρ_p^{1/2} cos θ) ]^{18/19} (1.75 − V_n/4)
          + 1.071 t_w^{2/3} ρ_p^{-1/3} ρ_b^{-1/9} S^{1/3} (σ/70)^{1/3} (V_n/4 − 0.75),

where 1.248 = 0.6·3^{2/3} (= 1.24805) and 1.071 = 3.918·7^{-2/3} (= 1.07069); the
weights (1.75 − V_n/4) and (V_n/4 − 0.75) are the linear interpolation above.  We
evaluate the regime ends exactly, so d_c is continuous at both boundaries; the rounded
form differs by about 3 × 10⁻⁴ relative (0.52141 vs 0.52127 cm in the example below).

A worked example (bumper 0.127 cm Al, wall 0.3175 cm, σ = 40 ksi, θ = 25°,
ρ_p = ρ_b = 2.7 g/cm³, S = 10 cm): at 7 km/s V_n = 6.344 km/s, so the point lies in
the *shatter* regime (W2), d_c = 0.521267 cm; at 10 km/s V_n = 9.063 km/s, (W3) gives
d_c = 0.482295 cm.  ρ_b = 2.713 gives 0.521011 and 0.482038 cm — both densities
reproduce the reference values 0.521 and 0.482 cm that the tests pin
(tests/ble/test_ble_whipple.py).  With S = 10.16 cm (bumper back to wall
front, the report's Appendix A geometry) d_c = 0.523808 and 0.484854 cm, 3 × 10⁻³ cm
above the reference values, which are therefore for S = 10 cm; the Table 2 verdicts
(0.575 and 0.530 cm perforate, 0.475 and 0.430 cm do not) hold for either spacing.
A (cos θ)^{-1/3} obliquity factor in (W3), found in some re-statements, would give
0.4667 cm at 10 km/s and does not reproduce the reference value.

Obliquity cap: θ enters every formula above, and the regime boundaries, as min(θ, 65°)
(Christiansen 1993 eq. 12; NASA/TM-2009-214785 eq. 4-26), so nothing changes below 65°
and every angle from 65° to 90° is evaluated at 65°.  Uncapped, at 85° the ballistic regime
would reach 3/cos 85° = 34 km/s, and (W1)'s (cos θ)^{-(5/3)(18/19)} would give a d_c
(cos 65°/cos 85°)^{1.58} = 12 times the value at 65°.  The equations were fitted to
aluminium-on-aluminium tests.
"""

from __future__ import annotations

import numpy as np

from impactdyn.ble._equation import HypervelocityLimit, WhippleEquation
from impactdyn.ble._registry import register

#: Upper end of the ballistic regime of the 1993 equations, on V cos θ (km/s).
V_BALLISTIC_MAX_KM_S = 3.0


def hypervelocity_diameter(shield, v, cos_t, rho_p):
    """(W3): d_c = 3.918 t_w^{2/3} ρ_p^{-1/3} ρ_b^{-1/9} (V cos θ)^{-2/3} S^{1/3} (σ/70)^{1/3}."""
    return (3.918 * shield.wall_thickness_cm ** (2.0 / 3.0) * rho_p ** (-1.0 / 3.0)
            * shield.bumper_density_g_cm3 ** (-1.0 / 9.0) * (v * cos_t) ** (-2.0 / 3.0)
            * shield.spacing_cm ** (1.0 / 3.0) * (shield.wall_yield_ksi / 70.0) ** (1.0 / 3.0))


def _hypervelocity_limit(shield, v, cos_t, rho_p) -> HypervelocityLimit:
    """(W3) as a :class:`HypervelocityLimit`: one value everywhere, nothing to note."""
    d = hypervelocity_diameter(shield, v, cos_t, rho_p)
    return HypervelocityLimit(diameter=d, threshold=d, note=np.full(d.shape, None, dtype=object))


JSC1993 = register(WhippleEquation(
    name="jsc1993",
    title="JSC Whipple, Christiansen 1993",
    ballistic_max_km_s=V_BALLISTIC_MAX_KM_S,
    hypervelocity=_hypervelocity_limit,
))
