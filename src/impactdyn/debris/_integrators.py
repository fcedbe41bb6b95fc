"""Integrators of the particle state equations, one interface and a registry (DESIGN §5).

Every particle is an independent 33-dimensional ODE (:mod:`._particle`)
integrated from t = 0 to its own end time (its arrival time at the wall). Each
integrator is a compiled ``prange`` loop over particles: one particle per
iteration, its state and scratch allocated once per particle, nothing allocated
per step. Registered names:

``verlet`` (default)
    Strang splitting of the state equations, second order, symplectic and
    time-reversible when η = ∞ and ζ = 0. The system is Hamiltonian in (F, H)
    with T(H) = ½ tr(H J⁻¹ Hᵀ) and U(F; Eₚ), so position Störmer–Verlet applies;
    the dissipative parts are solved exactly over the substeps in which F is
    frozen::

        D(h/2) · R(h/2) · V(h/2) · K(h) · V(h/2) · R(h/2) · D(h/2)

    D (drift)   F ← F + τ H J⁻¹;
    K (kick)    H ← H − τ F S(F, Eₚ);
    R (relax)   Ėₚ = r (E' − Eₚ) with E' frozen: Eₚ ← E' + (Eₚ − E') e^{−rτ};
    V (bulk viscosity) Ḣ = −a tr(H B) F⁻ᵀ, a = ζV₀J_F/3, B = J⁻¹F⁻¹, is linear in H
    with F frozen: s = tr(HB) decays as e^{−κτ}, κ = a tr(F⁻ᵀB) ≥ 0, so
    H ← H − a τ φ₁(κτ) s F⁻ᵀ, φ₁(x) = (1 − e^{−x})/x.
    Fixed step: ``dt`` if given, else 2π/(ω̂ · steps_per_period) where
    ω̂ = √(V₀ max(2μ, 3K_b) / λ_min(J)) bounds the particle's highest linear
    vibration frequency (stiffness over mass operator, largest over smallest
    eigenvalue); each particle takes ⌈t_end/dt⌉ equal steps that land on t_end.
    The step size is independent of ``eps``.

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

Choice of default (benchmarks/bench_debris_integrators.py, synthetic Al cloud,
flights up to 15 µs): verlet at 32 steps per period is about 15× cheaper than
legacy at eps = 1e-6 and 2–3× cheaper than rk45 at eps = 1e-6, with arrival
vertices within ~3e-4 cm (1 % of a 0.03175 cm cell; the error is the phase of
the particle's fast vibration, which stays bounded because the scheme does not
drift in energy). Where vertex errors below ~1e-5 cm matter, use rk45 (1e-6:
~1.5e-5 cm; 1e-8: ~1e-7 cm at 4–5× the cost of verlet).

Failure codes (:class:`Failure`) are per particle and never silent; a failed
particle keeps the last state reached (``stats.t_reached``) and does not affect
the others.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import IntEnum
from typing import Callable

import numba
import numpy as np
from numba import prange

from impactdyn.debris._particle import (
    EP_SLICE, F_ROWS, H_SLICE, N_WORK, P_ZETA, STATE_ROWS, STATE_SIZE, Material, det3,
    frobenius, inline_kernel, inv3, kernel, matmul3, rates_into, relaxation_rate, scratch_views,
    state_views, strain_measures, stress_from_strain, trace_of_product,
)


class Failure(IntEnum):
    """Per-particle outcome of an integration."""

    OK = 0
    STEP_UNDERFLOW = 1   # adaptive step fell below its minimum
    NAN = 2              # a state component is NaN or infinite
    INVERTED = 3         # det F ≤ 0: the tetrahedron turned inside out
    STEP_BUDGET = 4      # max_steps reached before t_end


# The codes as plain ints, compile-time constants in the kernels.
_OK, _UNDERFLOW, _NAN, _INVERTED, _BUDGET = (int(c) for c in Failure)

# Particles handed to a thread at a time (numba.set_parallel_chunksize), see propagate.
_CHUNK = 8


@dataclass(frozen=True)
class StepControl:
    """Step-size control shared by all integrators (each reads what applies to it).

    eps: tolerance of the adaptive methods; dt: verlet step, or first step of
    rk45 (µs; scalar or ``(N,)``; None: from the particle's ω̂); steps_per_period:
    verlet steps per 2π/ω̂ when dt is None; max_steps: accepted + rejected steps
    per particle before Failure.STEP_BUDGET; ymxref: legacy's floor of the
    running maxima.
    """

    eps: float = 1e-6
    dt: float | np.ndarray | None = None
    steps_per_period: float = 32.0
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
def state_failure(Y):
    """Failure code of a state ``Y (11, 3)``: NAN if a component is not finite, INVERTED if det F ≤ 0."""
    for r in range(STATE_ROWS):
        for k in range(3):
            if not math.isfinite(Y[r, k]):
                return _NAN
    if det3(Y[F_ROWS]) <= 0.0:
        return _INVERTED
    return _OK


@inline_kernel
def _f(Y, body, Ydot, w):
    """Ẏ = f(Y) for the particle constants body = (J⁻¹, m, V₀, params); rows ``(11, 3)``."""
    rates_into(Y, body[0], body[1], body[2], body[3], Ydot, w)


@inline_kernel
def _phi1(x):
    """φ₁(x) = (1 − e^{−x})/x, accurate for small x."""
    if x < 1e-8:
        return 1.0 - 0.5 * x
    return -math.expm1(-x) / x


# --- verlet ------------------------------------------------------------------------------


@inline_kernel
def _drift(F, H, Jinv, tau, tmp):
    """D(τ): F ← F + τ H J⁻¹."""
    matmul3(H, Jinv, tmp)
    for i in range(3):
        for j in range(3):
            F[i, j] += tau * tmp[i, j]


@inline_kernel
def _relax(Ep, Edev, decay):
    """R(τ): Eₚ ← E' + (Eₚ − E') e^{−rτ}, with decay = e^{−rτ}."""
    for i in range(3):
        for j in range(3):
            Ep[i, j] = Edev[i, j] + (Ep[i, j] - Edev[i, j]) * decay


@inline_kernel
def _bulk_viscosity(H, Finv, B, a, kappa, tau):
    """V(τ): H ← H − a τ φ₁(κτ) tr(H B) F⁻ᵀ.

    The exact flow of Ḣ = −a tr(HB) F⁻ᵀ for frozen F (module docstring).
    """
    factor = a * tau * _phi1(kappa * tau) * trace_of_product(H, B)
    for i in range(3):
        for j in range(3):
            H[i, j] -= factor * Finv[j, i]


@inline_kernel
def verlet_step(Yv, Jinv, V0, params, h, decay, sc):
    """One step D(h/2) R(h/2) V(h/2) K(h) V(h/2) R(h/2) D(h/2) (module docstring).

    ``Yv``: state_views, advanced in place (c excepted); decay = e^{−r h/2};
    ``sc``: scratch_views.
    """
    H, F, Ep = Yv[0], Yv[1], Yv[2]
    _, _, Edev, S, Finv, B, tmp = sc
    half = 0.5 * h

    _drift(F, H, Jinv, half, tmp)
    detF = strain_measures(F, sc)  # C⁻¹ and E' stay valid until the next drift
    _relax(Ep, Edev, decay)
    zeta = params[P_ZETA]
    a = zeta * V0 * detF / 3.0
    kappa = 0.0
    if zeta > 0.0:
        inv3(F, Finv)
        matmul3(Jinv, Finv, B)
        kappa = a * frobenius(Finv, B)  # a tr(F⁻ᵀ J⁻¹ F⁻¹)
        _bulk_viscosity(H, Finv, B, a, kappa, half)
    stress_from_strain(detF, Ep, V0, params, sc)
    matmul3(F, S, tmp)
    for i in range(3):
        for j in range(3):
            H[i, j] -= h * tmp[i, j]
    if zeta > 0.0:
        _bulk_viscosity(H, Finv, B, a, kappa, half)
    _relax(Ep, Edev, decay)
    _drift(F, H, Jinv, half, tmp)


@kernel
def steps_to_cover(t_end, dt):
    """Number of equal steps ≤ dt covering t_end (a relative 1e-9 slack, so t_end = k·dt gives k)."""
    return max(1, int(math.ceil(t_end / dt * (1.0 - 1e-9))))


@kernel
def _verlet_particle(y, Jinv, m, V0, t_end, dt, params, max_steps, w):
    Y = y.reshape((STATE_ROWS, 3))
    Yv, sc = state_views(Y), scratch_views(w)
    code = state_failure(Y)
    if code != _OK or t_end <= 0.0:
        return 0.0, 0, code
    n = steps_to_cover(t_end, dt)
    h = t_end / n
    decay = math.exp(-0.5 * h * relaxation_rate(V0, params))
    done = 0
    while done < n:
        if done == max_steps:
            code = _BUDGET
            break
        verlet_step(Yv, Jinv, V0, params, h, decay, sc)
        done += 1
        code = state_failure(Y)
        if code != _OK:
            break
    t = t_end if done == n else done * h
    p, c = Yv[3], Yv[4]
    for k in range(3):  # c(t) = c(0) + t p/m, exact (ṗ = 0)
        c[k] += t * p[k] / m
    return t, done, code


@kernel(parallel=True)
def _verlet_all(y, Jinv, m, V0, t_end, dt, params, max_steps, t_out, counts):
    for n in prange(y.shape[0]):
        w = np.empty((N_WORK, 3, 3))
        t_out[n], counts[n, 0], counts[n, 2] = _verlet_particle(
            y[n], Jinv[n], m[n], V0[n], t_end[n], dt[n], params, max_steps, w)


@register_integrator("verlet")
def verlet(batch: ParticleBatch, control: StepControl):
    """Störmer–Verlet splitting with exact relaxation and bulk-viscosity substeps (module docstring)."""
    if control.dt is None:
        dt = 2.0 * np.pi / (batch.omega_hat * control.steps_per_period)
    else:
        dt = batch.per_particle(control.dt)
    y, t_out, counts = _outputs(batch)
    _verlet_all(y, batch.Jinv, batch.m, batch.V0, batch.t_end, dt, batch.params,
                control.max_steps, t_out, counts)
    return y, t_out, counts


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


def _as_batch(states, J, m, t_end, material: Material, phi) -> ParticleBatch:
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


def propagate(states, J, m, t_end, material: Material, *, phi=0.0, method: str = "verlet",
              eps: float = 1e-6, dt=None, steps_per_period: float = StepControl.steps_per_period,
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
    if not steps_per_period > math.pi:
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
