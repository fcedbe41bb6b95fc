"""The Whipple shield the ballistic limit equations describe (literature units)."""

from __future__ import annotations

from dataclasses import dataclass, fields

from impactdyn.ble import _check

#: Default projectile, bumper and wall density: aluminium (g/cm³).
ALUMINIUM_DENSITY_G_CM3 = 2.7


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
    wall_density_g_cm3 : ρ_w (g/cm³); not used by the Whipple equations, but by the
        single-wall (rear-wall-only) equation, see :func:`impactdyn.ble.rear_wall`.

    The equations read the first five attributes only; the test database
    (:class:`impactdyn.ble.ShotDatabase`) carries the same five as per-shot arrays.
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
