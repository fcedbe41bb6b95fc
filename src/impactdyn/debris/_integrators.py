"""Integrators of the particle state equations: their options and :func:`propagate` (docs/theory/debris.md).

Every particle is an independent 33-dimensional ODE (:mod:`._particle`)
integrated from t = 0 to its own end time (its arrival time at the wall). Each
integrator is a compiled ``prange`` loop over particles: one particle per
iteration, its state and scratch allocated once per particle, nothing allocated
per step. Registered names:

``splitting4`` (default), ``verlet``
    Symmetric compositions of the exact flows of a drift (F moves, H frozen)
    and of the frozen-F dynamics (H kicked by the time-integrated stress while
    Eₚ relaxes exponentially), with the bulk viscosity as an exact substep of
    half a step at each end (:mod:`._splitting`, where the equations are).
    ``verlet``: Störmer–Verlet, order 2, one stress evaluation per step.
    ``splitting4``: Blanes & Moan's S₆, order 4, six per step. Both are
    symplectic and time-reversible when η = ∞ and ζ = 0 (no energy drift) and
    keep the internal angular momentum to rounding; with ζ > 0 the viscous
    coupling is second order. Fixed step: ``dt`` if given, else
    2π/(ω̂ · steps_per_period) where ω̂ = √(V₀ max(2μ, 3K_b) / λ_min(J))
    bounds the particle's highest linear vibration frequency (stiffness over
    mass operator, largest over smallest eigenvalue); each particle takes
    ⌈t_end/dt⌉ equal steps that land on t_end. steps_per_period defaults to
    :data:`DEFAULT_STEPS_PER_PERIOD` of the method (8 for splitting4, 32 for
    verlet). The step size is independent of ``eps``. The kernels run blocks
    of particles in SIMD lanes.

``rk45``
    Dormand–Prince 5(4) with FSAL and local extrapolation (the ode45 / scipy
    RK45 pair). Chosen over Bogacki–Shampine 3(2) because the tolerances of
    interest (1e-6 and tighter) favour fifth order, and over DOP853 for its
    small per-step state. Error norm: the max over H, F, Eₚ of
    |err_i| / (eps·max(|y_i|, |y_i'|, floor_i)), floor 1 for F and Eₚ
    (dimensionless) and λ_max(J)·ω̂ for H (the momentum of Ḟ ~ ω̂, so an H error
    is weighted like the F error it causes within 1/ω̂). p and c are left out:
    ṗ = 0 and ċ = p/m are integrated exactly by any Runge–Kutta scheme.
    PI step control (Gustafsson; the exponents of Hairer's DOPRI5): factor
    0.9·err_n^(−0.17)·err_{n−1}^(0.04) in [0.2, 5], no growth right after a
    rejection, 0.9·err^(−1/5) ≥ 0.2 after one. The PI term matters here: the
    local error of these oscillators swings with the vibration phase, and the
    plain err^(−1/5) controller rejected about a third of its steps on the
    benchmark cloud. A trial with det F ≤ 0 or a non-finite component is
    rejected. First step ``dt`` if given, else 0.1/ω̂. Step underflow below
    1e-10 of the first step.

``legacy``
    The listing's IVDCRK: classical RK4 with step doubling (one step of h
    against two of h/2, the two half steps kept, no extrapolation), error
    max_i |y_h/2 − y_h| / (eps · ymax_i) over all 33 components with
    ymax_i = max(ymxref, running max |y_i|); accept if ≤ 1 and set
    h ← 0.99 h err^(−1/5) (h ← 2h if err = 0), else halve. First step
    t_end/10⁶, underflow below a tenth of it. As in the listing a NaN error
    does not reject the step (the NaN state is then reported, code 2); unlike
    it, the last step lands exactly on t_end. In cm-g-µs units H is ~1e-12 to
    1e-9 g cm²/µs, far below the listing's ymxref = 1e-6, so H is held only to
    an absolute eps·1e-6; its errors are controlled through the F they drive.

``slow``
    The slow-manifold integrator (:mod:`._slow_manifold`): each particle is
    projected once onto its stress-free configuration F = R U*(Eₚ) — the ringing's
    energy is dropped, which plastic flow and bulk viscosity would dissipate — and
    then turns as a free rigid body carrying its angular momentum (McLachlan's exact
    body-axis splitting composed to order 4), its centroid exact.  Stable for any
    ω̂h; ``steps_per_period`` counts steps per rigid rotation period (default 24),
    ``dt`` a fixed step.  An averaging method (:data:`AVERAGING`): it does not
    converge to the full solution as the step shrinks; valid while the ringing is
    small (|D|/ω̂ ≪ 1) and 2μ/η ≪ ω̂.  On ``table2_7a``/``10a`` its element impulses
    are within 4.5e-4 (L1, relative) of splitting4's, at 1/100 of the cost.

Choice of default (``benchmarks/bench_debris_integrators.py``, synthetic Al
cloud, flights up to 15 µs, arrival vertices against DOP853 at rtol 1e-12;
accuracy in docs/vv/analytic.md, "Debris particles (DC3D) against a tight reference solution",
times in ``benchmarks/BENCHMARKS.md``, "Debris particles (DC3D): integrators"): splitting4 at 8 steps per period
lands the arrival vertices more accurately than the listing's legacy integrator
at eps = 1e-6 (max 2–5e-7 cm against 7–9e-7 cm) for about a twentieth of its
CPU time, and several hundred times more accurately than verlet at 32 steps per
period (whose error, ~1e-4 cm, is the phase of the particle's fast vibration)
for about the same time. At 6 steps per period it is a quarter cheaper and
still below legacy in the median, not always in the max. Its negative
substeps make it a poor choice only where the plastic relaxation is stiff on
the step (2μ/η · h ≳ 1); there, or for the cheapest coarse runs (the Whipple
examples' 8 verlet steps per period), use verlet.

Failure codes (:class:`Failure`) are per particle and never silent; a failed
particle keeps the last state reached (``stats.t_reached``) and does not affect
the others.

Modules: the interface and registry (:mod:`._registry`), the splittings
(:mod:`._splitting`), ``rk45`` (:mod:`._rk45`), ``legacy`` (:mod:`._rk4_doubling`), what these two
share (:mod:`._adaptive`);
here :class:`IntegratorOptions`, the one home of the integrator settings' defaults
and bounds, and :func:`propagate`.
"""

