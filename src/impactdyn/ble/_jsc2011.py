r"""NASA's current Whipple-shield equation: Ryan & Christiansen 2011 (``"jsc2011"``).

Sources
-------
* S. Ryan, E.L. Christiansen, "A ballistic limit analysis programme for shielding against
  micrometeoroids and orbital debris", Acta Astronautica 69 (2011) 245–257, and the
  program's manual, S. Ryan, E.L. Christiansen, "Micrometeoroid and orbital debris (MMOD)
  shield ballistic limit analysis program", NASA/TM-2009-214789 (2010), Whipple shield.
* E.L. Christiansen, Int. J. Impact Eng. 14 (1993) 145–156, and NASA/TM-2009-214785 §4:
  (W1), (W3) (see :mod:`impactdyn.ble._jsc`) and the Whipple rear-wall sizing equation (S).

The equation numbers of the 2011 paper and of the manual could not be checked against
their texts where this module was written; the formulas are labelled (R1)–(R4) here.

Units: cm, g/cm³, km/s, ksi; θ from the target normal, capped at 65° as in the 1993
equations.  The 2011 form keeps (W1), the shatter blend and (W3), and changes two things:

1. the ballistic regime ends at V cos θ = 2.6 km/s (V_LV = 2.6/cos θ), not 3 km/s;
2. in the hypervelocity regime, V cos θ ≥ 7 km/s, thin bumpers are de-rated::

    (R1) d_c = 3.918 F2*^{-2/3} t_w^{2/3} ρ_p^{-1/3} ρ_b^{-1/9} (V cos θ)^{-2/3} S^{1/3} (σ/70)^{1/3}
             = F2*^{-2/3} d_c^{(W3)}

    (R2) F2* = 1                                                     t_b/d ≥ (t_b/d)_crit
         F2* = r_S/D − 2 x (r_S/D − 1) + x² (r_S/D − 1)              t_b/d < (t_b/d)_crit
             = 1 + (r_S/D − 1)(1 − x)²,   x = (t_b/d) / (t_b/d)_crit

    (R3) (t_b/d)_crit = 0.25 for S/d < 30,  0.20 for S/d ≥ 30

    (R4) r_S/D = t_w,0 / t_w,crit at V_HV = 7/cos θ: the rear wall the projectile needs with
         no bumper over the one it needs behind an optimum bumper,
         t_w,0    = 0.6 d^{19/18} (cos θ)^{5/3} ρ_p^{1/2} V_HV^{2/3} (σ/40)^{-1/2}
                    ((W1) with t_b = 0, solved for t_w),
         t_w,crit = c_w d^{1/2} (ρ_p ρ_b)^{1/6} m_p^{1/3} V_HV cos θ S^{-1/2} (70/σ)^{1/2},
                    c_w = 0.16, m_p = π ρ_p d³/6 (the sizing equation (S)).

F2* goes from r_S/D at t_b/d = 0 to 1, with zero slope, at (t_b/d)_crit.  r_S/D is taken
at V_HV in both regimes it reaches: the hypervelocity regime, and the shatter regime,
whose upper end is (R1) at V_HV.  Written out, r_S/D = 1.839 cos θ ρ_b^{-1/6} S^{1/2}
d^{-4/9}: ρ_p, σ and V drop out.

The fixed point
---------------
F2* depends on the diameter of the projectile, so d_c solves d = F2*(d)^{-2/3} d_c^{(W3)}.
With R(d) = ln d − ln d_c^{(W3)} + (2/3) ln F2*(d), within each branch of (R3):

* R is continuous (F2* is C¹ at x = 1) and strictly increasing in ln d.  r_S/D ∝ d^{-4/9}
  and x ∝ 1/d give d ln F2*/d ln d = [−(4/9) r_S/D (1 − x)² + 2 (r_S/D − 1)(1 − x) x] / F2*;
  the first term is > −4/9 because F2* ≥ r_S/D (1 − x)², the second is ≥ 0 for r_S/D ≥ 1
  and > −1 for r_S/D < 1 (there F2* = 1 − (1 − r_S/D)(1 − x)² and
  2 a u (1 − u) / (1 − a u²) < 2u/(1 + u) < 1 for a, u in (0, 1)).  So
  dR/d ln d > 1 − (2/3)(13/9) = 1/27, and each branch holds at most one root.
* Brackets: at d_lo = ½ min(d_c^{(W3)}, t_b/0.25), F2* = 1 and R = ln(d_lo/d_c^{(W3)}) < 0;
  F2* ≥ min(1, r_S/D) gives R ≥ ln 2 at d_hi = max(2 d_c^{(W3)}, (2 d_c^{(W3)} r_1^{-2/3})^{27/19}),
  r_1 = r_S/D at d = 1 cm.  Bisection on ln d between them; no solver stopping point is
  ever returned.

At d = S/30, where (R3) changes branch, R jumps.  Where r_S/D > 1 there (10.07 cos θ
ρ_b^{-1/6} (S/30)^{1/18}: for any real shield), x drops by the factor 0.8 across S/30,
F2* rises, the limit drops and R jumps up, so there is one root or none.  With none, every
projectile up to S/30 is below its own limit and every larger one above it: the equation
draws the line between perforation and none at S/30, but no diameter equals its own limit.
Then d_c is NaN, the threshold is S/30, and the note says so; in the shatter regime, whose
upper end is then missing, d_c is NaN too and the threshold blends to S/30 at V_HV.  Where
r_S/D < 1 at S/30 (only for absurd shields, e.g. a bumper of 10⁹ g/cm³) the limit jumps up
there, R down, and there can be two roots; the smaller is d_c (the conservative one), with
a note.
"""

