"""Rigid-link (Hencky) chain: an independent, fully nonlinear model of the hub–beam.

A check of the modal model's ``coupled`` option that shares none of its
approximations: the beam is cut into N rigid uniform links of length ℓ = L/N,
joined by rotational springs, with exact planar kinematics — no mode shapes, no
small-deflection expansion, no foreshortening integrals. Free motion only (no stop).

Coordinates: the hub angle θ and the absolute angles ψ₁…ψ_N of the links (from the
same inertial axis as θ); α = [θ, ψ₁…ψ_N]. The root of the beam sits on the hub at
radius A and is clamped along the hub's radius, so with e(φ) = (cos φ, sin φ) the
joints and link centres are::

    P₀ = A e(θ),   Pᵢ = Pᵢ₋₁ + ℓ e(ψᵢ),   Cᵢ = Pᵢ₋₁ + ½ℓ e(ψᵢ).

Hence Ċᵢ = Σₖ Rᵢₖ α̇ₖ e⊥(αₖ) with the lever table Rᵢ₀ = A, Rᵢⱼ = ℓ for links j < i,
Rᵢᵢ = ℓ/2, and with m = ρℓ, Sₖₗ = m Σᵢ RᵢₖRᵢₗ::

    T = ½ J_h θ̇² + ½ Σₖₗ Sₖₗ cos(αₖ − αₗ) α̇ₖ α̇ₗ + ½ (mℓ²/12) Σᵢ ψ̇ᵢ²,
    V = ½ k₀ (ψ₁ − θ)² + ½ k Σᵢ₌₂ᴺ (ψᵢ − ψᵢ₋₁)² + g Σₖ wₖ sin αₖ,   wₖ = m Σᵢ Rᵢₖ,

gravity acting along −e(π/2) as in the modal model (its hub term ρLg(A + L/2) sin θ).

Springs (Hencky bar-chain): k = EI/ℓ between links, the relative rotation of two
links being the curvature over one link length; at the clamp k₀ = 2EI/ℓ, because
the root spring carries the curvature of only half a link (the central-difference
clamp condition w₋₁ = w₁ gives κ₀ = 2ψ₁/ℓ). J_h = IR·ρL(A² + AL + L²/3) is the
hub's own inertia, as in the modal model (docs/theory/beam.md, eq. (4)). Lagrange's equations::

    Σₗ [Sₖₗ cos(αₖ − αₗ) + Dₖ δₖₗ] α̈ₗ = Qₖ − Σₗ Sₖₗ sin(αₖ − αₗ) α̇ₗ² − (Kα)ₖ − g wₖ cos αₖ,

D = (J_h, mℓ²/12, …), K the spring matrix of V, Q₀ = τ(t) − c θ̇ (torque pulse and
joint damping), Qᵢ = 0. As N → ∞ the chain tends to the inextensible
Euler–Bernoulli beam (no shear, no rotary inertia of the cross-section); its
small-amplitude frequencies converge as 1/N² (tests/beam/test_chain_reference.py).
The equations are integrated with SciPy's ``solve_ivp`` (DOP853), restarted at the
corners of the torque pulse.

With a light hub (the samples' IR = 0.002) each torque step sets the hub ringing at
frequencies the chain resolves only slowly: its hub angle converges irregularly in N
(at some instants the change halves, not quarters, from 32 to 64 links), and it stays
~2e-4 rad per N·m of torque from the converged linearised modal model at small torque,
in proportion to τ. Large-deflection effects are compared through the part of the
response nonlinear in τ, where this cancels (verification/verify_beam_chain.py).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit
from scipy.integrate import solve_ivp
from scipy.linalg import eigh

from impactdyn._errors import SimulationError
from impactdyn.beam._case import BeamCase
from impactdyn.beam._simulate import torque_schedule


@njit(cache=True)
def _chain_rhs(state, torque, S, D, springs, w, g, c):
    """d/dt [α, α̇] of the chain, (2N + 2,); arrays as in :class:`RigidLinkChain`."""
    n = D.shape[0]
    alpha, rate = state[:n], state[n:]
    cos_a, sin_a = np.cos(alpha), np.sin(alpha)
    M = np.empty((n, n))
    f = -g * w * cos_a
    f[0] += torque - c * rate[0]
    for k in range(n):
        for l in range(n):
            # cos(αₖ − αₗ) and sin(αₖ − αₗ)
            M[k, l] = S[k, l] * (cos_a[k] * cos_a[l] + sin_a[k] * sin_a[l])
            f[k] -= S[k, l] * (sin_a[k] * cos_a[l] - cos_a[k] * sin_a[l]) * rate[l] * rate[l]
        M[k, k] += D[k]
    for j in range(n - 1):  # spring j: moment springs[j] (α_{j+1} − α_j) on α_j, its reaction on α_{j+1}
        moment = springs[j] * (alpha[j + 1] - alpha[j])
        f[j] += moment
        f[j + 1] -= moment
    out = np.full(2 * n, np.nan)  # a wild trial step of the solver: NaN makes it reject the step
    out[:n] = rate
    if np.isfinite(M).all() and np.isfinite(f).all():
        out[n:] = np.linalg.solve(M, f)
    return out


@dataclass(frozen=True)
class ChainResult:
    """Output of :meth:`RigidLinkChain.simulate`.

    t : (m,) s.   theta, theta_dot : (m,) hub angle (rad) and rate (rad/s).
    psi : (m, N) link angles, rad.   tip_deflection : (m,) transverse tip
    displacement in the hub frame, ℓ Σ sin(ψᵢ − θ), m.
    """

    t: np.ndarray
    theta: np.ndarray
    theta_dot: np.ndarray
    psi: np.ndarray
    tip_deflection: np.ndarray


@dataclass(frozen=True)
class RigidLinkChain:
    """The chain of the module docstring for one beam case (SI).

    Attributes
    ----------
    n_links : N.      link : ℓ = L/N.
    S : (N + 1, N + 1) inertia coefficients Sₖₗ.   D : (N + 1,) own inertias (J_h, mℓ²/12, …).
    springs : (N,) stiffnesses (k₀, k, …, k); spring j turns with α_{j+1} − α_j.
    w : (N + 1,) gravity moment weights wₖ.
    gravity : g.   joint_damping : c.
    """

    n_links: int
    link: float
    S: np.ndarray
    D: np.ndarray
    springs: np.ndarray
    w: np.ndarray
    gravity: float
    joint_damping: float

    @classmethod
    def from_case(cls, case: BeamCase, n_links: int) -> "RigidLinkChain":
        """The chain of ``case``'s beam, hub, gravity and joint damping (modal damping,
        legacy options and the stop do not apply)."""
        bm = case.beam
        rho, L, A, EI = bm.mass_per_length_kg_m, bm.length_m, bm.hub_radius_m, bm.EI_N_m2
        N = n_links
        ell = L / N
        m = rho * ell
        R = np.zeros((N, N + 1))  # Ċᵢ = Σₖ Rᵢₖ α̇ₖ e⊥(αₖ)
        R[:, 0] = A
        for i in range(N):
            R[i, 1 : i + 1] = ell
            R[i, i + 1] = 0.5 * ell
        hub_inertia = bm.inertia_ratio * rho * L * (A * A + A * L + L * L / 3.0)
        D = np.full(N + 1, m * ell * ell / 12.0)
        D[0] = hub_inertia
        springs = np.full(N, EI / ell)
        springs[0] = 2.0 * EI / ell  # clamp: half-link rule
        return cls(n_links=N, link=ell, S=m * R.T @ R, D=D, springs=springs, w=m * R.sum(axis=0),
                   gravity=case.model.gravity_m_s2, joint_damping=case.damping.joint_N_m_s)

    def spring_matrix(self) -> np.ndarray:
        """K of V = ½ αᵀKα (the springs' part), (N + 1, N + 1)."""
        N = self.n_links
        diff = np.zeros((N, N + 1))
        diff[np.arange(N), np.arange(N)] = -1.0
        diff[np.arange(N), np.arange(1, N + 1)] = 1.0
        return diff.T @ (self.springs[:, None] * diff)

    def clamped_frequencies(self) -> np.ndarray:
        """Small-amplitude natural frequencies (rad/s, ascending) with the hub held
        still and no gravity: M ψ̈ + K ψ = 0 about the straight beam, (N,)."""
        M = self.S[1:, 1:] + np.diag(self.D[1:])
        return np.sqrt(eigh(self.spring_matrix()[1:, 1:], M, eigvals_only=True))

    def rhs(self, t: float, state: np.ndarray, torque: float) -> np.ndarray:
        """d/dt [α, α̇] (2N + 2,) from Lagrange's equations of the module docstring."""
        return _chain_rhs(state, torque, self.S, self.D, self.springs, self.w, self.gravity, self.joint_damping)

    def energy(self, states: np.ndarray) -> np.ndarray:
        """T + V of the module docstring for states (..., 2N + 2)."""
        n = self.n_links + 1
        alpha, rate = states[..., :n], states[..., n:]
        diff = np.diff(alpha, axis=-1)
        cos_kl = np.cos(alpha[..., :, None] - alpha[..., None, :])
        T = 0.5 * np.einsum("...k,kl,...kl,...l->...", rate, self.S, cos_kl, rate) + 0.5 * (self.D * rate**2).sum(-1)
        V = 0.5 * (self.springs * diff**2).sum(-1) + self.gravity * (self.w * np.sin(alpha)).sum(-1)
        return T + V

    def initial_state(self, theta: float, theta_dot: float) -> np.ndarray:
        """A straight beam turning rigidly with the hub, (2N + 2,)."""
        n = self.n_links + 1
        return np.concatenate([np.full(n, theta), np.full(n, theta_dot)])

    def integrate(self, state: np.ndarray, t_eval: np.ndarray, corners=(), torques=(0.0,), rtol: float = 1e-9,
                  atol: float = 1e-11, method: str = "DOP853") -> np.ndarray:
        """States (m, 2N + 2) at ``t_eval`` (m,) from ``state`` at ``t_eval[0]``, under the
        piecewise-constant hub torque ``torques[k]`` before ``corners[k]`` (the last after
        them all), restarting the solver at each corner."""
        corners, torques = np.asarray(corners, dtype=float), np.asarray(torques, dtype=float)
        t0, t_end = float(t_eval[0]), float(t_eval[-1])
        bounds = np.concatenate([[t0], corners[(corners > t0) & (corners < t_end)], [t_end]])
        out = np.empty((len(t_eval), state.size))
        for a, b in zip(bounds[:-1], bounds[1:]):
            tau = torques[np.searchsorted(corners, a, side="right")]
            sol = solve_ivp(self.rhs, (a, b), state, method=method, rtol=rtol, atol=atol,
                            dense_output=True, args=(tau,))
            if not sol.success:
                raise SimulationError(f"chain integration failed at t = {sol.t[-1]:.6g} s: {sol.message}")
            inside = (t_eval >= a) & (t_eval <= b)
            out[inside] = sol.sol(t_eval[inside]).T
            state = sol.y[:, -1]
        return out

    def simulate(self, case: BeamCase, t_eval: np.ndarray, **solver) -> ChainResult:
        """Free motion under ``case``'s torque pulse from a straight beam at
        ``case.initial`` (θ, θ̇; modal initial deflections do not apply), sampled at
        ``t_eval`` (m,), which starts at ``case.time.start_s``; ``solver`` as in
        :meth:`integrate`."""
        state = self.initial_state(case.initial.theta_rad, case.initial.theta_dot_rad_s)
        out = self.integrate(state, t_eval, *torque_schedule(case), **solver)
        n = self.n_links + 1
        theta, psi = out[:, 0], out[:, 1:n]
        return ChainResult(t=t_eval, theta=theta, theta_dot=out[:, n], psi=psi,
                           tip_deflection=self.link * np.sin(psi - theta[:, None]).sum(axis=1))
