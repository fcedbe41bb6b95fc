"""``slow``: a slow-manifold integrator that steps over the particles' elastic ringing (docs/theory/debris.md).

Why not an implicit scheme on (F, H).  A debris particle rings elastically with
ω ≈ ω̂ ~ 200/µs while its slow motion — the rigid rotation of a tetrahedron of
~0.03 cm spinning at |ω_rot| ~ 1/µs — turns it by ~10 rad in 15 µs.  An
A-stable implicit scheme (implicit midpoint, Simo & Tarnow's or Gonzalez's
energy–momentum methods) is stable at ω̂h ≫ 1, but it keeps the ringing
(|R(iω̂h)| = 1: the aliased vibration stays in F at full amplitude), needs a
Newton solve of the 9×9 tangent per step, and is second order in the rotation:
landing the rotation phase to 1e-3 rad after 10 rad takes |ω_rot|h ≲ 0.03, i.e.
hundreds of Newton steps per particle, well above the 60-s budget for 10⁶
particles.  The slow motion of this model is instead a free rigid rotation,
which is cheap to integrate to fourth order, so the integrator computes that
(the averaging / slow-manifold route; the stiff-spring limit of
Rubin & Ungar 1957 and Bornemann 1998, "Homogenization in time of singularly
perturbed mechanical systems", LNM 1687).

The slow manifold.  For ω̂ → ∞ with the other rates fixed, a particle's motion
splits into a vibration about a stress-free configuration and the motion of that
configuration.  S(F, Eₚ) = 0 ⇔ J_F = 1 and E' = Eₚ (module :mod:`._particle`),
i.e. C = FᵀF = C*(Eₚ) with

    C* = 2Eₚ + c I,   det(2Eₚ + c I) = 1        (c from a scalar Newton iteration),

so the stress-free configurations are F = R U*, U* = √C*, R ∈ SO(3), and on
them Ėₚ = (2μ/η)(E' − Eₚ) = 0 and the bulk viscosity, ∝ tr D = 0, does no work:
the slow motion is the free rigid rotation of the shape G = R₀U* with the
inertia M = G J Gᵀ (mass second moment), carrying the particle's angular
momentum, which the state equations conserve for every η and ζ:

    A = H Fᵀ − F Hᵀ = [ℓ]ₓ,   ℓ = (tr M I − M) ω,   Ḟ = [ω]ₓ F,   H = [ω]ₓ F J.

Plastic flow and bulk viscosity act on the ringing only, which they damp; their
effect on the mean is the plastic drift the ringing leaves behind, ΔEₚ ≈
(2μ/η)·|D|/ω̂² (a linear oscillator ẍ = −ω²(x − xₚ), ẋₚ = r(x − xₚ) started at
x = xₚ with speed v ends with xₚ = r v/ω²; 2e-5 for the Al cloud's |D| ~ 1/µs),
and the centrifugal strain (|ω|/ω̂)² ~ 1e-5 is left out likewise.  The model is
valid while the ringing is small (|D|/ω̂ ≪ 1) and r = 2μ/η ≪ ω̂ (a stiffly
plastic, fluid-like particle would flow with its deformation rate instead).

The step, per particle:

1. projection at t = 0: R₀ the rotation of the polar decomposition F₀ = R₀U₀
   (Higham's iteration X ← ½(X + X⁻ᵀ)); G = R₀U*(Eₚ) (U* by Jacobi
   eigenvectors of C*); ℓ = axial(H₀F₀ᵀ − F₀H₀ᵀ); the principal axes Q and
   moments mᵢ of M = G J Gᵀ (Jacobi), body inertia Iᵢ = tr m − mᵢ, body
   momentum π = Qᵀℓ.  The ringing's energy, ½ tr(H₀J⁻¹H₀ᵀ) + U(F₀) minus the
   rigid ½ Σ πᵢ²/Iᵢ, is dropped here (it is what plastic flow and bulk
   viscosity dissipate in the full model, or what rings forever when η = ∞
   and ζ = 0);
2. n steps of the free rigid body P(t) (body → space, P(0) = Q) by the splitting
   of T = Σᵢ πᵢ²/(2Iᵢ) into three rotations about the body axes, each exact
   (McLachlan 1993, Phys. Rev. Lett. 71, 3043; Dullweber, Leimkuhler &
   McLachlan 1997, J. Chem. Phys. 107, 5840)::

       Tᵢ(τ):  θ = τ πᵢ/Iᵢ,  π ← Rotᵢ(θ)ᵀ π,  P ← P Rotᵢ(θ),

   in the symmetric Strang order T₁(h/2)T₂(h/2)T₃(h)T₂(h/2)T₁(h/2), composed to
   order 4 by Suzuki's fractal (1990, Phys. Lett. A 146, 319): five Strang steps
   γh, γh, (1 − 4γ)h, γh, γh, γ = 1/(4 − 4^{1/3}), the T₁ that meet merged (20
   rotations a step).  Each rotation is by its
   Cayley form c = (1 − t²)/(1 + t²), s = 2t/(1 + t²), t = tan(θ/2) (a series
   for small θ), orthogonal to rounding: ℓ = P π is kept to rounding, the
   energy error of the symplectic composition stays bounded (no drift);
3. the state at t: R = P Qᵀ, F = R G, H = [P ω_b]ₓ F J with ω_b = π/I,
   Eₚ unchanged, p unchanged, c = c₀ + t p/m (exact: linear momentum is
   conserved exactly).

Step control (the slow dynamics'): ``steps_per_period`` counts steps per rigid
rotation period 2π/ω_max, ω_max = |π|/min Iᵢ ≥ |ω(t)|; each particle takes
n = max(1, ⌈t_end ω_max · steps_per_period/2π⌉) equal steps ending on t_end
(default :data:`STEPS_PER_ROTATION`), or n = ⌈t_end/dt⌉ when ``dt`` is given.
A particle that does not rotate takes one step.  The integrator's error is
therefore that of the averaging (the ringing amplitude, of order |D|/ω̂ in F,
and the O(r|D|/ω̂², (|ω|/ω̂)²) drifts above) plus the rotation's phase error
(4th order in |ω|h), not a convergence to the full solution as h → 0.  At 24
steps per rotation the phase error is far below the averaging error: on the
benchmark cloud (15 µs, |ω| ~ 1/µs) the arrival vertices move by at most 2e-6 cm
against 800 steps per rotation (3e-5 cm at 12, 1e-7 cm at 48; the ringing
amplitude is ~1e-5 to 1e-4 cm), ~54 steps per particle.

Where the averaging is not enough: near the separatrix of the free rigid body
(spin close to the intermediate principal axis, 2E I₂/|ℓ|² ≈ 1) the rigid motion is
hypersensitive, and the O(ε², (|ω|/ω̂)²) terms left out grow.  For a cell
tetrahedron with a random velocity gradient (std g) the time-averaged F follows
DOP853 (η = 1) over 15 µs to 5e-5 at g = 0.1/µs, 1.5e-4 at 0.3/µs and 1.6e-3 at
1/µs (|D|/ω̂ ~ 5e-3; the last includes the ringing left in the 0.1-µs average);
a particle 0.1 % off the separatrix at g = 0.3/µs drifts to 1.4e-3 at 5 µs and
1.3e-2 at 15 µs.  The Whipple particles ring with |D|/ω̂ ≈ 7e-4 (median; 2e-3 at
the 99th percentile) and spin at |W| ≈ 0.05/µs (median).

Failure codes as the other integrators: an initial state that is not finite or
has det F ≤ 0 is returned unchanged with its code; a projection that gives a
non-finite state (C* not positive definite) is NAN; max_steps < n is
STEP_BUDGET with the state at the last step.
"""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from impactdyn.debris import _mat3 as m3
from impactdyn.debris._failure import BUDGET, OK, state_failure
from impactdyn.debris._particle import C_SLICE, P_SLICE, STATE_ROWS, kernel
from impactdyn.debris._registry import ParticleBatch, StepControl, register_integrator

