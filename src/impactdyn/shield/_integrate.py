"""SPH equations of motion and their time integration (updated Lagrangian, 3-D).

Discrete equations (Libersky & Petschek 1991, 1993; Monaghan 1992, 2005; Gray,
Monaghan & Swift 2001), with σ = −pI + S, ∇ᵢWᵢⱼ = ∇ᵢW(xᵢ − xⱼ, hᵢⱼ),
hᵢⱼ = (hᵢ + hⱼ)/2, vᵢⱼ = vᵢ − vⱼ and the pair tensor::

    Tᵢⱼ = σᵢ/ρᵢ² + σⱼ/ρⱼ² − Πᵢⱼ I + (Rᵢ + Rⱼ) fᵢⱼⁿ

    dρᵢ/dt      = Σⱼ mⱼ vᵢⱼ · ∇ᵢWᵢⱼ                    (continuity)
    dvᵢ/dt      = Σⱼ mⱼ Tᵢⱼ · ∇ᵢWᵢⱼ                     (momentum)
    deᵢ/dt      = −½ Σⱼ mⱼ vᵢⱼ · Tᵢⱼ · ∇ᵢWᵢⱼ            (energy)
    ∂vᵢ^α/∂x^β  = −Σⱼ (mⱼ/ρⱼ) vᵢⱼ^α ∂_βWᵢⱼ               (velocity gradient, for the Jaumann rate)

Tᵢⱼ = Tⱼᵢ and ∇ᵢWᵢⱼ = −∇ⱼWⱼᵢ, so pair forces are equal and opposite: the total
momentum changes only by round-off, and d/dt Σ mᵢ(½vᵢ² + eᵢ) = 0 exactly in the
semi-discrete equations (the energy equation is the compatible one). Boundary
images (:mod:`._neighbours`) enter the sums as neighbours j with the mirrored or
shifted state; the force of i's image on j mirrors the force of j's image on i,
so a symmetry plane x = c conserves the y and z momentum exactly (it exchanges
x-momentum with the mirror half, as it must) and periodic axes conserve all three.

* Artificial viscosity (Monaghan 1992, eq. 4.1), for vᵢⱼ·xᵢⱼ < 0::

      Πᵢⱼ = (−α c̄ᵢⱼ μᵢⱼ + β μᵢⱼ²)/ρ̄ᵢⱼ,   μᵢⱼ = hᵢⱼ vᵢⱼ·xᵢⱼ / (|xᵢⱼ|² + 0.01 hᵢⱼ²)

  defaults α = 1, β = 2 (a strong-shock setting; the linear term damps the
  post-shock ringing, the quadratic one prevents interpenetration).
* Artificial stress Rᵢ (:mod:`._strength`) with fᵢⱼ = W(rᵢⱼ, hᵢⱼ)/W(hᵢⱼ/κ, hᵢⱼ)
  (the initial spacing Δp = h/κ), defaults ε = 0.3, n = 4 (Gray, Monaghan &
  Swift 2001).
* Density by the continuity equation, not by summation: summation density is
  deficient within 2h of free surfaces and smears the density jump at the
  projectile–plate interface, both of which are everywhere in a thin-plate
  perforation; the continuity form starts from ρ₀ everywhere and needs no
  surface correction (Libersky & Petschek 1993). It is integrated for ln ρ
  (rate ρ̇ᵢ/ρᵢ, exponential update) under a step limit on the relative density
  change (below), which keeps ρ > 0 however fast failed debris expands: the
  linear update ρ + Δt ρ̇ drove a particle of the 10 km/s Table 2 shot to a
  negative density. Below ρ₀/h_max_factor³ (where h stops growing) the rate is
  ρ̇ᵢ/(ρ₀/h_max_factor³): such a particle is failed debris in free flight with
  p = 0, and ρ̇ᵢ/ρᵢ of a nearly empty particle meeting a neighbour collapsed the
  step (Table 2 shot 10b, 2.8 µs).
* Smoothing length hᵢ = κ (mᵢ/ρᵢ)^{1/3} — the exact integral of
  dh/dt = −(h/3)(dρ/dt)/ρ — with ρ floored at ρ₀/h_max_factor³ so that h grows
  at most h_max_factor-fold in expanding debris.
* Failure: a particle with p < −p_spall or εₚ > εₚ,f is flagged failed for good;
  failed particles carry p ≥ 0 and S = 0. Failed material therefore expands
  freely, and its continuity density falls with the local divergence: in a
  fragment cloud a particle's density is the bulk density of the cloud around
  it (the binning's mass and bulk density (1 − φ)ρ are unaffected by this).

Time integration: kick–drift–kick leapfrog with a predicted state for the force
evaluation, one neighbour search and one force pass per step (Springel 2005
GADGET-2 §5 form)::

    v^{n+½} = vⁿ + ½Δt aⁿ,    xⁿ⁺¹ = xⁿ + Δt v^{n+½}
    predictor:  v* = v^{n+½} + ½Δt aⁿ,
                (e, S)* = (e, S)ⁿ + Δt (ė, Ṡ)ⁿ, ρ* = ρⁿ exp(Δt (ρ̇/ρ)ⁿ), S* returned to the yield surface
    rates at xⁿ⁺¹ and the predicted state → aⁿ⁺¹, (ρ̇/ρ, ė, Ṡ)ⁿ⁺¹
    corrector:  vⁿ⁺¹ = v^{n+½} + ½Δt aⁿ⁺¹,
                (e, S)ⁿ⁺¹ = (e, S)ⁿ + ½Δt [(ė, Ṡ)ⁿ + (ė, Ṡ)ⁿ⁺¹],
                ρⁿ⁺¹ = ρⁿ exp(½Δt [(ρ̇/ρ)ⁿ + (ρ̇/ρ)ⁿ⁺¹]),
                radial return of Sⁿ⁺¹ (accumulating εₚ), failure check

Each kick adds Σ mᵢ aᵢ Δt/2 = 0, so momentum is conserved to round-off at any Δt.
Time step (Monaghan 1992, eq. 4.12)::

    Δt = min_i min( C_cfl hᵢ / (cᵢ + 1.2 (α cᵢ + β maxⱼ|μᵢⱼ|)),  C_f √(hᵢ/|aᵢ|),  C_cfl ρᵢ/|ρ̇ᵢ| )

the relative velocity of approaching neighbours entering through μᵢⱼ
(defaults C_cfl = 0.3, C_f = 0.25); the last term bounds the density change of
a step (it binds only in fast expansion, where the first two do not see the flow).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numba import njit, prange

from impactdyn._errors import InputError
from impactdyn.shield._eos import (C0, EPS_FAIL, GAMMA0, P_SPALL, RHO0, SHEAR, SLOPE, pack_materials, pressure,
                                   sound_speed, temperature)
from impactdyn.shield._kernel import gradient_factor, w_shape
from impactdyn.shield._neighbours import NeighbourList, spatial_order
from impactdyn.shield._state import History, Particles, RunResult
from impactdyn.shield._strength import artificial_stress, flow_stress, jaumann_rate, radial_return

FLOW_STRESS_MODELS = ("perfectly_plastic", "johnson_cook")


class SPHError(RuntimeError):
    """The SPH run broke down (non-finite state or a collapsing time step)."""


@dataclass(frozen=True)
class SPHOptions:
    """Numerical parameters of the SPH stage (module docstring).

    alpha, beta : artificial viscosity coefficients.
    artificial_stress, artificial_stress_power : ε and n of the artificial stress (ε = 0 disables it).
    h_factor : κ in h = κ (m/ρ)^{1/3} (h over the particle spacing).
    h_max_factor : the largest growth of h under expansion.
    cfl, force_cfl : time-step factors.
    flow_stress : "perfectly_plastic" (Y = Y₀) or "johnson_cook".
    failure : apply the spall / plastic-strain failure criteria of the materials.
    """

    alpha: float = 1.0
    beta: float = 2.0
    artificial_stress: float = 0.3
    artificial_stress_power: int = 4
    h_factor: float = 1.3
    h_max_factor: float = 2.0
    cfl: float = 0.3
    force_cfl: float = 0.25
    flow_stress: str = "perfectly_plastic"
    failure: bool = True

    def __post_init__(self) -> None:
        for name in ("alpha", "beta", "artificial_stress"):
            if not (math.isfinite(getattr(self, name)) and getattr(self, name) >= 0):
                raise InputError(f"SPHOptions.{name}: must be ≥ 0, got {getattr(self, name)!r}")
        if not (isinstance(self.artificial_stress_power, int) and 1 <= self.artificial_stress_power <= 8):
            raise InputError(f"SPHOptions.artificial_stress_power: must be an integer in [1, 8], "
                             f"got {self.artificial_stress_power!r}")
        for name in ("cfl", "force_cfl"):
            if not 0 < getattr(self, name) <= 1:
                raise InputError(f"SPHOptions.{name}: must be in (0, 1], got {getattr(self, name)!r}")
        if not 0.8 <= self.h_factor <= 2.5:
            raise InputError(f"SPHOptions.h_factor: must be in [0.8, 2.5], got {self.h_factor!r}")
        if not self.h_max_factor >= 1:
            raise InputError(f"SPHOptions.h_max_factor: must be ≥ 1, got {self.h_max_factor!r}")
        if self.flow_stress not in FLOW_STRESS_MODELS:
            raise InputError(f"SPHOptions.flow_stress: {self.flow_stress!r}, expected one of {FLOW_STRESS_MODELS}")


@njit(cache=True)
def _particle_eos(i, m, rho, e, S, failed, mat, params, h_factor, rho_floor, eps_as, p, c, h, R, tension,
                  sr, vol, work_a, work_v):
    """Pressure p, sound speed c, smoothing length h, artificial stress R, σ/ρ² (sr) and m/ρ (vol) of particle i."""
    k = mat[i]
    rho0 = params[k, RHO0]
    pi = pressure(rho[i], e[i], rho0, params[k, C0], params[k, SLOPE], params[k, GAMMA0])
    if failed[i]:
        pi = max(pi, 0.0)
    p[i] = pi
    c[i] = sound_speed(rho[i], pi, rho0, params[k, C0], params[k, SLOPE], params[k, GAMMA0])
    h[i] = h_factor * (m[i] / max(rho[i], rho0 * rho_floor)) ** (1.0 / 3.0)
    q = 1.0 / (rho[i] * rho[i])
    for d in range(6):
        sr[i, d] = (S[i, d] - pi * (d < 3)) * q
    vol[i] = m[i] / rho[i]
    tension[i] = False
    if eps_as > 0.0:
        tension[i] = artificial_stress(S, pi, rho[i], eps_as, i, R, work_a, work_v)


@njit(parallel=True, cache=True)
def update_particles(m, rho, e, S, failed, mat, params, h_factor, rho_floor, eps_as, p, c, h, R, tension, sr, vol,
                     work_a, work_v):
    """p, c, h, R, σ/ρ² and m/ρ of every particle (:func:`_particle_eos`)."""
    for i in prange(m.size):
        _particle_eos(i, m, rho, e, S, failed, mat, params, h_factor, rho_floor, eps_as, p, c, h, R, tension, sr,
                      vol, work_a, work_v)


@njit(parallel=True, cache=True)
def compute_rates(x, v, m, rho, rho_floor, c, h, S, sr, vol, R, tension, failed, mat, params, nbr, img, count,
                  signs, offsets, alpha, beta, as_power, as_norm, cfl, force_cfl, grad_v, acc, dlnrho, de, dS, rate, dt_i):
    """Rates of every particle (module docstring) and its stable time step dt_i.

    sr (N, 6): σ/ρ² of every particle; vol (N,): m/ρ.
    """
    for i in prange(m.size):
        xi0, xi1, xi2 = x[i, 0], x[i, 1], x[i, 2]
        vi0, vi1, vi2 = v[i, 0], v[i, 1], v[i, 2]
        hi, ci, rhoi = h[i], c[i], rho[i]
        axx, ayy, azz, axy, ayz, azx = sr[i, 0], sr[i, 1], sr[i, 2], sr[i, 3], sr[i, 4], sr[i, 5]
        a0 = a1 = a2 = 0.0
        dr = du = 0.0
        l00 = l01 = l02 = l10 = l11 = l12 = l20 = l21 = l22 = 0.0
        mu_max = 0.0
        for k in range(count[i]):
            j = nbr[i, k]
            t = img[i, k]
            s0, s1, s2 = signs[t, 0], signs[t, 1], signs[t, 2]
            dx0 = xi0 - (s0 * x[j, 0] + offsets[t, 0])
            dx1 = xi1 - (s1 * x[j, 1] + offsets[t, 1])
            dx2 = xi2 - (s2 * x[j, 2] + offsets[t, 2])
            r2 = dx0 * dx0 + dx1 * dx1 + dx2 * dx2
            hij = 0.5 * (hi + h[j])
            r = math.sqrt(r2)
            if r >= 2.0 * hij:
                continue
            f = gradient_factor(r, hij)
            g0, g1, g2 = f * dx0, f * dx1, f * dx2
            dv0 = vi0 - s0 * v[j, 0]
            dv1 = vi1 - s1 * v[j, 1]
            dv2 = vi2 - s2 * v[j, 2]
            # σⱼ/ρⱼ² of the image: components (α, β) pick up s_α s_β
            bxx, byy, bzz = sr[j, 0], sr[j, 1], sr[j, 2]
            bxy, byz, bzx = s0 * s1 * sr[j, 3], s1 * s2 * sr[j, 4], s2 * s0 * sr[j, 5]
            vr = dv0 * dx0 + dv1 * dx1 + dv2 * dx2
            visc = 0.0
            if vr < 0.0:
                mu = hij * vr / (r2 + 0.01 * hij * hij)
                visc = (-alpha * 0.5 * (ci + c[j]) * mu + beta * mu * mu) / (0.5 * (rhoi + rho[j]))
                mu_max = max(mu_max, -mu)
            txx = axx + bxx - visc
            tyy = ayy + byy - visc
            tzz = azz + bzz - visc
            txy = axy + bxy
            tyz = ayz + byz
            tzx = azx + bzx
            if tension[i] or tension[j]:
                fn = 1.0
                fij = w_shape(r / hij) * as_norm
                for _ in range(as_power):
                    fn *= fij
                txx += (R[i, 0] + R[j, 0]) * fn
                tyy += (R[i, 1] + R[j, 1]) * fn
                tzz += (R[i, 2] + R[j, 2]) * fn
                txy += (R[i, 3] + s0 * s1 * R[j, 3]) * fn
                tyz += (R[i, 4] + s1 * s2 * R[j, 4]) * fn
                tzx += (R[i, 5] + s2 * s0 * R[j, 5]) * fn
            mj = m[j]
            tg0 = txx * g0 + txy * g1 + tzx * g2
            tg1 = txy * g0 + tyy * g1 + tyz * g2
            tg2 = tzx * g0 + tyz * g1 + tzz * g2
            a0 += mj * tg0
            a1 += mj * tg1
            a2 += mj * tg2
            du -= 0.5 * mj * (dv0 * tg0 + dv1 * tg1 + dv2 * tg2)
            dr += mj * (dv0 * g0 + dv1 * g1 + dv2 * g2)
            vj = vol[j]
            l00 -= vj * dv0 * g0
            l01 -= vj * dv0 * g1
            l02 -= vj * dv0 * g2
            l10 -= vj * dv1 * g0
            l11 -= vj * dv1 * g1
            l12 -= vj * dv1 * g2
            l20 -= vj * dv2 * g0
            l21 -= vj * dv2 * g1
            l22 -= vj * dv2 * g2
        acc[i, 0], acc[i, 1], acc[i, 2] = a0, a1, a2
        dlnrho[i] = dr / max(rhoi, params[mat[i], RHO0] * rho_floor)
        de[i] = du
        grad_v[i, 0, 0], grad_v[i, 0, 1], grad_v[i, 0, 2] = l00, l01, l02
        grad_v[i, 1, 0], grad_v[i, 1, 1], grad_v[i, 1, 2] = l10, l11, l12
        grad_v[i, 2, 0], grad_v[i, 2, 1], grad_v[i, 2, 2] = l20, l21, l22
        ds, rate[i] = jaumann_rate(S[i, 0], S[i, 1], S[i, 2], S[i, 3], S[i, 4], S[i, 5], grad_v, i,
                                   params[mat[i], SHEAR])
        for k in range(6):
            dS[i, k] = 0.0 if failed[i] else ds[k]
        amag = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
        dt_i[i] = cfl * hi / (ci + 1.2 * (alpha * ci + beta * mu_max))
        if amag > 0.0:
            dt_i[i] = min(dt_i[i], force_cfl * math.sqrt(hi / amag))
        if dlnrho[i] != 0.0:
            dt_i[i] = min(dt_i[i], cfl / abs(dlnrho[i]))


@njit(parallel=True, cache=True)
def kick_drift_predict(x, v, acc, rho, dlnrho, e, de, S, dS, eps_p, rate, failed, m, mat, params, johnson_cook,
                       h_factor, rho_floor, eps_as, dt, v_p, rho_p, e_p, S_p, p, c, h, R, tension, sr, vol, work_a,
                       work_v):
    """Half kick v ← v + ½Δt a, drift x ← x + Δt v, and the predicted state at the step's end.

    Predicted: v_p = v + ½Δt a, (e, S)_p = (e, S) + Δt (ė, Ṡ), ρ_p = ρ exp(Δt ρ̇/ρ), S_p returned to the
    yield surface; then its p, c, h and R (:func:`_particle_eos`).
    """
    for i in prange(m.size):
        k = mat[i]
        for d in range(3):
            v[i, d] += 0.5 * dt * acc[i, d]
            x[i, d] += dt * v[i, d]
            v_p[i, d] = v[i, d] + 0.5 * dt * acc[i, d]
        rho_p[i] = rho[i] * math.exp(dt * dlnrho[i])
        e_p[i] = e[i] + dt * de[i]
        for d in range(6):
            S_p[i, d] = S[i, d] + dt * dS[i, d]
        Y = flow_stress(params, k, johnson_cook, eps_p[i], rate[i], temperature(rho_p[i], e_p[i], params, k))
        radial_return(S_p, i, Y, params[k, SHEAR])
        _particle_eos(i, m, rho_p, e_p, S_p, failed, mat, params, h_factor, rho_floor, eps_as, p, c, h, R,
                      tension, sr, vol, work_a, work_v)


@njit(parallel=True, cache=True)
def correct(v, acc, rho, dlnrho_old, dlnrho, e, de_old, de, S, dS_old, dS, eps_p, rate, failed, mat, params,
            johnson_cook, failure, dt):
    """Corrector: second half kick, trapezoidal ln ρ, e, S, radial return (εₚ), failure check."""
    for i in prange(rho.size):
        k = mat[i]
        for d in range(3):
            v[i, d] += 0.5 * dt * acc[i, d]
        rho[i] *= math.exp(0.5 * dt * (dlnrho_old[i] + dlnrho[i]))
        e[i] += 0.5 * dt * (de_old[i] + de[i])
        for d in range(6):
            S[i, d] += 0.5 * dt * (dS_old[i, d] + dS[i, d])
        Y = flow_stress(params, k, johnson_cook, eps_p[i], rate[i], temperature(rho[i], e[i], params, k))
        eps_p[i] += radial_return(S, i, Y, params[k, SHEAR])
        if failure and not failed[i]:
            pi = pressure(rho[i], e[i], params[k, RHO0], params[k, C0], params[k, SLOPE], params[k, GAMMA0])
            if pi < -params[k, P_SPALL] or eps_p[i] > params[k, EPS_FAIL]:
                failed[i] = True
        if failed[i]:
            for d in range(6):
                S[i, d] = 0.0


@njit(parallel=True, cache=True)
def temperatures(rho, e, mat, params):
    """Temperature estimate of every particle (:func:`impactdyn.shield._eos.temperature`), K."""
    T = np.empty(rho.size)
    for i in prange(rho.size):
        T[i] = temperature(rho[i], e[i], params, mat[i])
    return T


@njit(parallel=True, cache=True)
def totals(m, v, e):
    """(Σm, Σm vₓ, Σm v_y, Σm v_z, Σ ½m|v|², Σ m e)."""
    mass = px = py = pz = kin = internal = 0.0
    for i in prange(m.size):
        mass += m[i]
        px += m[i] * v[i, 0]
        py += m[i] * v[i, 1]
        pz += m[i] * v[i, 2]
        kin += 0.5 * m[i] * (v[i, 0] ** 2 + v[i, 1] ** 2 + v[i, 2] ** 2)
        internal += m[i] * e[i]
    return mass, px, py, pz, kin, internal


class _Solver:
    """The arrays of one run and the step sequence (module docstring), allocated once.

    Particles are kept in spatial (cell-key) order for cache locality: every
    ``REORDER_EVERY`` steps the state and its rates are permuted; ``ids`` maps
    the stored order back to the problem's particle order.
    """

    REORDER_EVERY = 10
    STATE = ("x", "v", "m", "rho", "e", "S", "eps_p", "failed", "mat", "ids", "acc", "dlnrho", "de", "dS", "rate")

    def __init__(self, problem, options: SPHOptions):
        init = problem.particles
        n = len(init)
        self.options, self.domain, self.names = options, problem.domain, init.materials
        self.params = pack_materials(problem.materials)
        self.x, self.v = init.position.copy(), init.velocity.copy()
        self.m, self.rho, self.e = init.mass.copy(), init.density.copy(), init.specific_energy.copy()
        self.S, self.eps_p, self.failed = init.deviatoric_stress.copy(), init.plastic_strain.copy(), init.failed.copy()
        self.mat, self.ids = init.material.copy(), np.arange(n)
        z1, z3, z6 = (lambda: np.zeros(n)), (lambda: np.zeros((n, 3))), (lambda: np.zeros((n, 6)))
        self.p, self.c, self.h, self.rate, self.dt_i = z1(), z1(), z1(), z1(), z1()
        self.R, self.tension, self.sr, self.vol = z6(), np.zeros(n, dtype=np.bool_), z6(), z1()
        self.work_a, self.work_v, self.grad_v = np.zeros((n, 3, 3)), np.zeros((n, 3, 3)), np.zeros((n, 3, 3))
        self.acc, self.dlnrho, self.de, self.dS = z3(), z1(), z1(), z6()
        self.acc_new, self.dlnrho_new, self.de_new, self.dS_new = z3(), z1(), z1(), z6()
        self.v_p, self.rho_p, self.e_p, self.S_p = z3(), z1(), z1(), z6()
        self.neighbours = NeighbourList(n, problem.domain)
        self.jc = options.flow_stress == "johnson_cook"
        self.rho_floor = options.h_max_factor ** -3.0
        self.as_norm = 1.0 / float(w_shape(1.0 / options.h_factor))
        self.steps = 0
        self._eos(self.rho, self.e, self.S)
        self.dt = self._rates(self.v, self.rho, self.S, (self.acc, self.dlnrho, self.de, self.dS))

    def _eos(self, rho, e, S) -> None:
        o = self.options
        update_particles(self.m, rho, e, S, self.failed, self.mat, self.params, o.h_factor, self.rho_floor,
                         o.artificial_stress, self.p, self.c, self.h, self.R, self.tension, self.sr, self.vol,
                         self.work_a, self.work_v)

    def _rates(self, v, rho, S, out) -> float:
        """Neighbour search at the current positions and the rates of state (x, v, ρ, S) into ``out``; Δt."""
        o, nl = self.options, self.neighbours
        if 2.0 * self.h.max() > self.domain.min_period():
            raise SPHError(f"kernel support 2h = {2 * self.h.max():.4g} cm exceeds the periodic length "
                           f"{self.domain.min_period():.4g} cm")
        nl.update(self.x, self.h)
        acc, dlnrho, de, dS = out
        compute_rates(self.x, v, self.m, rho, self.rho_floor, self.c, self.h, S, self.sr, self.vol, self.R,
                      self.tension, self.failed, self.mat, self.params, nl.neighbours, nl.image, nl.count, nl.signs, nl.offsets, o.alpha, o.beta,
                      o.artificial_stress_power, self.as_norm, o.cfl, o.force_cfl, self.grad_v, acc, dlnrho, de, dS,
                      self.rate, self.dt_i)
        return float(self.dt_i.min())

    def totals(self) -> tuple[float, ...]:
        return totals(self.m, self.v, self.e)

    def step(self, dt: float) -> tuple[float, ...]:
        """Advance by dt (module docstring); returns the totals of the new state."""
        if self.steps % self.REORDER_EVERY == 0:
            order = spatial_order(self.x, self.h)
            for name in self.STATE:
                setattr(self, name, getattr(self, name)[order])
        o = self.options
        kick_drift_predict(self.x, self.v, self.acc, self.rho, self.dlnrho, self.e, self.de, self.S, self.dS,
                           self.eps_p, self.rate, self.failed, self.m, self.mat, self.params, self.jc, o.h_factor,
                           self.rho_floor, o.artificial_stress, dt, self.v_p, self.rho_p, self.e_p, self.S_p,
                           self.p, self.c, self.h, self.R, self.tension, self.sr, self.vol, self.work_a, self.work_v)
        self.domain.wrap(self.x)
        self.dt = self._rates(self.v_p, self.rho_p, self.S_p,
                              (self.acc_new, self.dlnrho_new, self.de_new, self.dS_new))
        correct(self.v, self.acc_new, self.rho, self.dlnrho, self.dlnrho_new, self.e, self.de, self.de_new, self.S,
                self.dS, self.dS_new, self.eps_p, self.rate, self.failed, self.mat, self.params, self.jc, o.failure,
                dt)
        self.acc, self.acc_new = self.acc_new, self.acc
        self.dlnrho, self.dlnrho_new = self.dlnrho_new, self.dlnrho
        self.de, self.de_new = self.de_new, self.de
        self.dS, self.dS_new = self.dS_new, self.dS
        self.steps += 1
        return self.totals()

    def particles(self, time: float) -> Particles:
        """The current state as :class:`Particles`, in the problem's particle order."""
        self._eos(self.rho, self.e, self.S)
        back = np.argsort(self.ids)
        T = temperatures(self.rho, self.e, self.mat, self.params)
        return Particles(position=self.x[back], velocity=self.v[back], mass=self.m[back], density=self.rho[back],
                         pressure=self.p[back], specific_energy=self.e[back], deviatoric_stress=self.S[back],
                         plastic_strain=self.eps_p[back], failed=self.failed[back], smoothing_length=self.h[back],
                         sound_speed=self.c[back], temperature=T[back], material=self.mat[back],
                         materials=self.names, time=time)