from __future__ import annotations

from __future__ import annotations

import math
from typing import Annotated

import numba
import numpy as np
from pydantic import Field, field_validator, model_validator

from impactdyn._config import Positive, Section
from impactdyn._errors import InputError
# the built-in integrators, registered on import in this order
from impactdyn.debris import _splitting  # noqa: F401, I001
from impactdyn.debris import _rk45  # noqa: F401
from impactdyn.debris import _rk4_doubling  # noqa: F401
from impactdyn.debris import _slow_manifold  # noqa: F401
from impactdyn.debris._failure import Failure
from impactdyn.debris._particle import ParticleMaterial
from impactdyn.debris._registry import (AVERAGING, DEFAULT_STEPS_PER_PERIOD, INTEGRATORS, ParticleBatch,
                                        PropagationStats, StepControl, register_integrator)

# Particles handed to a thread at a time (numba.set_parallel_chunksize), see propagate.
_CHUNK = 8


class IntegratorOptions(Section):
    """How the particles are integrated: :func:`propagate`'s settings, and a case's ``[integrator]`` table.

    method : a name in :data:`INTEGRATORS` (module docstring): "splitting4" (default; Blanes &
        Moan's fourth-order splitting, fixed step), "verlet" (Störmer–Verlet, order 2), "rk45"
        (adaptive Dormand–Prince), "legacy" (the listing's RK4 with step doubling) or "slow" (the
        slow-manifold averaging method, which drops each particle's elastic ringing).
    eps : the relative tolerance of the adaptive methods (rk45, legacy); the fixed-step methods
        ignore it.
    steps_per_period : splitting steps per period 2π/ω̂ of the particle's fastest linear
        vibration (for "slow", steps per rigid rotation period); left out, the method's own
        (:data:`DEFAULT_STEPS_PER_PERIOD`), filled in so that a resolved case records the step
        used.  It must exceed π: Störmer–Verlet, like every leapfrog, is stable on an oscillation
        of frequency ω only for ωh < 2, i.e. more than π steps per period, and ω̂ bounds every
        frequency of the particle (Blanes & Moan's S₆ is stable to about 2 steps per period, so
        the bound holds for both).  The adaptive methods ignore it.
    max_steps : accepted + rejected steps per particle before it stops with
        ``Failure.STEP_BUDGET`` (its last state kept and reported; the others go on).
    ymxref : the "legacy" method's floor of the error scale (the listing's IVDCRK, dc3din record
        14, 1e-6): a component's error is measured against eps · max(ymxref, its running maximum
        |yᵢ|), so components smaller than ymxref are held to the absolute error eps · ymxref.  In
        cm-g-µs units H (1e-12 to 1e-9) lies far below it; its errors are controlled through the
        F they drive.  The other methods ignore it.
    """

    method: str = "splitting4"
    eps: Annotated[float, Field(gt=0, lt=1)] = 1e-6
    steps_per_period: Annotated[float, Field(gt=math.pi)] | None = None
    max_steps: Annotated[int, Field(ge=1)] = 10_000_000
    ymxref: Positive = 1e-6

    @field_validator("method")
    @classmethod
    def _registered(cls, method: str) -> str:
        if method not in INTEGRATORS:
            raise ValueError(INTEGRATORS.unknown(method, key=""))
        return INTEGRATORS.check(method)

    @model_validator(mode="before")
    @classmethod
    def _method_step(cls, data):
        """Fill in the method's own steps_per_period, so config.resolved.toml records the step used."""
        if isinstance(data, dict) and data.get("steps_per_period") is None:
            method = data.get("method", cls.model_fields["method"].default)
            if isinstance(method, str) and method in DEFAULT_STEPS_PER_PERIOD:
                return {**data, "steps_per_period": DEFAULT_STEPS_PER_PERIOD[method]}
        return data