STEPS_PER_ROTATION = 24.0
"""Default steps per rigid rotation period 2π/ω_max (docs/vv/convergence.md, "Integrator steps":
order 4 in the rotation step, 1.9e-6 cm at 24)."""

SUZUKI_GAMMA = 1.0 / (4.0 - 4.0 ** (1.0 / 3.0))
"""γ of Suzuki's fourth-order fractal composition of a symmetric second-order step."""

_OK, _BUDGET = OK, BUDGET  # failure codes as compile-time constants
_ITERATIONS = 60  # cap of the polar, Newton and Jacobi iterations (each converges in a handful)


@m3.inline
def _polar_rotation(F):
    """R of F = RU (det F > 0) by Higham's iteration X ← ½(X + X⁻ᵀ), quadratically convergent."""
    X = F
    for _ in range(_ITERATIONS):
        Y = m3.scale(0.5, m3.add(X, m3.transpose(m3.inv(X))))
        d = m3.sub(Y, X)
        X = Y
        if m3.trace_of_product(d, m3.transpose(d)) < 1e-30:
            break
    return X


@m3.inline
def _jacobi_eigen(A):
    """(V, λ₀, λ₁, λ₂) with A = V diag(λ) Vᵀ, det V = 1, of a symmetric A by cyclic Jacobi rotations.

    Rotation (p, q) with t = sgn θ/(|θ| + √(θ² + 1)), θ = (a_qq − a_pp)/(2a_pq),
    c = 1/√(t² + 1), s = tc: A ← PᵀAP, V ← VP (Numerical Recipes §11.1).
    """
    V = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    for _ in range(_ITERATIONS):
        off = A[1] * A[1] + A[2] * A[2] + A[5] * A[5]
        if off <= 1e-32 * (A[0] * A[0] + A[4] * A[4] + A[8] * A[8]):
            break
        for pq in range(3):
            p, q = (0, 0, 1)[pq], (1, 2, 2)[pq]
            apq = A[3 * p + q]
            if apq == 0.0:
                continue
            theta = (A[3 * q + q] - A[3 * p + p]) / (2.0 * apq)
            t = (1.0 if theta >= 0.0 else -1.0) / (abs(theta) + math.sqrt(theta * theta + 1.0))
            c = 1.0 / math.sqrt(t * t + 1.0)
            s = t * c
            P = _plane_rotation(pq, c, s)
            A = m3.mtm(P, m3.mm(A, P))
            V = m3.mm(V, P)
    if m3.det(V) < 0.0:
        V = (V[0], V[1], -V[2], V[3], V[4], -V[5], V[6], V[7], -V[8])
    return V, A[0], A[4], A[8]