def run(problem, t_end_us: float, *, options: SPHOptions = SPHOptions(),
        snapshot_times_us: Sequence[float] = (), progress: Callable[[float, float], None] | None = None
        ) -> RunResult:
    """Integrate ``problem`` (:class:`impactdyn.shield.Problem`) from its initial state to ``t_end_us``.

    snapshot_times_us : times in (0, t_end] at which to keep the particle state (steps land on them).
    progress : called after every step as ``progress(t_us, t_end_us)`` (a CLI draws its progress bar).

    Returns a :class:`RunResult`: the final :class:`Particles`, the :class:`History`
    of mass, momentum, kinetic and internal energy after every step, and the snapshots.
    Raises :class:`SPHError` if the state stops being finite or the step collapses.
    """
    t_end = float(t_end_us)
    if not (math.isfinite(t_end) and t_end > 0):
        raise InputError(f"t_end_us: must be a positive number, got {t_end_us!r}")
    marks = sorted({float(t) for t in snapshot_times_us})
    if any(not (0 < t <= t_end) for t in marks):
        raise InputError(f"snapshot_times_us: every time must lie in (0, {t_end}], got {list(snapshot_times_us)}")
    targets = marks + ([t_end] if not marks or marks[-1] < t_end else [])

    solver = _Solver(problem, options)
    rows = [(0.0,) + solver.totals()]
    t, snapshots = 0.0, []
    for target in targets:
        while t < target:
            dt = solver.dt
            if not (math.isfinite(dt) and dt > 1e-9 * t_end):
                raise SPHError(f"time step {dt!r} µs at t = {t:.6g} µs (step {solver.steps}): the state is no "
                               "longer finite or the step collapsed")
            step = min(dt, target - t)
            sums = solver.step(step)
            t = target if target - t - step <= 1e-12 * t_end else t + step
            rows.append((t,) + sums)
            if progress is not None:
                progress(t, t_end)
        if target in marks:
            snapshots.append(solver.particles(target))
    h = np.array(rows)
    history = History(time=h[:, 0], mass=h[:, 1], momentum=h[:, 2:5], kinetic=h[:, 5], internal=h[:, 6])
    final = snapshots[-1] if marks and marks[-1] == t_end else solver.particles(t_end)
    return RunResult(state=final, history=history, snapshots=tuple(snapshots), steps=solver.steps)
