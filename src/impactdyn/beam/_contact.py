"""Contact laws between the beam's stop point and the rigid stop (one registry).

Two kinds:

* **impulsive** laws (``momentum``, IMPACTC) act at an instant: the simulator
  locates g = 0 with ġ < 0 and applies the momentum balance
  ``M Δv = Jᵀ P``, ``J v⁺ = −e J v⁻`` (docs/theory/beam.md, eq. (7)) with the law's restitution e(v);
* **compliant** laws (``hertz``, ``hunt_crossley``, ``lankarani_nikravesh``) give a
  force F(δ, δ̇) ≥ 0 of the penetration δ = −g > 0 and its rate δ̇ = −ġ, integrated
  with the equations of motion. Their force kernels are numba functions of
  ``(delta, delta_dot, v0, params)`` where v0 is the approach speed at first touch,
  reached through :func:`force_kernel` by the law's ``kernel_id``.

Every compliant law also supplies ``release(delta, delta_dot, v0, params)``, a
function with the sign of F for δ > 0 that is smooth through F = 0: contact ends
when it crosses zero (the surface would pull) or when δ returns to zero.
"""

from __future__ import annotations

import abc
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numba import njit

from impactdyn._registry import Registry

#: Registered contact laws by name (the case key ``model``; :class:`impactdyn._registry.Registry`).
CONTACT_LAWS: Registry[type["ContactLaw"]] = Registry("contact law", "model")
# kernel ids: compiled code dispatches on an integer (a first-class function
# argument would be re-typed by numba on every call from Python)
NO_FORCE, HERTZ, POWER_LAW = 0, 1, 2



def register_contact(name: str):
    """Class decorator: ``CONTACT_LAWS.register(name, cls)``."""

    def deco(cls):
        cls.name = name
        return CONTACT_LAWS.register(name, cls)

    return deco


class ContactLaw(abc.ABC):
    """Base class; ``impulsive`` selects the simulator's treatment."""

    name: ClassVar[str]
    impulsive: ClassVar[bool]
    kernel_id: ClassVar[int]

    @abc.abstractmethod
    def params(self) -> np.ndarray:
        """The law's parameters packed for its kernels, shape ``(m,)``."""


# --------------------------------------------------------------------------- impulsive


def listing_restitution(v: float) -> float:
    """Velocity-dependent restitution of IMPACTC (the 1988 report, listing TRESP).

    e(v) = 2.578 v² − 1.7428 v + 1 for v < 0.2 m/s, else 0.5014 v^−0.25,
    v = |ġ⁻| the approach speed of the stop point in m/s. The two branches meet
    within 0.005 at 0.2 m/s; e → 1 as v → 0.
    """
    v = abs(v)
    if v < 0.2:
        return 2.578 * v * v - 1.7428 * v + 1.0
    return 0.5014 * v**-0.25


@register_contact("momentum")
@dataclass(frozen=True)
class Momentum(ContactLaw):
    """Momentum balance with a coefficient of restitution (IMPACTC).

    ``restitution`` is a constant e, or ``None`` for the listing's law
    :func:`listing_restitution`.
    """

    restitution: float | None = None
    impulsive: ClassVar[bool] = True
    kernel_id: ClassVar[int] = NO_FORCE

    def params(self) -> np.ndarray:
        return np.zeros(1)

    def e(self, v_approach: float) -> float:
        return listing_restitution(v_approach) if self.restitution is None else self.restitution


# --------------------------------------------------------------------------- compliant


@njit(cache=True, inline="always")
def _hertz_force(delta, delta_dot, v0, p):
    # p = (k, c): F = k δ^{3/2} + ¾ c k δ δ̇   (IMPACTB, listing EQNS)
    return p[0] * delta * (np.sqrt(delta) + 0.75 * p[1] * delta_dot)


@njit(cache=True, inline="always")
def _hertz_release(delta, delta_dot, v0, p):
    return np.sqrt(max(delta, 0.0)) + 0.75 * p[1] * delta_dot


@njit(cache=True, inline="always")
def _power_force(delta, delta_dot, v0, p):
    # p = (k, n, D·v0): F = k δⁿ (1 + D δ̇), D = p[2]/v0
    return p[0] * delta ** p[1] * (1.0 + p[2] / v0 * delta_dot)


@njit(cache=True, inline="always")
def _power_release(delta, delta_dot, v0, p):
    return 1.0 + p[2] / v0 * delta_dot



@njit(cache=True, inline="always")
def force_kernel(law_id, delta, delta_dot, v0, p):
    """Unclipped force of law ``law_id`` at penetration δ and rate δ̇."""
    if law_id == HERTZ:
        return _hertz_force(delta, delta_dot, v0, p)
    if law_id == POWER_LAW:
        return _power_force(delta, delta_dot, v0, p)
    return 0.0


@njit(cache=True, inline="always")
def release_kernel(law_id, delta, delta_dot, v0, p):
    """Release indicator (sign of F for δ > 0, smooth through F = 0)."""
    if law_id == HERTZ:
        return _hertz_release(delta, delta_dot, v0, p)
    if law_id == POWER_LAW:
        return _power_release(delta, delta_dot, v0, p)
    return 1.0


class CompliantLaw(ContactLaw):
    """A force law F(δ, δ̇; v0) with compiled kernels."""

    impulsive: ClassVar[bool] = False

    def force(self, delta: float, delta_dot: float, v0: float) -> float:
        """F ≥ 0 for δ > 0 and a positive release indicator, else 0 (N)."""
        if delta <= 0.0:
            return 0.0
        return max(0.0, force_kernel(self.kernel_id, delta, delta_dot, v0, self.params()))


@register_contact("hertz")
@dataclass(frozen=True)
class Hertz(CompliantLaw):
    """Hertzian spring–dashpot of IMPACTB: F = k δ^{3/2} + ¾ c k δ δ̇.

    k in N/m^{3/2}; c in s/m (the IMPACTB damping coefficient, so that the
    dashpot is ¾ c times the local stiffness k δ).
    """

    stiffness: float
    damping: float = 0.0
    kernel_id = HERTZ

    def params(self) -> np.ndarray:
        return np.array([self.stiffness, self.damping])


@dataclass(frozen=True)
class PowerLaw(CompliantLaw):
    """F = k δⁿ (1 + D δ̇) with D = ``damping_factor(e)``/v₀ (v₀: approach speed at touch)."""

    stiffness: float
    exponent: float = 1.5
    restitution: float = 0.8
    kernel_id = POWER_LAW

    @staticmethod
    def damping_factor(e: float) -> float:
        raise TypeError("use a registered power law")  # pragma: no cover

    def params(self) -> np.ndarray:
        return np.array([self.stiffness, self.exponent, self.damping_factor(self.restitution)])


@register_contact("hunt_crossley")
@dataclass(frozen=True)
class HuntCrossley(PowerLaw):
    """Hunt & Crossley (1975): F = k δⁿ (1 + D δ̇), D = 3(1 − e)/(2 v₀)."""

    @staticmethod
    def damping_factor(e: float) -> float:
        return 1.5 * (1.0 - e)


@register_contact("lankarani_nikravesh")
@dataclass(frozen=True)
class LankaraniNikravesh(PowerLaw):
    """Lankarani & Nikravesh (1990): F = k δⁿ (1 + D δ̇), D = 3(1 − e²)/(4 v₀)."""

    @staticmethod
    def damping_factor(e: float) -> float:
        return 0.75 * (1.0 - e * e)
