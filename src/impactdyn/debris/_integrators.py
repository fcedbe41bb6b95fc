"""Integrators of the particle state equations, one interface and a registry (DESIGN §5).

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

Choice of default (``benchmarks/bench_debris_integrators.py``, synthetic Al
cloud, flights up to 15 µs, arrival vertices against DOP853 at rtol 1e-12;
numbers in ``benchmarks/BENCHMARKS.md``): splitting4 at 8 steps per period
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
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numba
import numpy as np
from numba import prange

from impactdyn.debris._particle import (
    EP_SLICE, H_SLICE, N_WORK, P_RELAX, P_RELAX_PER_VOLUME, STATE_ROWS, STATE_SIZE,
    ParticleMaterial, inline_kernel, kernel, rates_into,
)
from impactdyn.debris._failure import BUDGET, OK, UNDERFLOW, Failure, state_failure
from impactdyn.debris._splitting import BLANES_MOAN_S6, VERLET, run_splitting


# The failure codes as plain ints, compile-time constants in the kernels.
_OK, _UNDERFLOW, _BUDGET = OK, UNDERFLOW, BUDGET

# Particles handed to a thread at a time (numba.set_parallel_chunksize), see propagate.
_CHUNK = 8


@dataclass(frozen=True)
class StepControl:
    """Step-size control shared by all integrators (each reads what applies to it).

    eps: tolerance of the adaptive methods; dt: splitting step, or first step of
    rk45 (µs; scalar or ``(N,)``; None: from the particle's ω̂); steps_per_period:
    splitting steps per 2π/ω̂ when dt is None (None: the method's own default); max_steps: accepted + rejected steps
    per particle before Failure.STEP_BUDGET; ymxref: legacy's floor of the
    running maxima.
    """

    eps: float = 1e-6
    dt: float | np.ndarray | None = None
    steps_per_period: float | None = None
    max_steps: int = 10_000_000
    ymxref: float = 1e-6


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

    def per_particle(self, value) -> np.ndarray:
        """A scalar or ``(N,)`` value as a contiguous ``(N,)`` float array."""
        return np.ascontiguousarray(np.broadcast_to(np.asarray(value, dtype=float), self.m.shape))


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


IntegratorFn = Callable[[ParticleBatch, StepControl], tuple[np.ndarray, np.ndarray, np.ndarray]]
"""(batch, control) -> (states ``(N, 33)``, t_reached ``(N,)``, counts ``(N, 3)``: steps, rejected, code)."""

INTEGRATORS: dict[str, IntegratorFn] = {}


def register_integrator(name: str):
    """Decorator adding an :data:`IntegratorFn` to :data:`INTEGRATORS` under ``name``."""
    def add(fn: IntegratorFn) -> IntegratorFn:
        if name in INTEGRATORS:
            raise ValueError(f"integrator {name!r} is already registered")
        INTEGRATORS[name] = fn
        return fn
    return add


# --- shared kernels ------------------------------------------------------------------
# Per particle, a kernel gets the flat state ``y (33,)`` for vector algebra, and
# makes the views it needs once, before the step loop (see _particle).


@inline_kernel
def _f(Y, body, Ydot, w):
    """Ẏ = f(Y) for the particle constants body = (J⁻¹, m, V₀, params); rows ``(11, 3)``."""
    rates_into(Y, body[0], body[1], body[2], body[3], Ydot, w)


# --- splittings (verlet, splitting4) ----------------------------------------------------


DEFAULT_STEPS_PER_PERIOD: dict[str, float] = {}
"""Steps per 2π/ω̂ of each splitting integrator when none is given."""


def _register_splitting(name: str, coefficients, steps_per_period: float) -> None:
    """Register :func:`._splitting.run_splitting` with ``coefficients`` (a, b) as ``name``."""
    @register_integrator(name)
    def integrate(batch: ParticleBatch, control: StepControl):
        if control.dt is None:
            dt = 2.0 * np.pi / (batch.omega_hat * (control.steps_per_period or steps_per_period))
        else:
            dt = batch.per_particle(control.dt)
        y, t_out, counts = _outputs(batch)
        r = batch.params[P_RELAX] * (batch.V0 if batch.params[P_RELAX_PER_VOLUME] else 1.0)
        t_out[:], counts[:, 0], counts[:, 2] = run_splitting(
            y, batch.Jinv, batch.m, batch.V0, batch.per_particle(r), batch.params, batch.t_end, dt,
            control.max_steps, coefficients)
        return y, t_out, counts
    DEFAULT_STEPS_PER_PERIOD[name] = steps_per_period


_register_splitting("splitting4", BLANES_MOAN_S6, 8.0)
_register_splitting("verlet", VERLET, 32.0)


def _outputs(batch: ParticleBatch):
    n = len(batch.m)
    return batch.y0.copy(), np.zeros(n), np.zeros((n, 3), dtype=np.int64)


# --- rk45 (Dormand–Prince 5(4)) ------------------------------------------------------

_DP_A = np.array([
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1 / 5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3 / 40, 9 / 40, 0.0, 0.0, 0.0, 0.0, 0.0],
    [44 / 45, -56 / 15, 32 / 9, 0.0, 0.0, 0.0, 0.0],
    [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729, 0.0, 0.0, 0.0],
    [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656, 0.0, 0.0],
    [35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84, 0.0],
])
"""Stage coefficients; the last row is the fifth-order solution (FSAL)."""
_DP_E = np.array([71 / 57600, 0.0, -71 / 16695, 71 / 1920, -17253 / 339200, 22 / 525, -1 / 40])
"""b − b̂: fifth- minus fourth-order weights, the local error estimate."""

_N_CONTROLLED = EP_SLICE.stop  # H, F, Eₚ enter the error norm; p, c are exact
_N_H = H_SLICE.stop


@kernel
def _rk45_particle(y, body, t_end, h0, h_floor, eps, max_steps, K, ytrial, w):
    Y, Ytrial = y.reshape((STATE_ROWS, 3)), ytrial.reshape((STATE_ROWS, 3))
    Kr = K.reshape((7, STATE_ROWS, 3))
    code = state_failure(Y)
    if code != _OK or t_end <= 0.0:
        return 0.0, 0, 0, code
    _f(Y, body, Kr[0], w)
    t, h, h_min = 0.0, min(h0, t_end), 1e-10 * h0
    steps, rejected, after_rejection, err_old = 0, 0, False, 1e-4
    while True:
        if steps + rejected >= max_steps:
            code = _BUDGET
            break
        final = t + h >= t_end
        if final:
            h = t_end - t
        for s in range(1, 7):
            for i in range(STATE_SIZE):
                acc = 0.0
                for j in range(s):
                    acc += _DP_A[s, j] * K[j, i]
                ytrial[i] = y[i] + h * acc
            _f(Ytrial, body, Kr[s], w)
        err = 0.0
        for i in range(_N_CONTROLLED):
            local = 0.0
            for j in range(7):
                local += _DP_E[j] * K[j, i]
            floor = h_floor if i < _N_H else 1.0
            err = max(err, abs(h * local) / (eps * max(abs(y[i]), abs(ytrial[i]), floor)))
        if state_failure(Ytrial) != _OK:
            err = math.inf
        if err <= 1.0:
            y[:] = ytrial
            K[0, :] = K[6]
            steps += 1
            if final:
                t = t_end
                break
            t += h
            factor = 5.0 if err == 0.0 else min(5.0, 0.9 * err ** -0.17 * err_old ** 0.04)
            err_old = max(err, 1e-4)  # DOPRI5's floor: a tiny error must not stall growth
            if after_rejection:
                factor = min(factor, 1.0)
            after_rejection = False
        else:
            rejected += 1
            after_rejection = True
            factor = max(0.2, 0.9 * err ** -0.2) if err < math.inf else 0.2
        h *= factor
        if h < h_min:
            code = _UNDERFLOW
            break
    return t, steps, rejected, code


@kernel(parallel=True)
def _rk45_all(y, Jinv, m, V0, t_end, h0, h_floor, eps, params, max_steps, t_out, counts):
    for n in prange(y.shape[0]):
        K = np.empty((7, STATE_SIZE))
        ytrial = np.empty(STATE_SIZE)
        w = np.empty((N_WORK, 3, 3))
        t_out[n], counts[n, 0], counts[n, 1], counts[n, 2] = _rk45_particle(
            y[n], (Jinv[n], m[n], V0[n], params), t_end[n], h0[n], h_floor[n], eps, max_steps,
            K, ytrial, w)


@register_integrator("rk45")
def rk45(batch: ParticleBatch, control: StepControl):
    """Adaptive Dormand–Prince 5(4) (module docstring)."""
    h0 = 0.1 / batch.omega_hat if control.dt is None else batch.per_particle(control.dt)
    y, t_out, counts = _outputs(batch)
    _rk45_all(y, batch.Jinv, batch.m, batch.V0, batch.t_end, h0, batch.j_max * batch.omega_hat,
              control.eps, batch.params, control.max_steps, t_out, counts)
    return y, t_out, counts


# --- legacy (listing IVDCRK: RK4 with step doubling) ------------------------------------


@kernel
def _rk4_step(y, f_y, h, out, body, K, tmp, w):
    """out = classical RK4 step of size h from y, given f_y = f(y).

    Flat ``(33,)`` arrays y, f_y, out, tmp; K ``(3, 33)`` stage rates; w scratch.
    """
    Kr, Tmp = K.reshape((3, STATE_ROWS, 3)), tmp.reshape((STATE_ROWS, 3))
    for i in range(STATE_SIZE):
        tmp[i] = y[i] + 0.5 * h * f_y[i]
    _f(Tmp, body, Kr[0], w)
    for i in range(STATE_SIZE):
        tmp[i] = y[i] + 0.5 * h * K[0, i]
    _f(Tmp, body, Kr[1], w)
    for i in range(STATE_SIZE):
        tmp[i] = y[i] + h * K[1, i]
    _f(Tmp, body, Kr[2], w)
    for i in range(STATE_SIZE):
        out[i] = y[i] + h / 6.0 * (f_y[i] + 2.0 * K[0, i] + 2.0 * K[1, i] + K[2, i])


@kernel
def _legacy_particle(y, body, t_end, eps, ymxref, max_steps, K, W, w):
    # W rows: f(y), f(y_half), y_full, y_half, y_two, ymax, tmp
    f_y, f_half, y_full, y_half, y_two, ymax, tmp = W[0], W[1], W[2], W[3], W[4], W[5], W[6]
    Y, Wr = y.reshape((STATE_ROWS, 3)), W.reshape((7, STATE_ROWS, 3))
    code = state_failure(Y)
    if code != _OK or t_end <= 0.0:
        return 0.0, 0, 0, code
    for i in range(STATE_SIZE):
        ymax[i] = max(ymxref, abs(y[i]))
    h = t_end / 1.0e6
    h_min = h / 10.0
    t, steps, rejected = 0.0, 0, 0
    _f(Y, body, Wr[0], w)
    while True:
        if steps + rejected >= max_steps:
            code = _BUDGET
            break
        final = t + h >= t_end
        if final:
            h = t_end - t
        _rk4_step(y, f_y, h, y_full, body, K, tmp, w)
        _rk4_step(y, f_y, 0.5 * h, y_half, body, K, tmp, w)
        _f(Wr[3], body, Wr[1], w)
        _rk4_step(y_half, f_half, 0.5 * h, y_two, body, K, tmp, w)
        err = 0.0
        for i in range(STATE_SIZE):
            err = max(err, abs(y_two[i] - y_full[i]) / (eps * ymax[i]))
        if err > 1.0:
            rejected += 1
            h *= 0.5
            if h < h_min:
                code = _UNDERFLOW
                break
            continue
        h_used = h
        h = 2.0 * h if err <= 0.0 else 0.99 * h * err ** -0.2
        y[:] = y_two
        for i in range(STATE_SIZE):
            ymax[i] = max(ymax[i], abs(y[i]))
        steps += 1
        t = t_end if final else t + h_used
        code = state_failure(Y)
        if code != _OK or final:
            break
        if h < h_min:
            code = _UNDERFLOW
            break
        _f(Y, body, Wr[0], w)
    return t, steps, rejected, code


@kernel(parallel=True)
def _legacy_all(y, Jinv, m, V0, t_end, eps, ymxref, params, max_steps, t_out, counts):
    for n in prange(y.shape[0]):
        K = np.empty((3, STATE_SIZE))
        W = np.empty((7, STATE_SIZE))
        w = np.empty((N_WORK, 3, 3))
        t_out[n], counts[n, 0], counts[n, 1], counts[n, 2] = _legacy_particle(
            y[n], (Jinv[n], m[n], V0[n], params), t_end[n], eps, ymxref, max_steps, K, W, w)


@register_integrator("legacy")
def legacy(batch: ParticleBatch, control: StepControl):
    """The listing's RK4 with step doubling (module docstring)."""
    y, t_out, counts = _outputs(batch)
    _legacy_all(y, batch.Jinv, batch.m, batch.V0, batch.t_end, control.eps, control.ymxref,
                batch.params, control.max_steps, t_out, counts)
    return y, t_out, counts


# --- public entry point -------------------------------------------------------------


def _as_batch(states, J, m, t_end, material: ParticleMaterial, phi) -> ParticleBatch:
    y0 = np.ascontiguousarray(np.asarray(states, dtype=float))
    if y0.ndim != 2 or y0.shape[1] != STATE_SIZE:
        raise ValueError(f"states must have shape (N, {STATE_SIZE}), got {y0.shape}")
    n = len(y0)
    J = np.ascontiguousarray(np.asarray(J, dtype=float))
    if J.shape != (n, 3, 3):
        raise ValueError(f"J must have shape ({n}, 3, 3), got {J.shape}")
    m = np.ascontiguousarray(np.asarray(m, dtype=float))
    if m.shape != (n,) or not np.all(np.isfinite(m) & (m > 0)):
        raise ValueError(f"m must be ({n},) finite and > 0")
    t_end = np.ascontiguousarray(np.broadcast_to(np.asarray(t_end, dtype=float), (n,)))
    if not np.all(np.isfinite(t_end) & (t_end >= 0)):
        raise ValueError("t_end must be finite and >= 0")
    phi = np.broadcast_to(np.asarray(phi, dtype=float), (n,))
    if not np.all((phi >= 0) & (phi < 1)):
        raise ValueError("phi must be in [0, 1)")
    if not np.all(np.isfinite(J)) or not np.allclose(J, np.swapaxes(J, 1, 2), rtol=1e-12, atol=0):
        raise ValueError("J must be finite and symmetric")
    eig = np.linalg.eigvalsh(J) if n else np.ones((0, 3))
    if not np.all(eig[:, 0] > 0):
        bad = int(np.argmax(~(eig[:, 0] > 0)))
        raise ValueError(f"J must be positive definite (particle {bad}: eigenvalues {eig[bad]})")
    V0 = np.ascontiguousarray(material.reference_volume(m, phi))
    return ParticleBatch(
        y0=y0, Jinv=np.ascontiguousarray(np.linalg.inv(J)), m=m, V0=V0, t_end=t_end,
        params=material.packed(),
        omega_hat=np.sqrt(V0 * material.stiffness_bound() / eig[:, 0]), j_max=eig[:, 2].copy())


def propagate(states, J, m, t_end, material: ParticleMaterial, *, phi=0.0, method: str = "splitting4",
              eps: float = 1e-6, dt=None, steps_per_period: float | None = None,
              max_steps: int = StepControl.max_steps, ymxref: float = StepControl.ymxref):
    """Integrate N independent particles from t = 0 to their own end times.

    states ``(N, 33)`` packed initial states (:mod:`._particle`); J ``(N, 3, 3)``
    inertia tensors (g cm²); m ``(N,)`` masses (g); t_end scalar or ``(N,)`` (µs);
    phi scalar or ``(N,)`` void fractions (V₀ = m/((1 − φ)ρ_ref)); method a name
    in :data:`INTEGRATORS`; eps, dt, steps_per_period, max_steps, ymxref as in
    :class:`StepControl`.

    Returns (states ``(N, 33)`` at ``stats.t_reached``, :class:`PropagationStats`).
    Particles whose initial state is not finite or has det F ≤ 0 are returned
    unchanged with their failure code.
    """
    if method not in INTEGRATORS:
        raise ValueError(f"unknown integrator {method!r}; available: {sorted(INTEGRATORS)}")
    if not eps > 0:
        raise ValueError(f"eps must be > 0, got {eps}")
    if dt is not None and not np.all(np.asarray(dt, dtype=float) > 0):
        raise ValueError("dt must be > 0")
    if steps_per_period is not None and not steps_per_period > math.pi:
        raise ValueError(f"steps_per_period must exceed pi (leapfrog stability), got {steps_per_period}")
    if not (max_steps >= 1 and ymxref > 0):
        raise ValueError(f"max_steps must be >= 1 and ymxref > 0, got {max_steps}, {ymxref}")
    batch = _as_batch(states, J, m, t_end, material, phi)
    control = StepControl(eps=eps, dt=dt, steps_per_period=steps_per_period,
                          max_steps=int(max_steps), ymxref=ymxref)
    # Particles cost very different amounts (their end times differ, and they are
    # often sorted by position, hence by flight time): hand them to the threads in
    # small chunks on demand instead of numba's default equal contiguous blocks.
    previous = numba.set_parallel_chunksize(_CHUNK)
    try:
        y, t_reached, counts = INTEGRATORS[method](batch, control)
    finally:
        numba.set_parallel_chunksize(previous)
    return y, PropagationStats(steps=counts[:, 0], rejected=counts[:, 1], code=counts[:, 2],
                               t_reached=t_reached)
