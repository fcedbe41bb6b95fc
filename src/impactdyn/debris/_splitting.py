"""Splitting integrators of the particle state equations, vectorised across particles (docs/theory/debris.md, eq. (3)).

The state equations of :mod:`._particle` split as f = f_A + f_B into two flows
that are solved exactly:

A (drift), H and Eₚ frozen::

    F ← F + τ H J⁻¹

B (F frozen), so C = FᵀF, E', J_F = det F and P = K_b (1/J_F − 1)/J_F are
constants and Eₚ relaxes exponentially, Eₚ(t) = E' + (Eₚ − E') e^{−rt}; the
stress S = V₀ [2μ (E' − Eₚ) − P C⁻¹] is then integrated in closed form::

    Eₚ ← E' + (Eₚ − E') e^{−rτ}
    H  ← H − τ F V₀ [2μ (E' − Eₚ) φ₁(rτ) − P C⁻¹],     φ₁(x) = (1 − e^{−x})/x

A step of size h is the symmetric composition

    V(h/2) · A(a₁h) B(b₁h) A(a₂h) B(b₂h) … B(b_s h) A(a_{s+1}h) · V(h/2)

where V, present when ζ > 0, is the exact flow of the bulk viscosity
Ḣ = −a tr(H 𝔅) F⁻ᵀ with F frozen, a = ζV₀J_F/3, 𝔅 = J⁻¹F⁻¹ (linear in H:
s = tr(H𝔅) decays as e^{−κt}, κ = a tr(F⁻ᵀ𝔅) ≥ 0)::

    H ← H − a τ φ₁(κτ) s F⁻ᵀ

V stays outside the composition because its rate κ is typically far above the
vibration frequency (κh ~ 30 in the Whipple examples): inside, the negative
substeps of a higher-order composition would run it backwards, e^{+κ|b|h}.

``verlet``: a = (½, ½), b = (1), Störmer–Verlet, order 2.
``splitting4``: the 6-stage method S₆ of Blanes & Moan (2002, J. Comput. Appl.
Math. 142, 313–330), order 4 for any split into two exactly solved
flows. With η = ∞ and ζ = 0 the system is Hamiltonian in (F, H) with
T(H) = ½ tr(H J⁻¹ Hᵀ) and U(F), A and B are the flows of T and U, and both
methods are symplectic and time-reversible (bounded energy error, no drift). The
orders hold for finite η too (B is exact); with ζ > 0 the viscous coupling is
second order (Strang). The relaxation runs backwards on the negative substeps
too, which is harmless while 2μ/η · h ≪ 1.

Each particle takes ⌈t_end/dt⌉ equal steps that land on its t_end; the step dt
is given, or 2π/(ω̂ · steps_per_period) from the particle's bound ω̂ on its highest
linear vibration frequency (:mod:`._integrators`). Both methods are registered at the
bottom of this module with their default steps per period (:mod:`._registry`).

Vectorisation: particles are integrated in blocks of :data:`BLOCK`, sorted by
their number of steps so that a block's lanes finish together. A block's state
is stored component-major (``Y[c·BLOCK + k]`` is component c of lane k), and the
innermost loop of every kernel runs over the lanes with straight-line 9-tuple
algebra (:mod:`._mat3`) in registers, which LLVM turns into SIMD instructions
where its cost model for the CPU finds that profitable (on a 128-bit-FPU AMD EPYC
it mostly does not; the gain there, 1.6× per step over a particle-per-iteration
kernel, is from registers and no reference counting). A lane that
has finished or failed keeps its state by a per-lane select, so a particle's
arithmetic does not depend on its block-mates: results are bit-identical for
any chunking or ordering of the particles.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba import prange

from impactdyn.debris import _mat3 as m3
from impactdyn.debris._failure import BUDGET, INVERTED, NAN, OK, state_failure
from impactdyn.debris._particle import (C_SLICE, P_KB, P_MU, P_RELAX, P_RELAX_PER_VOLUME, P_SLICE, P_ZETA, STATE_ROWS,
                                       kernel)
from impactdyn.debris._registry import DEFAULT_STEPS_PER_PERIOD, ParticleBatch, StepControl, register_integrator

BLOCK = 16
"""Particles per vectorised block (a multiple of the SIMD width)."""

_STATE = 27  # H, F, Eₚ: the components a step changes (p is constant, c is advanced exactly at the end)
_H, _F, _EP = 0, 9, 18

_OK, _NAN, _INVERTED, _BUDGET = OK, NAN, INVERTED, BUDGET  # failure codes as compile-time constants

VERLET = (np.array([0.5, 0.5]), np.array([1.0]))
"""(a, b) of Störmer–Verlet: A(h/2) B(h) A(h/2)."""


def _blanes_moan_s6():
    a1, a2, a3 = 0.0792036964311957, 0.353172906049774, -0.0420650803577195
    b1, b2 = 0.209515106613362, -0.143851773179818
    a4, b3 = 1.0 - 2.0 * (a1 + a2 + a3), 0.5 - (b1 + b2)
    return np.array([a1, a2, a3, a4, a3, a2, a1]), np.array([b1, b2, b3, b3, b2, b1])


BLANES_MOAN_S6 = _blanes_moan_s6()
"""(a, b) of the order-4 method S₆ of Blanes & Moan (2002): 7 drifts, 6 B-stages."""


@m3.inline
def _load(Y, row, k):
    B = BLOCK
    return (Y[row * B + k], Y[(row + 1) * B + k], Y[(row + 2) * B + k], Y[(row + 3) * B + k],
            Y[(row + 4) * B + k], Y[(row + 5) * B + k], Y[(row + 6) * B + k], Y[(row + 7) * B + k],
            Y[(row + 8) * B + k])


@m3.inline
def _store(Y, row, k, A):
    B = BLOCK
    Y[row * B + k] = A[0]
    Y[(row + 1) * B + k] = A[1]
    Y[(row + 2) * B + k] = A[2]
    Y[(row + 3) * B + k] = A[3]
    Y[(row + 4) * B + k] = A[4]
    Y[(row + 5) * B + k] = A[5]
    Y[(row + 6) * B + k] = A[6]
    Y[(row + 7) * B + k] = A[7]
    Y[(row + 8) * B + k] = A[8]


@m3.inline
def _phi1(x):
    """φ₁(x) = (1 − e^{−x})/x, accurate for small x."""
    if abs(x) < 1e-8:
        return 1.0 - 0.5 * x
    return -math.expm1(-x) / x


@m3.inline
def drift(F, H, Jinv, tau):
    """A(τ): F + τ H J⁻¹."""
    return m3.axpy(tau, m3.mm(H, Jinv), F)


@m3.inline
def frozen_f_flow(H, F, Ep, V0, mu, kb, tau, decay, phi):
    """B₀(τ), the exact flow with F frozen and no viscosity: (H, Eₚ) after τ (module docstring).

    decay = e^{−rτ}, phi = φ₁(rτ).
    """
    C = m3.mtm(F, F)
    Edev = m3.deviator_half(C)
    r = 1.0 / m3.det(F)  # one division: det C = det(F)², C⁻¹ = adj(C) r²
    pressure = kb * (r - 1.0) * r
    lag = m3.sub(Edev, Ep)  # E' − Eₚ
    S_mean = m3.scale(V0, m3.sub(m3.scale(2.0 * mu * phi, lag), m3.scale(pressure * r * r, m3.adjugate(C))))
    return m3.axpy(-tau, m3.mm(F, S_mean), H), m3.axpy(-decay, lag, Edev)


@m3.inline
def viscous_rate(F, Jinv, V0, zeta):
    """κ = a tr(F⁻ᵀ𝔅), the decay rate of tr(H𝔅) under the viscous flow (module docstring)."""
    Finv = m3.inv(F)
    return zeta * V0 * m3.det(F) / 3.0 * m3.trace_of_product(m3.transpose(Finv), m3.mm(Jinv, Finv))


@m3.inline
def bulk_viscosity_flow(H, F, Jinv, V0, zeta, tau, phi):
    """V(τ): H − a τ φ₁(κτ) tr(H𝔅) F⁻ᵀ, the exact viscous flow for frozen F, given phi = φ₁(κτ)."""
    Finv = m3.inv(F)
    a = zeta * V0 * m3.det(F) / 3.0
    return m3.axpy(-a * tau * phi * m3.trace_of_product(H, m3.mm(Jinv, Finv)), m3.transpose(Finv), H)


@m3.inline
def failure_code(H, F, Ep):
    """NAN if a component is not finite, INVERTED if det F ≤ 0, else OK (branch-free)."""
    total = m3.trace_of_product(H, H) + m3.trace_of_product(F, F) + m3.trace_of_product(Ep, Ep)
    finite = total - total == 0.0
    return _OK if finite and m3.det(F) > 0.0 else (_INVERTED if finite else _NAN)


# Rows of a block's constants ``K (rows·BLOCK,)``, after the 9 of J⁻¹: V₀, h, the live
# flag of the current step (1.0 or 0.0), τ and φ₁(κτ) of the current viscous substep, then
# e^{−r bᵢh} and φ₁(r bᵢh) per stage i. One array for all of them keeps the SIMD loops to
# two memory streams: LLVM vectorises a loop only if it can rule out aliasing with a few
# runtime checks.
_V0, _STEP, _LIVE, _TAU_V, _PHI_V, _DECAY = 9, 10, 11, 12, 13, 14


@kernel
def _viscous_step(Y, K, zeta):
    """V(τ) on every live lane of a block, τ = K[_TAU_V] per lane (module docstring)."""
    for k in range(BLOCK):  # φ₁(κτ), a libm call per lane: kept out of the SIMD loop below
        Jinv, tau = _load(K, 0, k), K[_TAU_V * BLOCK + k]
        K[_PHI_V * BLOCK + k] = _phi1(tau * viscous_rate(_load(Y, _F, k), Jinv, K[_V0 * BLOCK + k], zeta))
    for k in range(BLOCK):
        live = K[_LIVE * BLOCK + k] > 0.0
        H, F, Jinv = _load(Y, _H, k), _load(Y, _F, k), _load(K, 0, k)
        H1 = bulk_viscosity_flow(H, F, Jinv, K[_V0 * BLOCK + k], zeta, K[_TAU_V * BLOCK + k], K[_PHI_V * BLOCK + k])
        _store(Y, _H, k, m3.select(live, H1, H))


@kernel
def _advance_block(Y, K, n, code, done, a, b, mu, kb, zeta):
    """Advance one block ``Y (27·BLOCK,)`` by each lane's n steps; update code, done ``(BLOCK,)``.

    K ``((14 + 2 len(b))·BLOCK,)``: the lanes' constants (rows ``_V0`` …); a, b the
    coefficients. The loops over the lanes that carry the work are free of calls and
    branches, so that LLVM can vectorise them. With ζ > 0 the closing V(h/2) of a step
    and the opening V(h/2) of the next act on the same F, so they are taken as one
    V(h), exactly; a lane's last step (or the step it fails in) closes with V(h/2)
    only when it ends by n (a failed particle's H may have had the other half).
    """
    n_b = b.shape[0]
    phi_row = _DECAY + n_b
    n_max = 0
    for k in range(BLOCK):
        n_max = max(n_max, n[k])
    for s in range(n_max):
        for k in range(BLOCK):
            K[_LIVE * BLOCK + k] = 1.0 if (s < n[k]) & (code[k] == _OK) else 0.0
        if zeta > 0.0 and s == 0:
            for k in range(BLOCK):
                K[_TAU_V * BLOCK + k] = 0.5 * K[_STEP * BLOCK + k]
            _viscous_step(Y, K, zeta)
        for i in range(n_b):
            a_i, b_i = a[i], b[i]
            for k in range(BLOCK):  # A(aᵢh) then B₀(bᵢh)
                live = K[_LIVE * BLOCK + k] > 0.0
                H, F, Ep, Jinv = _load(Y, _H, k), _load(Y, _F, k), _load(Y, _EP, k), _load(K, 0, k)
                h = K[_STEP * BLOCK + k]
                F1 = drift(F, H, Jinv, a_i * h)
                H1, Ep1 = frozen_f_flow(H, F1, Ep, K[_V0 * BLOCK + k], mu, kb, b_i * h,
                                        K[(_DECAY + i) * BLOCK + k], K[(phi_row + i) * BLOCK + k])
                _store(Y, _H, k, m3.select(live, H1, H))
                _store(Y, _F, k, m3.select(live, F1, F))
                _store(Y, _EP, k, m3.select(live, Ep1, Ep))
        a_last = a[n_b]
        for k in range(BLOCK):  # the closing A(a_{s+1}h)
            live = K[_LIVE * BLOCK + k] > 0.0
            H, F, Jinv = _load(Y, _H, k), _load(Y, _F, k), _load(K, 0, k)
            _store(Y, _F, k, m3.select(live, drift(F, H, Jinv, a_last * K[_STEP * BLOCK + k]), F))
        if zeta > 0.0:
            for k in range(BLOCK):  # V(h/2) closing the last step, V(h) = V(h/2)·V(h/2) between steps
                K[_TAU_V * BLOCK + k] = K[_STEP * BLOCK + k] * (0.5 if s + 1 >= n[k] else 1.0)
            _viscous_step(Y, K, zeta)
        for k in range(BLOCK):  # the failure check
            live = K[_LIVE * BLOCK + k] > 0.0
            c = failure_code(_load(Y, _H, k), _load(Y, _F, k), _load(Y, _EP, k))
            code[k] = c if live else code[k]
            done[k] = done[k] + 1 if live else done[k]


@kernel(parallel=True)
def _advance_all(y, Jinv, V0, rate, h, n, order, a, b, params, code, done):
    """Gather blocks of particles in ``order``, advance them, scatter back (y ``(N, 33)`` in place)."""
    N = y.shape[0]
    n_b = b.shape[0]
    mu, kb, zeta = params[P_MU], params[P_KB], params[P_ZETA]
    for blk in prange((N + BLOCK - 1) // BLOCK):
        Y = np.zeros(_STATE * BLOCK)
        K = np.ones((_DECAY + 2 * n_b) * BLOCK)
        nb, cb, db = np.zeros(BLOCK, np.int64), np.zeros(BLOCK, np.int64), np.zeros(BLOCK, np.int64)
        for k in range(BLOCK):
            j = blk * BLOCK + k
            if j < N:
                p = order[j]
                for c in range(_STATE):
                    Y[c * BLOCK + k] = y[p, c]
                for c in range(9):
                    K[c * BLOCK + k] = Jinv[p, c // 3, c % 3]
                K[_V0 * BLOCK + k], K[_STEP * BLOCK + k] = V0[p], h[p]
                for i in range(n_b):
                    x = rate[p] * b[i] * h[p]
                    K[(_DECAY + i) * BLOCK + k] = math.exp(-x)
                    K[(_DECAY + n_b + i) * BLOCK + k] = _phi1(x)
                nb[k], cb[k] = n[p], state_failure(y[p].reshape((STATE_ROWS, 3)))
            else:  # an idle lane: a unit tetrahedron that takes no step
                for c in range(9):
                    K[c * BLOCK + k] = 1.0 if c % 4 == 0 else 0.0
                for c in (0, 4, 8):
                    Y[(_F + c) * BLOCK + k] = 1.0
        _advance_block(Y, K, nb, cb, db, a, b, mu, kb, zeta)
        for k in range(BLOCK):
            j = blk * BLOCK + k
            if j < N:
                p = order[j]
                for c in range(_STATE):
                    y[p, c] = Y[c * BLOCK + k]
                code[p], done[p] = cb[k], db[k]


def run_splitting(y, Jinv, m, V0, relaxation_rate, params, t_end, dt, max_steps, coefficients):
    """Integrate particles ``y (N, 33)`` in place by the splitting ``coefficients = (a, b)``.

    Jinv ``(N, 3, 3)``; m, V0, relaxation_rate (r of Ėₚ = r(E' − Eₚ)), t_end,
    dt ``(N,)``. Each particle takes n = ⌈t_end/dt⌉ steps of t_end/n, at most
    ``max_steps``. Returns (t_reached, steps, code), each ``(N,)``: the time
    the returned state belongs to, steps taken, and the failure code
    (:class:`._failure.Failure`; STEP_BUDGET when max_steps < n).
    """
    a, b = (np.ascontiguousarray(c, dtype=np.float64) for c in coefficients)
    n = np.where(t_end > 0.0, np.maximum(1, np.ceil(t_end / dt * (1.0 - 1e-9))), 0).astype(np.int64)
    h = np.divide(t_end, n, out=np.zeros_like(t_end), where=n > 0)
    code = np.zeros(len(y), dtype=np.int64)  # the kernel checks the initial states first
    done = np.zeros(len(y), dtype=np.int64)
    run = np.minimum(n, max_steps)
    order = np.argsort(-run, kind="stable")  # longest first: the big blocks start early
    previous = numba.set_parallel_chunksize(1)  # a block at a time: blocks cost up to t_max/t_min more
    try:
        _advance_all(y, Jinv, V0, relaxation_rate, h, run, order, a, b, params, code, done)
    finally:
        numba.set_parallel_chunksize(previous)
    code = np.where((code == _OK) & (done < n), _BUDGET, code)
    t_reached = np.where(done == n, t_end, done * h)
    y[:, C_SLICE] += t_reached[:, None] * y[:, P_SLICE] / m[:, None]  # c(t) = c(0) + t p/m, exact (ṗ = 0)
    return t_reached, done, code


def _register(name: str, coefficients, steps_per_period: float) -> None:
    """Register :func:`run_splitting` with ``coefficients`` (a, b) as integrator ``name`` (:mod:`._registry`)."""
    @register_integrator(name)
    def integrate(batch: ParticleBatch, control: StepControl):
        if control.dt is None:
            dt = 2.0 * np.pi / (batch.omega_hat * (control.steps_per_period or steps_per_period))
        else:
            dt = batch.per_particle(control.dt)
        y, t_out, counts = batch.outputs()
        r = batch.params[P_RELAX] * (batch.V0 if batch.params[P_RELAX_PER_VOLUME] else 1.0)
        t_out[:], counts[:, 0], counts[:, 2] = run_splitting(
            y, batch.Jinv, batch.m, batch.V0, batch.per_particle(r), batch.params, batch.t_end, dt,
            control.max_steps, coefficients)
        return y, t_out, counts
    DEFAULT_STEPS_PER_PERIOD[name] = steps_per_period


_register("splitting4", BLANES_MOAN_S6, 8.0)
_register("verlet", VERLET, 32.0)

__all__ = ["BLANES_MOAN_S6", "BLOCK", "VERLET", "run_splitting"]
