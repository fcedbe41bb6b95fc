"""The integrator interface and registry: what an integrator receives and returns (docs/theory/debris.md, eq. (3)).

An integrator is a function ``(batch, control) -> (states, t_reached, counts)``
(:data:`IntegratorFn`) registered under a name in :data:`INTEGRATORS` (a
:class:`impactdyn._registry.Registry`, the package's one plug-in idiom; :func:`register_integrator`); :func:`impactdyn.debris.propagate` checks the
particles into a :class:`ParticleBatch`, builds the :class:`StepControl` from
its :class:`~impactdyn.debris.IntegratorOptions` and calls it.  The built-in
integrators register themselves at the bottom of their modules
(:mod:`._splitting`, :mod:`._rk45`, :mod:`._rk4_doubling`; :mod:`._slow_manifold`,
imported by the package's ``__init__``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from impactdyn._errors import InputError
from impactdyn._registry import Registry
from impactdyn.debris._failure import Failure
from impactdyn.debris._particle import STATE_SIZE, ParticleMaterial, inline_kernel, rates_into


@dataclass(frozen=True)
class StepControl:
    """Step-size control shared by all integrators (each reads what applies to it).

    eps: tolerance of the adaptive methods; dt: splitting step, or first step of
    rk45 (µs; scalar or ``(N,)``; None: from the particle's ω̂); steps_per_period:
    splitting steps per 2π/ω̂ when dt is None (None: the method's own default,
    :data:`DEFAULT_STEPS_PER_PERIOD`); max_steps: accepted + rejected steps per
    particle before Failure.STEP_BUDGET; ymxref: legacy's floor of the running
    maxima.  Built by :func:`impactdyn.debris.propagate` from an
    :class:`~impactdyn.debris.IntegratorOptions`, where the defaults and bounds live.
    """

    eps: float
    dt: float | np.ndarray | None
    steps_per_period: float | None
    max_steps: int
    ymxref: float


@dataclass(frozen=True)
class ParticleBatch:
    """What an integrator receives: N particles, all arrays C-contiguous float64.

    y0 ``(N, 33)`` initial states; Jinv ``(N, 3, 3)`` J⁻¹; m, V0 ``(N,)`` mass (g)
    and reference volume (cm³); t_end ``(N,)`` end times (µs); params
    ``(N_PARAMS,)`` packed material; omega_hat ``(N,)`` the bound ω̂ on the
    highest linear frequency (1/µs); j_max ``(N,)`` λ_max(J) (g cm²).
    """

    y0: np.ndarray
    Jinv: np.ndarray
    m: np.ndarray
    V0: np.ndarray
    t_end: np.ndarray
    params: np.ndarray
    omega_hat: np.ndarray
    j_max: np.ndarray

    @classmethod
    def of(cls, states, J, m, t_end, material: ParticleMaterial, phi) -> ParticleBatch:
        """Check the particles of :func:`impactdyn.debris.propagate` and pack them; an :class:`InputError`
        names the array, the first particle that breaks its rule and the value there."""
        y0 = _floats("states", states)
        if y0.ndim != 2 or y0.shape[1] != STATE_SIZE:
            raise InputError(f"propagate: states: shape {y0.shape}, expected (N, {STATE_SIZE}) packed states")
        n = len(y0)
        J = _floats("J", J)
        if J.shape != (n, 3, 3):
            raise InputError(f"propagate: J: shape {J.shape}, expected ({n}, 3, 3) for the {n} states")
        m = _floats("m", m)
        if m.shape != (n,):
            raise InputError(f"propagate: m: shape {m.shape}, expected ({n},) for the {n} states")
        _each("m", m, np.isfinite(m) & (m > 0), "a mass must be finite and > 0")
        t_end = _per_particle("t_end", t_end, n)
        _each("t_end", t_end, np.isfinite(t_end) & (t_end >= 0), "an end time must be finite and >= 0")
        phi = _per_particle("phi", phi, n)
        _each("phi", phi, (phi >= 0) & (phi < 1), "a void fraction must lie in [0, 1)")
        _each("J", J, np.isfinite(J).all(axis=(1, 2)) & np.isclose(J, np.swapaxes(J, 1, 2), rtol=1e-12, atol=0
                                                                  ).all(axis=(1, 2)),
              "an inertia tensor must be finite and symmetric")
        eig = np.linalg.eigvalsh(J) if n else np.ones((0, 3))
        _each("J", eig, eig[:, 0] > 0, "an inertia tensor must be positive definite (its eigenvalues are shown)")
        V0 = np.ascontiguousarray(material.reference_volume(m, phi))
        return cls(
            y0=y0, Jinv=np.ascontiguousarray(np.linalg.inv(J)), m=m, V0=V0, t_end=t_end,
            params=material.packed(),
            omega_hat=np.sqrt(V0 * material.stiffness_bound() / eig[:, 0]), j_max=eig[:, 2].copy())

    def per_particle(self, value) -> np.ndarray:
        """A scalar or ``(N,)`` value as a contiguous ``(N,)`` float array."""
        return np.ascontiguousarray(np.broadcast_to(np.asarray(value, dtype=float), self.m.shape))

    def outputs(self):
        """What an integrator fills in: states (a copy of y0), t_reached ``(N,)``, counts ``(N, 3)``."""
        n = len(self.m)
        return self.y0.copy(), np.zeros(n), np.zeros((n, 3), dtype=np.int64)


@dataclass(frozen=True)
class PropagationStats:
    """Per-particle integration statistics, all ``(N,)``.

    steps: accepted steps; rejected: rejected trial steps; code: :class:`Failure`
    values; t_reached: time the returned state belongs to (t_end when code is 0).
    """

    steps: np.ndarray
    rejected: np.ndarray
    code: np.ndarray
    t_reached: np.ndarray

    @property
    def n_failed(self) -> int:
        return int(np.count_nonzero(self.code))

    def failure_counts(self) -> dict[str, int]:
        """Number of particles per failure kind (kinds that occurred only)."""
        return {Failure(c).name: int(n) for c, n in zip(*np.unique(self.code, return_counts=True))
                if c != Failure.OK}


def _floats(name: str, value) -> np.ndarray:
    """``value`` as a C-contiguous float64 array (an InputError naming ``name`` if it is not one)."""
    try:
        return np.ascontiguousarray(np.asarray(value, dtype=float))
    except (TypeError, ValueError):
        raise InputError(f"propagate: {name}: not an array of numbers") from None


def _per_particle(name: str, value, n: int) -> np.ndarray:
    """A scalar or ``(n,)`` ``value`` as a contiguous ``(n,)`` float array."""
    a = _floats(name, value)
    try:
        return np.ascontiguousarray(np.broadcast_to(a, (n,)))
    except ValueError:
        raise InputError(f"propagate: {name}: shape {a.shape}, expected a number or ({n},)") from None


def _each(name: str, values: np.ndarray, ok: np.ndarray, rule: str) -> None:
    """An InputError naming the first particle where ``ok`` is false and its value of ``name``."""
    if not ok.all():
        i = int(np.argmin(ok))
        raise InputError(f"propagate: {name}: particle {i} of {len(ok)} has {values[i].tolist()}: {rule}")


IntegratorFn = Callable[[ParticleBatch, StepControl], tuple[np.ndarray, np.ndarray, np.ndarray]]
"""(batch, control) -> (states ``(N, 33)``, t_reached ``(N,)``, counts ``(N, 3)``: steps, rejected, code)."""

#: Registered integrators by name (the case key ``method``).
INTEGRATORS: Registry[IntegratorFn] = Registry("integrator", "method")

DEFAULT_STEPS_PER_PERIOD: dict[str, float] = {}
"""Steps per 2π/ω̂ of each splitting integrator when none is given."""

AVERAGING: set[str] = set()
"""Integrators that follow the particles' slow motion only, their elastic ringing averaged out
(``slow``): they do not converge to the full solution of the state equations as the step
shrinks, and are checked against the averaged motion instead."""


def register_integrator(name: str, averaging: bool = False):
    """Decorator: ``INTEGRATORS.register(name, fn)`` (:class:`impactdyn._registry.Registry`), and
    ``averaging``: ``fn`` belongs to :data:`AVERAGING`."""
    def add(fn: IntegratorFn) -> IntegratorFn:
        INTEGRATORS.register(name, fn)
        if averaging:
            AVERAGING.add(name)
        return fn
    return add


# Per particle, a kernel gets the flat state ``y (33,)`` for vector algebra, and
# makes the views it needs once, before the step loop (see _particle).


@inline_kernel
def body_rates(Y, body, Ydot, w):
    """Ẏ = f(Y) for the particle constants body = (J⁻¹, m, V₀, params); rows ``(11, 3)``."""
    rates_into(Y, body[0], body[1], body[2], body[3], Ydot, w)