from __future__ import annotations

import numpy as np

from impactdyn.ble._equation import V_HYPERVELOCITY_MIN_KM_S, HypervelocityLimit, WhippleEquation
from impactdyn.ble._jsc import hypervelocity_diameter
from impactdyn.ble._registry import register

#: Upper end of the ballistic regime of the 2011 form, on V cos θ (km/s).
V_BALLISTIC_MAX_KM_S = 2.6
#: (R3): (t_b/d)_crit for S/d < 30 and for S/d ≥ 30.
TB_D_CRIT_NEAR = 0.25
TB_D_CRIT_FAR = 0.20
S_D_SWITCH = 30.0
#: Rear-wall coefficient c_w of the Whipple sizing equation (cm²·s/(g^{2/3}·km)).
C_W = 0.16
#: Bisection stops when the bracket on ln d is this narrow (relative precision of d_c).
_TOL_LN_D = 1e-14


def rear_wall_without_bumper(shield, d, cos_t, rho_p, v):
    """t_w,0 of (R4), (W1) with t_b = 0 solved for t_w.

    0.6 d^{19/18} (cos θ)^{5/3} ρ_p^{1/2} V^{2/3} (σ/40)^{-1/2}.
    """
    return 0.6 * d ** (19.0 / 18.0) * cos_t ** (5.0 / 3.0) * np.sqrt(rho_p) * v ** (2.0 / 3.0) / np.sqrt(
        shield.wall_yield_ksi / 40.0)


def rear_wall_behind_optimum_bumper(shield, d, cos_t, rho_p, v):
    """t_w,crit of (R4), the sizing equation (S).

    c_w d^{1/2} (ρ_p ρ_b)^{1/6} m_p^{1/3} V cos θ S^{-1/2} (70/σ)^{1/2}, m_p = π ρ_p d³/6.
    """
    m_p = np.pi / 6.0 * rho_p * d ** 3
    return (C_W * np.sqrt(d) * (rho_p * shield.bumper_density_g_cm3) ** (1.0 / 6.0) * m_p ** (1.0 / 3.0)
            * v * cos_t / np.sqrt(shield.spacing_cm) * np.sqrt(70.0 / shield.wall_yield_ksi))


def r_sd(shield, d, cos_t, rho_p):
    """(R4): r_S/D = t_w,0 / t_w,crit at V_HV = 7/cos θ."""
    v_hv = V_HYPERVELOCITY_MIN_KM_S / cos_t
    return (rear_wall_without_bumper(shield, d, cos_t, rho_p, v_hv)
            / rear_wall_behind_optimum_bumper(shield, d, cos_t, rho_p, v_hv))