def propagate(states, J, m, t_end, material: ParticleMaterial, *, phi=0.0, dt=None, method: str | None = None,
              eps: float | None = None, steps_per_period: float | None = None, max_steps: int | None = None,
              ymxref: float | None = None):
    """Integrate N independent particles from t = 0 to their own end times.

    states ``(N, 33)`` packed initial states (:mod:`._particle`); J ``(N, 3, 3)``
    inertia tensors (g cm²); m ``(N,)`` masses (g); t_end scalar or ``(N,)`` (µs);
    phi scalar or ``(N,)`` void fractions (V₀ = m/((1 − φ)ρ_ref)); dt: the
    splitting step, or rk45's first step (µs; scalar or ``(N,)``; None: from each
    particle's ω̂); method, eps, steps_per_period, max_steps, ymxref: the
    :class:`IntegratorOptions` (None: its default).

    Returns (states ``(N, 33)`` at ``stats.t_reached``, :class:`PropagationStats`).
    Particles whose initial state is not finite or has det F ≤ 0 are returned
    unchanged with their failure code.  A bad option raises
    :class:`~impactdyn._errors.InputError` (a ValueError) naming it.
    """
    given = dict(method=method, eps=eps, steps_per_period=steps_per_period, max_steps=max_steps, ymxref=ymxref)
    o = IntegratorOptions(**{k: v for k, v in given.items() if v is not None})
    if dt is not None and not np.all(np.asarray(dt, dtype=float) > 0):
        raise InputError(f"propagate: dt = {dt}: must be > 0")
    batch = ParticleBatch.of(states, J, m, t_end, material, phi)
    control = StepControl(eps=o.eps, dt=dt, steps_per_period=o.steps_per_period, max_steps=o.max_steps,
                          ymxref=o.ymxref)
    # Particles cost very different amounts (their end times differ, and they are
    # often sorted by position, hence by flight time): hand them to the threads in
    # small chunks on demand instead of numba's default equal contiguous blocks.
    previous = numba.set_parallel_chunksize(_CHUNK)
    try:
        y, t_reached, counts = INTEGRATORS[o.method](batch, control)
    finally:
        numba.set_parallel_chunksize(previous)
    return y, PropagationStats(steps=counts[:, 0], rejected=counts[:, 1], code=counts[:, 2],
                               t_reached=t_reached)


__all__ = ["AVERAGING", "DEFAULT_STEPS_PER_PERIOD", "INTEGRATORS", "Failure", "IntegratorOptions", "ParticleBatch",
           "PropagationStats", "StepControl", "propagate", "register_integrator"]
