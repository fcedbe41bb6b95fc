"""Ballistic-limit curves d_c(V) and their velocity grid."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from impactdyn.ble import _check

#: Default velocity grid of the curves: 1–15 km/s every 0.05 km/s.
DEFAULT_VELOCITIES_KM_S = np.linspace(1.0, 15.0, 281)


def curve_velocities(velocities, extra=()) -> np.ndarray:
    """Sorted, de-duplicated velocity grid; ``extra`` points inside its range are added."""
    v = np.unique(_check.positive_array("velocities", DEFAULT_VELOCITIES_KM_S if velocities is None
                                        else velocities).ravel())
    inside = [x for x in extra if v[0] <= x <= v[-1]]
    return np.union1d(v, inside)


def _json_floats(a: np.ndarray) -> list:
    """A list of floats with ``None`` for NaN (JSON has no NaN)."""
    return [None if np.isnan(x) else float(x) for x in a]


@dataclass(frozen=True)
class BallisticLimitCurve:
    """d_c(V) at one obliquity and projectile density.

    ``critical_diameter_cm`` is NaN where the equation has no fixed point (the 2011 Whipple
    form, :mod:`impactdyn.ble._jsc2011`); ``threshold_cm`` is the diameter above which a
    sphere perforates, equal to d_c wherever that exists.  ``equation`` is the title of
    the equation and ``equation_name`` its registry name (``None`` for a single wall).
    ``regime`` holds the regime of each point and ``regime_boundaries_km_s`` the two
    boundary speeds for a Whipple shield; both are ``None`` for a single wall, which has
    one equation at all speeds.
    """

    velocity_km_s: np.ndarray
    critical_diameter_cm: np.ndarray
    threshold_cm: np.ndarray
    obliquity_deg: float
    projectile_density: float
    equation: str
    equation_name: str | None = None
    regime: np.ndarray | None = None
    regime_boundaries_km_s: tuple[float, float] | None = None

    def as_dict(self) -> dict:
        out = {
            "equation": self.equation,
            "equation_name": self.equation_name,
            "obliquity_deg": self.obliquity_deg,
            "projectile_density_g_cm3": self.projectile_density,
            "velocity_km_s": self.velocity_km_s.tolist(),
            "critical_diameter_cm": _json_floats(self.critical_diameter_cm),
            "threshold_cm": _json_floats(self.threshold_cm),
        }
        if self.regime is not None:
            out["regime"] = [str(r) for r in self.regime]
            out["regime_boundaries_km_s"] = list(self.regime_boundaries_km_s)
        return out
