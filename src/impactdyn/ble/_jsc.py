r"""NASA JSC ballistic limit equations for the aluminium Whipple shield.

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
labelled (W1)–(W3) below and in the functions that evaluate them.

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

Issue 4 acceptance example (bumper 0.127 cm Al, wall 0.3175 cm, σ = 40 ksi, θ = 25°,
ρ_p = ρ_b = 2.7 g/cm³, S = 10 cm): at 7 km/s V_n = 6.344 km/s, so the point lies in
the *shatter* regime (W2), d_c = 0.521267 cm; at 10 km/s V_n = 9.063 km/s, (W3) gives
d_c = 0.482295 cm.  ρ_b = 2.713 gives 0.521011 and 0.482038 cm — both densities
reproduce the issue's 0.521 and 0.482 cm.  With S = 10.16 cm (bumper back to wall
front, the report's Appendix A geometry) d_c = 0.523808 and 0.484854 cm, 3 × 10⁻³ cm
above the issue's numbers, which are therefore for S = 10 cm; the Table 2 verdicts
(0.575 and 0.530 cm perforate, 0.475 and 0.430 cm do not) hold for either spacing.
A (cos θ)^{-1/3} obliquity factor in (W3), found in some re-statements, would give
0.4667 cm at 10 km/s and does not reproduce the issue.

Validity: the equations were fitted to aluminium-on-aluminium tests; the handbook's
analysis program caps θ at 65° for Whipple shields (NASA/TM-2009-214789) — we do not
cap θ, callers who want that should pass ``min(θ, 65)``.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from enum import Enum

import numpy as np

from impactdyn.ble import _check

#: Upper end of the ballistic regime and lower end of the hypervelocity regime,
#: as normal velocity components V cos θ (km/s).
V_BALLISTIC_MAX_KM_S = 3.0
V_HYPERVELOCITY_MIN_KM_S = 7.0

#: Default projectile density: aluminium (g/cm³).
ALUMINIUM_DENSITY_G_CM3 = 2.7


class Regime(str, Enum):
    """Velocity regime of the JSC Whipple equations (on V cos θ)."""

    BALLISTIC = "ballistic"          # V_n ≤ 3 km/s: projectile stays intact (W1)
    SHATTER = "shatter"              # 3 < V_n < 7 km/s: fragmentation / partial melt (W2)
    HYPERVELOCITY = "hypervelocity"  # V_n ≥ 7 km/s: melt / vaporisation (W3)

    def __str__(self) -> str:
        return self.value


_REGIMES = np.array(list(Regime), dtype=object)


@dataclass(frozen=True)
class WhippleShield:
    """A bumper and a rear wall at standoff S (all values > 0, literature units).

    Attributes
    ----------
    bumper_thickness_cm : t_b (cm)
    wall_thickness_cm : t_w (cm)
    spacing_cm : S, the standoff between bumper and rear wall (cm)
    wall_yield_ksi : σ, the rear wall's yield stress (ksi; 1 ksi = 6.895 MPa)
    bumper_density_g_cm3 : ρ_b (g/cm³), aluminium by default
    wall_density_g_cm3 : ρ_w (g/cm³); not used by (W1)–(W3), but by the single-wall
        (rear-wall-only) equation, see :func:`impactdyn.ble.rear_wall`.
    """

    bumper_thickness_cm: float
    wall_thickness_cm: float
    spacing_cm: float
    wall_yield_ksi: float
    bumper_density_g_cm3: float = ALUMINIUM_DENSITY_G_CM3
    wall_density_g_cm3: float = ALUMINIUM_DENSITY_G_CM3

    def __post_init__(self) -> None:
        for f in fields(self):
            object.__setattr__(self, f.name, _check.positive(f.name, getattr(self, f.name)))

    def as_dict(self) -> dict[str, float]:
        return {f.name: getattr(self, f.name) for f in fields(self)}


def normal_velocity(velocity_km_s, obliquity_deg=0.0):
    """V_n = V cos θ (km/s), the component that selects the regime."""
    v = _check.positive_array("velocity_km_s", velocity_km_s)
    th = _check.obliquity(obliquity_deg)
    return _check.result(v * np.cos(np.radians(th)), v, th)


def regime_boundaries(obliquity_deg=0.0):
    """Total velocities (km/s) at the regime boundaries: (3/cos θ, 7/cos θ)."""
    th = _check.obliquity(obliquity_deg)
    c = np.cos(np.radians(th))
    return (_check.result(V_BALLISTIC_MAX_KM_S / c, th),
            _check.result(V_HYPERVELOCITY_MIN_KM_S / c, th))


def regime(velocity_km_s, obliquity_deg=0.0):
    """The :class:`Regime` of each impact (a ``Regime``, or an object array of them).

    Ballistic for V cos θ ≤ 3 km/s, hypervelocity for V cos θ ≥ 7 km/s, shatter between.
    """
    v = _check.positive_array("velocity_km_s", velocity_km_s)
    th = _check.obliquity(obliquity_deg)
    vn = v * np.cos(np.radians(th))
    index = (vn > V_BALLISTIC_MAX_KM_S).astype(int) + (vn >= V_HYPERVELOCITY_MIN_KM_S)
    return _REGIMES[index]  # a 0-d index gives the Regime itself


def _ballistic(shield: WhippleShield, v, cos_t, rho_p):
    """(W1): d_c = [(t_w (σ/40)^{1/2} + t_b) / (0.6 (cos θ)^{5/3} ρ_p^{1/2} V^{2/3})]^{18/19}."""
    resist = shield.wall_thickness_cm * np.sqrt(shield.wall_yield_ksi / 40.0) + shield.bumper_thickness_cm
    return (resist / (0.6 * cos_t ** (5.0 / 3.0) * np.sqrt(rho_p) * v ** (2.0 / 3.0))) ** (18.0 / 19.0)


def _hypervelocity(shield: WhippleShield, v, cos_t, rho_p):
    """(W3): d_c = 3.918 t_w^{2/3} ρ_p^{-1/3} ρ_b^{-1/9} (V cos θ)^{-2/3} S^{1/3} (σ/70)^{1/3}."""
    return (3.918 * shield.wall_thickness_cm ** (2.0 / 3.0) * rho_p ** (-1.0 / 3.0)
            * shield.bumper_density_g_cm3 ** (-1.0 / 9.0) * (v * cos_t) ** (-2.0 / 3.0)
            * shield.spacing_cm ** (1.0 / 3.0) * (shield.wall_yield_ksi / 70.0) ** (1.0 / 3.0))


def critical_diameter(shield: WhippleShield, velocity_km_s, obliquity_deg=0.0,
                      projectile_density=ALUMINIUM_DENSITY_G_CM3):
    """Critical projectile diameter d_c (cm) of a Whipple shield, JSC equations (W1)–(W3).

    Parameters
    ----------
    shield : WhippleShield
    velocity_km_s : impact speed V (km/s), > 0; scalar or array
    obliquity_deg : θ from the target normal (degrees), 0 ≤ θ < 90; scalar or array
    projectile_density : ρ_p (g/cm³), > 0; scalar or array

    The arguments broadcast against each other; the result is a ``float`` when all are
    scalars.  A sphere of diameter d perforates the rear wall when d > d_c (see
    :func:`perforates`).  Equations, regimes and obliquity conventions: module docstring
    (Christiansen 1993; NASA/TM-2009-214785 §4).
    """
    if not isinstance(shield, WhippleShield):
        raise TypeError(f"shield must be a WhippleShield, not {type(shield).__name__}")
    v = _check.positive_array("velocity_km_s", velocity_km_s)
    th = _check.obliquity(obliquity_deg)
    rho_p = _check.positive_array("projectile_density", projectile_density)
    v_b, th_b, rho_b = np.broadcast_arrays(v, th, rho_p)
    cos_t = np.cos(np.radians(th_b))
    vn = v_b * cos_t
    v_lo = V_BALLISTIC_MAX_KM_S / cos_t
    v_hi = V_HYPERVELOCITY_MIN_KM_S / cos_t
    # (W2): linear in V between (W1) at V_lo and (W3) at V_hi
    d_lo = _ballistic(shield, v_lo, cos_t, rho_b)
    d_hi = _hypervelocity(shield, v_hi, cos_t, rho_b)
    w = (v_b - v_lo) / (v_hi - v_lo)
    d = d_lo + (d_hi - d_lo) * w
    low = vn <= V_BALLISTIC_MAX_KM_S
    high = vn >= V_HYPERVELOCITY_MIN_KM_S
    d = np.where(low, _ballistic(shield, v_b, cos_t, rho_b), d)
    d = np.where(high, _hypervelocity(shield, v_b, cos_t, rho_b), d)
    return _check.result(d, v, th, rho_p)


def perforates(shield: WhippleShield, diameter_cm, velocity_km_s, obliquity_deg=0.0,
               projectile_density=ALUMINIUM_DENSITY_G_CM3):
    """True where a sphere of ``diameter_cm`` perforates the rear wall (d > d_c)."""
    d = _check.positive_array("diameter_cm", diameter_cm)
    dc = critical_diameter(shield, velocity_km_s, obliquity_deg, projectile_density)
    out = d > dc
    return bool(out) if np.ndim(out) == 0 else out


@dataclass(frozen=True)
class BallisticLimitCurve:
    """d_c(V) at one obliquity and projectile density.

    ``regime`` holds the JSC regime of each point for a Whipple shield and is ``None``
    for a single wall, which has one equation at all speeds.
    """

    velocity_km_s: np.ndarray
    critical_diameter_cm: np.ndarray
    obliquity_deg: float
    projectile_density: float
    equation: str
    regime: np.ndarray | None = None

    def regime_boundaries(self) -> tuple[float, float] | None:
        """(3/cos θ, 7/cos θ) in km/s for a Whipple curve, else ``None``."""
        return None if self.regime is None else regime_boundaries(self.obliquity_deg)

    def as_dict(self) -> dict:
        out = {
            "equation": self.equation,
            "obliquity_deg": self.obliquity_deg,
            "projectile_density_g_cm3": self.projectile_density,
            "velocity_km_s": self.velocity_km_s.tolist(),
            "critical_diameter_cm": self.critical_diameter_cm.tolist(),
        }
        if self.regime is not None:
            out["regime"] = [str(r) for r in self.regime]
            out["regime_boundaries_km_s"] = list(self.regime_boundaries())
        return out


#: Default velocity grid of the curves: 1–15 km/s every 0.05 km/s.
DEFAULT_VELOCITIES_KM_S = np.linspace(1.0, 15.0, 281)


def curve_velocities(velocities, extra=()) -> np.ndarray:
    """Sorted, de-duplicated velocity grid; ``extra`` points inside its range are added."""
    v = np.unique(_check.positive_array("velocities", DEFAULT_VELOCITIES_KM_S if velocities is None
                                        else velocities).ravel())
    inside = [x for x in extra if v[0] <= x <= v[-1]]
    return np.union1d(v, inside)


def ballistic_limit_curve(shield: WhippleShield, velocities=None, obliquity_deg: float = 0.0,
                          projectile_density: float = ALUMINIUM_DENSITY_G_CM3) -> BallisticLimitCurve:
    """The Whipple ballistic-limit curve d_c(V), equations (W1)–(W3).

    ``velocities`` (km/s) defaults to 1–15 km/s; the regime boundaries 3/cos θ and
    7/cos θ are added to the grid where they fall inside it, so a plot shows the kinks.
    """
    th = _check.scalar_obliquity(obliquity_deg)
    rho_p = _check.positive("projectile_density", projectile_density)
    v = curve_velocities(velocities, regime_boundaries(th))
    return BallisticLimitCurve(
        velocity_km_s=v,
        critical_diameter_cm=np.asarray(critical_diameter(shield, v, th, rho_p), dtype=float),
        obliquity_deg=th,
        projectile_density=rho_p,
        equation="NASA JSC Whipple (Christiansen 1993; NASA/TM-2009-214785 §4)",
        regime=np.asarray(regime(v, th), dtype=object),
    )
