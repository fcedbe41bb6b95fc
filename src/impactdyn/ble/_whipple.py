"""Whipple-shield ballistic limits through a registered equation, selected by name.

Every function takes ``equation``: a registered name (``"jsc1993"``, ``"jsc2011"``; see
:data:`impactdyn.ble.EQUATIONS`) or ``None`` for :data:`impactdyn.ble.DEFAULT_EQUATION`.
Arguments are checked before any arithmetic, and broadcast against each other; results
are a ``float`` (or a ``Regime``) when every argument is a scalar.
"""

from __future__ import annotations

import numpy as np

from impactdyn.ble import _check
from impactdyn.ble._curve import BallisticLimitCurve, curve_velocities
from impactdyn.ble._equation import BallisticLimit, capped_cos
from impactdyn.ble._registry import get_equation
from impactdyn.ble._shield import ALUMINIUM_DENSITY_G_CM3, WhippleShield


def _shield(shield) -> WhippleShield:
    if not isinstance(shield, WhippleShield):
        raise TypeError(f"shield must be a WhippleShield, not {type(shield).__name__}")
    return shield


def normal_velocity(velocity_km_s, obliquity_deg=0.0):
    """V_n = V cos θ (km/s), the component that selects the regime (uncapped θ)."""
    v = _check.positive_array("velocity_km_s", velocity_km_s)
    th = _check.obliquity(obliquity_deg)
    return _check.result(v * np.cos(np.radians(th)), v, th)


def regime_boundaries(obliquity_deg=0.0, equation=None):
    """Total velocities (km/s) at the regime boundaries: (V_LV/cos θ, 7/cos θ), θ capped at 65°.

    V_LV is 3 km/s for ``"jsc1993"`` and 2.6 km/s for ``"jsc2011"``.
    """
    eq = get_equation(equation)
    th = _check.obliquity(obliquity_deg)
    lo, hi = eq.regime_boundaries(capped_cos(th))
    return _check.result(lo, th), _check.result(hi, th)


def regime(velocity_km_s, obliquity_deg=0.0, equation=None):
    """The :class:`Regime` of each impact (a ``Regime``, or an object array of them).

    Ballistic for V cos θ ≤ V_LV, hypervelocity for V cos θ ≥ 7 km/s, shatter between
    (θ capped at 65°).
    """
    eq = get_equation(equation)
    v = _check.positive_array("velocity_km_s", velocity_km_s)
    th = _check.obliquity(obliquity_deg)
    return eq.regime(v, th)


def ballistic_limit(shield: WhippleShield, velocity_km_s, obliquity_deg=0.0,
                    projectile_density=ALUMINIUM_DENSITY_G_CM3, equation=None) -> BallisticLimit:
    """The full answer of a Whipple equation, elementwise (arrays of the broadcast shape).

    :class:`BallisticLimit`: ``critical_diameter_cm`` (NaN where the equation has no fixed
    point), ``threshold_cm`` (above it a sphere perforates), ``regime``, and ``note`` (why
    d_c is missing or not unique there, naming the regime; else ``None``).
    """
    eq = get_equation(equation)
    _shield(shield)
    v = _check.positive_array("velocity_km_s", velocity_km_s)
    th = _check.obliquity(obliquity_deg)
    rho_p = _check.positive_array("projectile_density", projectile_density)
    return eq.limit(shield, v, th, rho_p)


def critical_diameter(shield: WhippleShield, velocity_km_s, obliquity_deg=0.0,
                      projectile_density=ALUMINIUM_DENSITY_G_CM3, equation=None):
    """Critical projectile diameter d_c (cm) of a Whipple shield; NaN where there is none.

    A sphere of diameter d perforates the rear wall when d > d_c (see :func:`perforates`).
    The 2011 form has no fixed point for some shields and speeds: there the result is NaN
    and :func:`ballistic_limit` says why.

    Parameters
    ----------
    shield : WhippleShield
    velocity_km_s : float or array
        Impact speed V (km/s), > 0.
    obliquity_deg : float
        θ from the target normal (degrees), 0 ≤ θ < 90, capped at 65°.
    projectile_density : float or array
        ρ_p (g/cm³), > 0.
    equation : str or None
        A registered name, ``None`` for the default.
    """
    limit = ballistic_limit(shield, velocity_km_s, obliquity_deg, projectile_density, equation)
    return _check.result(limit.critical_diameter_cm, velocity_km_s, obliquity_deg, projectile_density)


def perforates(shield: WhippleShield, diameter_cm, velocity_km_s, obliquity_deg=0.0,
               projectile_density=ALUMINIUM_DENSITY_G_CM3, equation=None):
    """True where a sphere of ``diameter_cm`` perforates the rear wall (d > the threshold)."""
    d = _check.positive_array("diameter_cm", diameter_cm)
    limit = ballistic_limit(shield, velocity_km_s, obliquity_deg, projectile_density, equation)
    out = d > limit.threshold_cm
    return bool(out) if np.ndim(out) == 0 else out


def jsc_verdict(shield: WhippleShield, diameter_cm: float, velocity_km_s: float, obliquity_deg: float = 0.0,
                projectile_density: float = ALUMINIUM_DENSITY_G_CM3, equation: str | None = None) -> dict:
    """One shot against a Whipple equation, as a JSON-ready dict.

    Keys: ``equation`` (its name), ``critical_diameter_cm`` (``None`` where the equation has
    no fixed point), ``threshold_cm`` (the diameter above which it calls perforation, = d_c
    where that exists), ``regime``, ``verdict`` (``"perforation"`` or ``"no perforation"``:
    d > threshold), ``note`` (``None``, or why d_c is missing or not unique).
    """
    eq = get_equation(equation)
    d = _check.positive("diameter_cm", diameter_cm)
    v = _check.positive("velocity_km_s", velocity_km_s)
    th = _check.scalar_obliquity(obliquity_deg)
    rho_p = _check.positive("projectile_density", projectile_density)
    limit = ballistic_limit(shield, v, th, rho_p, eq.name)
    dc = float(limit.critical_diameter_cm)
    threshold = float(limit.threshold_cm)
    return {
        "equation": eq.name,
        "critical_diameter_cm": None if np.isnan(dc) else dc,
        "threshold_cm": threshold,
        "regime": str(limit.regime[()]),
        "verdict": "perforation" if d > threshold else "no perforation",
        "note": limit.note[()],
    }


def ballistic_limit_curve(shield: WhippleShield, velocities=None, obliquity_deg: float = 0.0,
                          projectile_density: float = ALUMINIUM_DENSITY_G_CM3,
                          equation: str | None = None) -> BallisticLimitCurve:
    """The Whipple ballistic-limit curve d_c(V) of an equation.

    ``velocities`` (km/s) defaults to 1–15 km/s; the regime boundaries V_LV/cos θ and
    7/cos θ are added to the grid where they fall inside it, so a plot shows the kinks.
    """
    eq = get_equation(equation)
    th = _check.scalar_obliquity(obliquity_deg)
    rho_p = _check.positive("projectile_density", projectile_density)
    bounds = tuple(float(b) for b in eq.regime_boundaries(capped_cos(th)))
    v = curve_velocities(velocities, bounds)
    limit = ballistic_limit(shield, v, th, rho_p, eq.name)
    return BallisticLimitCurve(
        velocity_km_s=v,
        critical_diameter_cm=limit.critical_diameter_cm,
        threshold_cm=limit.threshold_cm,
        obliquity_deg=th,
        projectile_density=rho_p,
        equation=eq.title,
        equation_name=eq.name,
        regime=limit.regime,
        regime_boundaries_km_s=bounds,
    )
