r"""What the NASA JSC Whipple-shield equations share: regimes, the 65° cap, (W1), the shatter blend.

Both registered equations, Christiansen 1993 (:mod:`impactdyn.ble._jsc`) and Ryan &
Christiansen 2011 (:mod:`impactdyn.ble._jsc2011`), have one structure; the normal velocity
V_n = V cos θ selects the regime::

    ballistic       V_n ≤ V_LV           (W1)
    shatter         V_LV < V_n < 7 km/s  linear in V between (W1) at V_lo = V_LV / cos θ and
                                         the hypervelocity limit at V_hi = 7 / cos θ
    hypervelocity   V_n ≥ 7 km/s         the equation's own hypervelocity limit

    (W1) d_c = [ (t_w (σ/40)^{1/2} + t_b) / (0.6 (cos θ)^{5/3} ρ_p^{1/2} V^{2/3}) ]^{18/19}

V_LV is 3 km/s in the 1993 equations and 2.6 km/s in the 2011 form.  Units: cm, g/cm³,
km/s, ksi; θ from the target normal.

Obliquity cap: θ is replaced by min(θ, 65°) everywhere, in the regime boundaries too
(Christiansen 1993 eq. 12 and NASA/TM-2009-214785 eq. 4-26, as cited in
docs/theory/ble.md; the ballistic limit analysis program of NASA/TM-2009-214789 applies the same cap
to Whipple shields).  Beyond 65° the equations were never fitted, and the uncapped
(cos θ)^{-2/3} of the hypervelocity limit grows without bound toward 90°.

Each equation supplies its hypervelocity limit as a :class:`HypervelocityLimit`: the
critical diameter where it is defined (NaN where the equation has no fixed point, see
:mod:`impactdyn.ble._jsc2011`), the diameter above which projectiles perforate, and a note
saying why the two differ where they do.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from enum import Enum
from typing import NamedTuple

import numpy as np

#: Largest obliquity the Whipple equations take; larger angles are evaluated at 65°.
MAX_OBLIQUITY_DEG = 65.0
#: Lower end of the hypervelocity regime, on V cos θ (km/s), in both equations.
V_HYPERVELOCITY_MIN_KM_S = 7.0
#: The attributes of a shield the equations read (scalars, or arrays that broadcast).
SHIELD_ATTRIBUTES = ("bumper_thickness_cm", "wall_thickness_cm", "spacing_cm", "wall_yield_ksi",
                     "bumper_density_g_cm3")


class Regime(str, Enum):
    """Velocity regime of the JSC Whipple equations (on V cos θ)."""

    BALLISTIC = "ballistic"          # projectile stays intact (W1)
    SHATTER = "shatter"              # fragmentation / partial melt: linear blend
    HYPERVELOCITY = "hypervelocity"  # melt / vaporisation

    def __str__(self) -> str:
        return self.value


_REGIMES = np.array(list(Regime), dtype=object)


def capped_cos(obliquity_deg):
    """cos(min(θ, 65°)), the obliquity factor of every Whipple equation."""
    return np.cos(np.radians(np.minimum(obliquity_deg, MAX_OBLIQUITY_DEG)))


def ballistic_diameter(shield, v, cos_t, rho_p):
    """(W1): d_c = [(t_w (σ/40)^{1/2} + t_b) / (0.6 (cos θ)^{5/3} ρ_p^{1/2} V^{2/3})]^{18/19}."""
    resist = shield.wall_thickness_cm * np.sqrt(shield.wall_yield_ksi / 40.0) + shield.bumper_thickness_cm
    return (resist / (0.6 * cos_t ** (5.0 / 3.0) * np.sqrt(rho_p) * v ** (2.0 / 3.0))) ** (18.0 / 19.0)


class HypervelocityLimit(NamedTuple):
    """An equation's hypervelocity limit, elementwise.

    ``diameter``: the critical diameter (cm), NaN where the equation has none;
    ``threshold``: the diameter (cm) above which the equation calls perforation, equal to
    ``diameter`` wherever that is a single value; ``note``: object array, ``None`` or why not.
    """

    diameter: np.ndarray
    threshold: np.ndarray
    note: np.ndarray


@dataclass(frozen=True)
class BallisticLimit:
    """Elementwise result of a Whipple equation (arrays of the broadcast input shape).

    ``critical_diameter_cm``: d_c, NaN where the equation has no fixed point;
    ``threshold_cm``: the diameter above which a sphere perforates (= d_c wherever d_c is a
    single value); ``regime``: object array of :class:`Regime`; ``note``: object array,
    ``None`` or a sentence naming the regime and why d_c is missing or not unique.
    """

    critical_diameter_cm: np.ndarray
    threshold_cm: np.ndarray
    regime: np.ndarray
    note: np.ndarray


@dataclass(frozen=True)
class WhippleEquation:
    """One JSC Whipple-shield equation: its name, its V_LV, its hypervelocity limit.

    ``hypervelocity(shield, v, cos_t, rho_p)`` returns the :class:`HypervelocityLimit` at
    speeds v with the capped obliquity factor cos_t (arrays of one shape).
    """

    name: str
    title: str
    ballistic_max_km_s: float
    hypervelocity: Callable[..., HypervelocityLimit]

    def regime_boundaries(self, cos_t):
        """Total velocities (km/s) at the regime ends: (V_LV / cos θ, 7 / cos θ)."""
        return self.ballistic_max_km_s / cos_t, V_HYPERVELOCITY_MIN_KM_S / cos_t

    def regime(self, v, obliquity_deg) -> np.ndarray:
        """Object array of :class:`Regime` (a 0-d index gives the member itself)."""
        vn = v * capped_cos(obliquity_deg)
        return _REGIMES[self._regime_index(vn)]

    def _regime_index(self, vn):
        return (vn > self.ballistic_max_km_s).astype(int) + (vn >= V_HYPERVELOCITY_MIN_KM_S)

    def limit(self, shield, v, obliquity_deg, rho_p) -> BallisticLimit:
        """The limit at speeds ``v``, angles ``obliquity_deg``, densities ``rho_p`` (checked arrays)."""
        shape = np.broadcast_shapes(np.shape(v), np.shape(obliquity_deg), np.shape(rho_p),
                                    *(np.shape(getattr(shield, a)) for a in SHIELD_ATTRIBUTES))
        v, cos_t, rho_p = (np.broadcast_to(x, shape) for x in (v, capped_cos(obliquity_deg), rho_p))
        v_lo, v_hi = self.regime_boundaries(cos_t)
        index = self._regime_index(v * cos_t)
        at_v = self.hypervelocity(shield, v, cos_t, rho_p)
        at_hi = self.hypervelocity(shield, v_hi, cos_t, rho_p)
        low = ballistic_diameter(shield, v, cos_t, rho_p)
        low_end = ballistic_diameter(shield, v_lo, cos_t, rho_p)
        w = (v - v_lo) / (v_hi - v_lo)

        def blend(hv_at_v, hv_at_hi):
            return np.choose(index, [low, low_end + (hv_at_hi - low_end) * w, hv_at_v])

        note = np.full(shape, None, dtype=object)
        hyper = (index == 2) & (at_v.note != None)  # noqa: E711 (elementwise on an object array)
        note[hyper] = "hypervelocity regime: " + at_v.note[hyper]
        shatter = (index == 1) & (at_hi.note != None)  # noqa: E711
        note[shatter] = [f"shatter regime, at its hypervelocity end V = 7/cos θ = {vh:.4g} km/s: {n}"
                         for vh, n in zip(v_hi[shatter], at_hi.note[shatter])]
        return BallisticLimit(critical_diameter_cm=blend(at_v.diameter, at_hi.diameter),
                              threshold_cm=blend(at_v.threshold, at_hi.threshold),
                              regime=np.asarray(_REGIMES[index], dtype=object), note=note)