def f2_star(shield, d, tb_d_crit, cos_t, rho_p):
    """(R2) with the given (t_b/d)_crit, in the form 1 + (r_S/D − 1)(1 − x)² below it."""
    x = shield.bumper_thickness_cm / (d * tb_d_crit)
    return np.where(x >= 1.0, 1.0, 1.0 + (r_sd(shield, d, cos_t, rho_p) - 1.0) * (1.0 - x) ** 2)


def _bisect(residual, lo, hi):
    """Bisection on ln d, elementwise, where residual(lo) < 0 ≤ residual(hi)."""
    steps = int(np.ceil(np.log2(np.max(hi - lo, initial=_TOL_LN_D) / _TOL_LN_D)))
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        up = residual(mid) >= 0.0
        lo, hi = np.where(up, lo, mid), np.where(up, mid, hi)
    return 0.5 * (lo + hi)


def _hypervelocity_limit(shield, v, cos_t, rho_p) -> HypervelocityLimit:
    """(R1) at speeds v: the fixed point d = F2*(d)^{-2/3} d_c^{(W3)}, see the module docstring."""
    d3 = hypervelocity_diameter(shield, v, cos_t, rho_p)
    shape = d3.shape
    jump = np.broadcast_to(shield.spacing_cm / S_D_SWITCH, shape)
    ln_d3, ln_jump = np.log(d3), np.log(jump)

    def residual(ln_d, tb_d_crit):
        return ln_d - ln_d3 + (2.0 / 3.0) * np.log(f2_star(shield, np.exp(ln_d), tb_d_crit, cos_t, rho_p))

    d_lo = 0.5 * np.minimum(d3, shield.bumper_thickness_cm / TB_D_CRIT_NEAR)
    d_hi = np.maximum(2.0 * d3, (2.0 * d3 * r_sd(shield, 1.0, cos_t, rho_p) ** (-2.0 / 3.0)) ** (27.0 / 19.0))
    far = (d_lo < jump) & (residual(ln_jump, TB_D_CRIT_FAR) >= 0.0)  # a root with S/d ≥ 30
    ln_near_lo = np.log(np.maximum(jump, d_lo))
    near = residual(ln_near_lo, TB_D_CRIT_NEAR) < 0.0  # a root with S/d < 30
    tb_d_crit = np.where(far, TB_D_CRIT_FAR, TB_D_CRIT_NEAR)
    root = np.exp(_bisect(lambda ln_d: residual(ln_d, tb_d_crit),
                          np.where(far, np.log(d_lo), ln_near_lo),
                          np.where(far, ln_jump, np.maximum(np.log(d_hi), ln_near_lo))))
    found = far | near
    note = np.full(shape, None, dtype=object)
    note[~found] = [
        f"no fixed point: (t_b/d)_crit changes from 0.20 to 0.25 where S/d passes 30, at d = S/30 = {j:.4g} cm, "
        f"and the limit (R1) jumps across d there; every projectile up to {j:.4g} cm is below its own limit and "
        "every larger one above it, so perforation starts at S/30, but no diameter equals its own limit"
        for j in jump[~found]]
    both = far & near
    note[both] = [
        f"two fixed points (r_S/D < 1 where S/d passes 30, so the limit jumps up at S/30 = {j:.4g} cm): the "
        f"smaller, {d:.4g} cm, is taken; projectiles from {j:.4g} cm up to the larger are below their own limit again"
        for j, d in zip(jump[both], root[both])]
    return HypervelocityLimit(diameter=np.where(found, root, np.nan), threshold=np.where(found, root, jump),
                              note=note)


JSC2011 = register(WhippleEquation(
    name="jsc2011",
    title="JSC Whipple, Ryan & Christiansen 2011",
    ballistic_max_km_s=V_BALLISTIC_MAX_KM_S,
    hypervelocity=_hypervelocity_limit,
))