@m3.inline
def _plane_rotation(pq, c, s):
    """The identity with P_pp = P_qq = c, P_pq = s, P_qp = −s for (p, q) = (0, 1), (0, 2), (1, 2) by pq."""
    if pq == 0:
        return (c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0)
    if pq == 1:
        return (c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
    return (1.0, 0.0, 0.0, 0.0, c, s, 0.0, -s, c)


@m3.inline
def _stress_free_stretch(Ep):
    """U* = √C*, C* = 2Eₚ + cI with det C* = 1 (module docstring); NaN entries when C* is not positive definite."""
    A = m3.scale(2.0, Ep)
    tr = m3.trace(A)
    i2 = 0.5 * (tr * tr - m3.trace_of_product(A, A))
    da = m3.det(A)
    c = 1.0
    for _ in range(_ITERATIONS):  # det(A + cI) − 1 = c³ + c² tr A + c I₂(A) + det A − 1
        f = ((c + tr) * c + i2) * c + da - 1.0
        dc = f / ((3.0 * c + 2.0 * tr) * c + i2)
        c -= dc
        if abs(dc) < 1e-16:
            break
    V, l0, l1, l2 = _jacobi_eigen(m3.axpy(c, (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0), A))
    r0, r1, r2 = math.sqrt(l0), math.sqrt(l1), math.sqrt(l2)  # NaN for a negative eigenvalue
    return m3.mm(V, m3.mm((r0, 0.0, 0.0, 0.0, r1, 0.0, 0.0, 0.0, r2), m3.transpose(V)))


@m3.inline
def _cayley(theta):
    """(cos θ, sin θ) as (1 − t²)/(1 + t²), 2t/(1 + t²), t = tan(θ/2): exactly c² + s² = 1 in exact arithmetic."""
    x = 0.5 * theta
    if abs(x) < 0.1:  # tan x by its series, error < 1e-14 x
        x2 = x * x
        t = x * (1.0 + x2 * (1.0 / 3.0 + x2 * (2.0 / 15.0 + x2 * (17.0 / 315.0 + x2 * (62.0 / 2835.0)))))
    else:
        t = math.tan(x)
    d = 1.0 / (1.0 + t * t)
    return (1.0 - t * t) * d, 2.0 * t * d


@m3.inline
def _turn(c, s, a, b):
    """(a, b) turned: (c a + s b, c b − s a)."""
    return c * a + s * b, c * b - s * a


@m3.inline
def _body_rotation(i, tau, pi0, pi1, pi2, inertia, P):
    """Tᵢ(τ): the exact flow of πᵢ²/(2Iᵢ) — π ← Rotᵢ(θ)ᵀπ, P ← P Rotᵢ(θ), θ = τπᵢ/Iᵢ (module docstring).

    Rotᵢ turns the plane of the axes (j, k) = (i + 1, i + 2) mod 3: π's components
    j, k and P's columns j, k.
    """
    if i == 0:
        c, s = _cayley(tau * pi0 / inertia[0])
        pi1, pi2 = _turn(c, s, pi1, pi2)
        a0, b0 = _turn(c, s, P[1], P[2])
        a1, b1 = _turn(c, s, P[4], P[5])
        a2, b2 = _turn(c, s, P[7], P[8])
        return pi0, pi1, pi2, (P[0], a0, b0, P[3], a1, b1, P[6], a2, b2)
    if i == 1:
        c, s = _cayley(tau * pi1 / inertia[1])
        pi2, pi0 = _turn(c, s, pi2, pi0)
        a0, b0 = _turn(c, s, P[2], P[0])
        a1, b1 = _turn(c, s, P[5], P[3])
        a2, b2 = _turn(c, s, P[8], P[6])
        return pi0, pi1, pi2, (b0, P[1], a0, b1, P[4], a1, b2, P[7], a2)
    c, s = _cayley(tau * pi2 / inertia[2])
    pi0, pi1 = _turn(c, s, pi0, pi1)
    a0, b0 = _turn(c, s, P[0], P[1])
    a1, b1 = _turn(c, s, P[3], P[4])
    a2, b2 = _turn(c, s, P[6], P[7])
    return pi0, pi1, pi2, (a0, b0, P[2], a1, b1, P[5], a2, b2, P[8])


@m3.inline
def _inner(tau, pi0, pi1, pi2, inertia, P):
    """T₂(τ/2) T₃(τ) T₂(τ/2): the inside of the Strang step T₁(τ/2) T₂(τ/2) T₃(τ) T₂(τ/2) T₁(τ/2)."""
    pi0, pi1, pi2, P = _body_rotation(1, 0.5 * tau, pi0, pi1, pi2, inertia, P)
    pi0, pi1, pi2, P = _body_rotation(2, tau, pi0, pi1, pi2, inertia, P)
    return _body_rotation(1, 0.5 * tau, pi0, pi1, pi2, inertia, P)


@m3.inline
def _rigid_steps(n, h, pi0, pi1, pi2, inertia, P):
    """n steps of Suzuki's order-4 composition of five Strang steps γh, γh, (1 − 4γ)h, γh, γh.

    The T₁ halves that meet, between Strang steps and between steps, are one T₁ of
    the summed time (the flow of T₁ keeps π₁, so it composes by adding times):
    20 body rotations per step instead of 25.
    """
    g = SUZUKI_GAMMA
    g3 = 1.0 - 4.0 * g
    pi0, pi1, pi2, P = _body_rotation(0, 0.5 * g * h, pi0, pi1, pi2, inertia, P)
    for s in range(n):
        pi0, pi1, pi2, P = _inner(g * h, pi0, pi1, pi2, inertia, P)
        pi0, pi1, pi2, P = _body_rotation(0, g * h, pi0, pi1, pi2, inertia, P)
        pi0, pi1, pi2, P = _inner(g * h, pi0, pi1, pi2, inertia, P)
        pi0, pi1, pi2, P = _body_rotation(0, 0.5 * (g + g3) * h, pi0, pi1, pi2, inertia, P)
        pi0, pi1, pi2, P = _inner(g3 * h, pi0, pi1, pi2, inertia, P)
        pi0, pi1, pi2, P = _body_rotation(0, 0.5 * (g3 + g) * h, pi0, pi1, pi2, inertia, P)
        pi0, pi1, pi2, P = _inner(g * h, pi0, pi1, pi2, inertia, P)
        pi0, pi1, pi2, P = _body_rotation(0, g * h, pi0, pi1, pi2, inertia, P)
        pi0, pi1, pi2, P = _inner(g * h, pi0, pi1, pi2, inertia, P)
        # the closing T₁(γh/2) of this step and the opening T₁(γh/2) of the next
        pi0, pi1, pi2, P = _body_rotation(0, (g if s + 1 < n else 0.5 * g) * h, pi0, pi1, pi2, inertia, P)
    return pi0, pi1, pi2, P


@m3.inline
def _skew(w0, w1, w2):
    """[w]ₓ, the matrix of w × ·."""
    return (0.0, -w2, w1, w2, 0.0, -w0, -w1, w0, 0.0)


@kernel
def _advance_one(Y, Jinv, t_end, steps_per_rotation, dt, max_steps):
    """Project one particle ``Y (11, 3)`` on the slow manifold and rotate it rigidly to t_end (in place).

    Jinv ``(3, 3)``; dt ≤ 0: the step from steps_per_rotation. Returns (t_reached,
    steps, code); c is left for the caller. (A separate kernel: numba's parfor pass
    cannot analyse the inlined tuple algebra inside a prange body.)
    """
    code = state_failure(Y)
    if code != _OK or t_end <= 0.0:
        return 0.0, 0, code
    H, F, Ep = m3.mat(Y[0:3]), m3.mat(Y[3:6]), m3.mat(Y[6:9])
    J = m3.inv(m3.mat(Jinv))
    G = m3.mm(_polar_rotation(F), _stress_free_stretch(Ep))
    A = m3.sub(m3.mm(H, m3.transpose(F)), m3.mm(F, m3.transpose(H)))  # [ℓ]ₓ
    Q, m0, m1, m2 = _jacobi_eigen(m3.mm(G, m3.mm(J, m3.transpose(G))))
    inertia = (m1 + m2, m0 + m2, m0 + m1)
    l0, l1, l2 = A[7], A[2], A[3]
    pi0 = Q[0] * l0 + Q[3] * l1 + Q[6] * l2  # π = Qᵀℓ
    pi1 = Q[1] * l0 + Q[4] * l1 + Q[7] * l2
    pi2 = Q[2] * l0 + Q[5] * l1 + Q[8] * l2
    if dt > 0.0:
        n_steps = max(1, math.ceil(t_end / dt * (1.0 - 1e-9)))
    else:
        w_max = math.sqrt(pi0 * pi0 + pi1 * pi1 + pi2 * pi2) / min(inertia[0], inertia[1], inertia[2])
        n_steps = max(1, math.ceil(t_end * w_max * steps_per_rotation / (2.0 * math.pi)))
    h = t_end / n_steps
    taken = min(n_steps, max_steps)
    pi0, pi1, pi2, P = _rigid_steps(taken, h, pi0, pi1, pi2, inertia, Q)
    # F = R G, R = P Qᵀ; without angular momentum R = I exactly (P Qᵀ would be I to rounding)
    Fr = m3.mm(P, m3.mtm(Q, G)) if l0 != 0.0 or l1 != 0.0 or l2 != 0.0 else G
    w = m3.mm(P, (pi0 / inertia[0], 0.0, 0.0, pi1 / inertia[1], 0.0, 0.0, pi2 / inertia[2], 0.0, 0.0))
    Hr = m3.mm(_skew(w[0], w[3], w[6]), m3.mm(Fr, J))  # H = [ω]ₓ F J, ω = P ω_b
    for k in range(9):
        Y[k // 3, k % 3] = Hr[k]
        Y[3 + k // 3, k % 3] = Fr[k]
    code = state_failure(Y)
    if code == _OK and taken < n_steps:
        code = _BUDGET
    return (t_end if taken == n_steps else taken * h), taken, code


@kernel(parallel=True)
def _advance_all(y, Jinv, t_end, steps_per_rotation, dt, max_steps, t_reached, steps, code):
    """:func:`_advance_one` on every particle of ``y (N, 33)``; Jinv ``(N, 3, 3)``; t_end, dt, outputs ``(N,)``."""
    for n in prange(y.shape[0]):
        t_reached[n], steps[n], code[n] = _advance_one(y[n].reshape((STATE_ROWS, 3)), Jinv[n], t_end[n],
                                                       steps_per_rotation, dt[n], max_steps)


@register_integrator("slow", averaging=True)
def integrate(batch: ParticleBatch, control: StepControl):
    """The slow-manifold integrator (module docstring) as an :data:`~._registry.IntegratorFn`."""
    y, t_out, counts = batch.outputs()
    dt = np.zeros(len(y)) if control.dt is None else batch.per_particle(control.dt)
    steps, code = np.zeros(len(y), dtype=np.int64), np.zeros(len(y), dtype=np.int64)
    _advance_all(y, batch.Jinv, batch.t_end, control.steps_per_period or STEPS_PER_ROTATION, dt,
                 control.max_steps, t_out, steps, code)
    y[:, C_SLICE] += t_out[:, None] * y[:, P_SLICE] / batch.m[:, None]  # c(t) = c(0) + t p/m, exact (ṗ = 0)
    counts[:, 0], counts[:, 2] = steps, code
    return y, t_out, counts


__all__ = ["STEPS_PER_ROTATION", "SUZUKI_GAMMA"]
