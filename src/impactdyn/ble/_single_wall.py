r"""Cour-Palais single-wall (monolithic plate) ballistic limit equation.

Sources
-------
* B.G. Cour-Palais, "Hypervelocity impact in metals, glass and composites",
  Int. J. Impact Eng. 5 (1987) 221–237 — the penetration-depth equation.
* E.L. Christiansen, "Shield sizing and response equations", NASA JSC SN3-91-42
  (1991), and "Handbook for designing MMOD protection", NASA/TM-2009-214785 (2009),
  §4, single-wall equation (the "modified Cour-Palais" form used below, with the
  thickness multipliers k for the failure modes).

The equation numbers of those reports are not repeated here (the texts could not be
checked line by line where this module was written); the equation is labelled (S1).

Units: cm, g/cm³, km/s, Brinell hardness number; θ from the target normal::

    (S1) p_∞ = 5.24 d^{19/18} HB^{-1/4} (ρ_p/ρ_t)^{β} (V cos θ / C)^{2/3}
         β = 1/2 for ρ_p/ρ_t < 1.5, β = 2/3 for ρ_p/ρ_t ≥ 1.5

p_∞ is the crater depth in a semi-infinite target of Brinell hardness HB, density ρ_t
and speed of sound C (km/s).  A plate of thickness t fails when t < k p_∞, with
k = 1.8 for perforation, 2.2 for detached spall and 3.0 for incipient spall; solving
t = k p_∞ for d gives the critical diameter

    d_c = [ t / (5.24 k HB^{-1/4} (ρ_p/ρ_t)^{β} (V cos θ / C)^{2/3}) ]^{18/19}.

Applied to the rear wall of a Whipple shield alone (:func:`rear_wall`) it tells how
much the bumper buys.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from enum import Enum

import numpy as np

from impactdyn._errors import InputError
from impactdyn.ble import _check
from impactdyn.ble._curve import BallisticLimitCurve, curve_velocities
from impactdyn.ble._shield import ALUMINIUM_DENSITY_G_CM3, WhippleShield

#: Brinell hardness of Al 6061-T6 (ASM handbook value, as tabulated with the NASA
#: ballistic-limit program's material data).
AL6061_T6_BRINELL = 95.0
#: Brinell hardness with (S1) of the material library's aluminium walls (:mod:`impactdyn.materials`
#: names; ASM handbook values: 6061-T6 95, 2024-T3 and -T4 120).
BRINELL_HARDNESS = {"al6061-t6": AL6061_T6_BRINELL, "al2024-t4": 120.0}
#: Speed of sound of aluminium used with (S1), ≈ (E/ρ)^{1/2} = (68.9 GPa / 2.7 g/cm³)^{1/2}
#: = 5.05 km/s, rounded as usually quoted.
AL_SOUND_SPEED_KM_S = 5.1


class FailureMode(str, Enum):
    """Failure criterion of (S1) and its thickness multiplier ``k`` (t = k p_∞)."""

    PERFORATION = "perforation"
    DETACHED_SPALL = "detached_spall"
    INCIPIENT_SPALL = "incipient_spall"

    @property
    def k(self) -> float:
        return {"perforation": 1.8, "detached_spall": 2.2, "incipient_spall": 3.0}[self.value]

    def __str__(self) -> str:
        return self.value


@dataclass(frozen=True)
class SingleWall:
    """A monolithic plate (all values > 0): t (cm), ρ_t (g/cm³), HB, C (km/s).

    The defaults describe Al 6061-T6.
    """

    thickness_cm: float
    density_g_cm3: float = ALUMINIUM_DENSITY_G_CM3
    brinell_hardness: float = AL6061_T6_BRINELL
    sound_speed_km_s: float = AL_SOUND_SPEED_KM_S

    def __post_init__(self) -> None:
        for f in fields(self):
            object.__setattr__(self, f.name, _check.positive(f.name, getattr(self, f.name)))

    def as_dict(self) -> dict[str, float]:
        return {f.name: getattr(self, f.name) for f in fields(self)}


def rear_wall(shield: WhippleShield, brinell_hardness: float = AL6061_T6_BRINELL,
              sound_speed_km_s: float = AL_SOUND_SPEED_KM_S) -> SingleWall:
    """The rear wall of ``shield`` on its own, as a single wall (no bumper)."""
    return SingleWall(shield.wall_thickness_cm, shield.wall_density_g_cm3, brinell_hardness, sound_speed_km_s)


def _mode(mode) -> FailureMode:
    try:
        return FailureMode(mode)
    except ValueError:
        raise InputError(f"mode = {mode!r}: must be one of "
                         + ", ".join(m.value for m in FailureMode)) from None


def _density_factor(rho_p, rho_t: float):
    """(ρ_p/ρ_t)^β of (S1), β = 1/2 below a density ratio of 1.5 and 2/3 from it on."""
    ratio = rho_p / rho_t
    return ratio ** np.where(ratio < 1.5, 0.5, 2.0 / 3.0)


def penetration_depth(wall: SingleWall, diameter_cm, velocity_km_s, obliquity_deg=0.0,
                      projectile_density=ALUMINIUM_DENSITY_G_CM3):
    """Semi-infinite crater depth p_∞ (cm), equation (S1); arguments broadcast."""
    d = _check.positive_array("diameter_cm", diameter_cm)
    v = _check.positive_array("velocity_km_s", velocity_km_s)
    th = _check.obliquity(obliquity_deg)
    rho_p = _check.positive_array("projectile_density", projectile_density)
    vn = v * np.cos(np.radians(th))
    p = (5.24 * d ** (19.0 / 18.0) * wall.brinell_hardness ** -0.25 * _density_factor(rho_p, wall.density_g_cm3)
         * (vn / wall.sound_speed_km_s) ** (2.0 / 3.0))
    return _check.result(p, d, v, th, rho_p)


def single_wall_critical_diameter(wall: SingleWall, velocity_km_s, obliquity_deg=0.0,
                                  projectile_density=ALUMINIUM_DENSITY_G_CM3, mode="perforation"):
    """Critical diameter d_c (cm) of a single wall, (S1) solved for t = k p_∞.

    d_c = [t / (5.24 k HB^{-1/4} (ρ_p/ρ_t)^β (V cos θ / C)^{2/3})]^{18/19};
    ``mode`` is ``"perforation"`` (k = 1.8), ``"detached_spall"`` (2.2) or
    ``"incipient_spall"`` (3.0).  Arguments broadcast; ``float`` for scalar inputs.
    """
    if not isinstance(wall, SingleWall):
        raise TypeError(f"wall must be a SingleWall, not {type(wall).__name__}")
    k = _mode(mode).k
    v = _check.positive_array("velocity_km_s", velocity_km_s)
    th = _check.obliquity(obliquity_deg)
    rho_p = _check.positive_array("projectile_density", projectile_density)
    vn = v * np.cos(np.radians(th))
    denom = (5.24 * k * wall.brinell_hardness ** -0.25 * _density_factor(rho_p, wall.density_g_cm3)
             * (vn / wall.sound_speed_km_s) ** (2.0 / 3.0))
    return _check.result((wall.thickness_cm / denom) ** (18.0 / 19.0), v, th, rho_p)


def single_wall_perforates(wall: SingleWall, diameter_cm, velocity_km_s, obliquity_deg=0.0,
                           projectile_density=ALUMINIUM_DENSITY_G_CM3, mode="perforation"):
    """True where a sphere of ``diameter_cm`` exceeds the single-wall limit (d > d_c)."""
    d = _check.positive_array("diameter_cm", diameter_cm)
    out = d > single_wall_critical_diameter(wall, velocity_km_s, obliquity_deg, projectile_density, mode)
    return bool(out) if np.ndim(out) == 0 else out


def single_wall_ballistic_limit_curve(wall: SingleWall, velocities=None, obliquity_deg: float = 0.0,
                                      projectile_density: float = ALUMINIUM_DENSITY_G_CM3,
                                      mode="perforation") -> BallisticLimitCurve:
    """d_c(V) of a single wall, (S1); ``velocities`` (km/s) default to 1–15 km/s."""
    th = _check.scalar_obliquity(obliquity_deg)
    rho_p = _check.positive("projectile_density", projectile_density)
    m = _mode(mode)
    v = curve_velocities(velocities)
    dc = np.asarray(single_wall_critical_diameter(wall, v, th, rho_p, m), dtype=float)
    return BallisticLimitCurve(
        velocity_km_s=v,
        critical_diameter_cm=dc,
        threshold_cm=dc,
        obliquity_deg=th,
        projectile_density=rho_p,
        equation=f"Cour-Palais single wall, {m.value} (k = {m.k:g}; NASA/TM-2009-214785 §4)",
    )
