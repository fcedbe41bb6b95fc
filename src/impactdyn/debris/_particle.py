"""State equations of one DC3D deformable tetrahedral particle (Fahrenthold 1994; docs/theory/debris.md, eqs. (2), (3)).

A particle is a tetrahedron of mass m in homogeneous deformation (paper eq. 1)::

    x(t) = F(t) (r − r_c) + c(t),       v = Ḟ (r − r_c) + ċ,

with kinetic co-energy ½ m |ċ|² + ½ tr(Ḟ J Ḟᵀ) (eq. 3c) about the inertia tensor
J = ∫ρ₀ (r − r_c)⊗(r − r_c) dV₀ (eq. 3d), momenta p = m ċ, H = Ḟ J (eq. 4). The
material is the isothermal, variable-compressibility, Green–Naghdi
elastic–viscoplastic specialisation of eqs. 7–13 coded in the listing's FCN:

    C = FᵀF,   E = ½(C − I),   E' = E − ⅓ tr(E) I,   J_F = det F,
    V₀ = m / ((1 − φ) ρ_ref),   K_b = λ + ⅔μ,
    U(F, Eₚ) = V₀ [ μ |E' − Eₚ|² + K_b (J_F − 1)² / (2 J_F²) ],
    S = ∂U/∂E = V₀ [ 2μ (E' − Eₚ) − K_b (1/J_F − 1)(1/J_F) C⁻¹ ],
    T(p, H) = ½ |p|²/m + ½ tr(H J⁻¹ Hᵀ)                        (eq. 5b)

and the state equations (eq. 13 as specialised in FCN)::

    Ḟ = H J⁻¹                                                   (eq. 13c, 6d)
    Ḣ = −F S − ζ V₀ J_F ⅓ tr(D) F⁻ᵀ,   D = sym(Ḟ F⁻¹)           (eq. 13b, 2)
    Ėₚ = (2μ/η) (E' − Eₚ)                                       (eq. 10a, 13d)
    ṗ = 0,   ċ = p/m                                             (eq. 13a)

−F S = −∂U/∂F, so with η → ∞ and ζ = 0 the system is Hamiltonian in (F, H) and
the total energy T + U is conserved; the relaxation dissipates
2μ/η · 2μV₀ |E' − Eₚ|² ≥ 0 and the bulk viscosity ζ V₀ J_F (tr D)²/3 ≥ 0.
The internal angular momentum skew(H Fᵀ) is conserved for every η and ζ.

State packing (33 numbers per particle, the listing's y(1..33) in 0-based
order; 3×3 blocks row-major, so ``y[3*i + j]`` is H[i, j])::

    y[ 0: 9]  H   (g cm²/µs)      y[27:30]  p   (g cm/µs)
    y[ 9:18]  F   (1)             y[30:33]  c   (cm)
    y[18:27]  Eₚ  (1)

Kernels see a state as its rows Y = y.reshape(11, 3) and name the blocks with
:func:`state_views` (H, F, Eₚ, p, c); 3×3 scratch is named by
:func:`scratch_views`. A loop makes such views once, outside the loop: a view
made per step, or passed to a compiled call per step, costs reference-count
traffic that was more than half of a step's time.

Units cm, g, µs: moduli in Mbar, η and ζ in Mbar·µs, energy g·cm²/µs².

Listing deviations (the default is the model; each is behind an explicit option):

* ``ParticleMaterial.legacy_eta_per_volume`` — FCN's epd = −(1/η)·rkp gives
  Ėₚ = V₀·(2μ/η)(E' − Eₚ): its η is per unit volume.
* ``legacy_fdot_scaling`` of :func:`impactdyn.debris._tets.initial_state` —
  IVCALC multiplies the fitted velocity gradient by (ρ_ref/ρ)/3 before forming
  H(0) = Ḟ(0) J.
* ``legacy_inertia_transform`` of :func:`impactdyn.debris._tets.inertia_tensor` —
  JCALC maps the reference inertia with g⁻ᵀ J_ref g⁻¹ where the model needs
  g J_ref gᵀ.
* Left out, not an option: FCN multiplies the bulk-viscosity term by a power of
  ½|D|² that the OCR text garbles (docs/theory/debris.md, the listing's errata); the term here is the linear one.
"""

from __future__ import annotations

import math
from functools import partial
from typing import Annotated

import numpy as np
from numba import njit
from pydantic import Field

from impactdyn._config import NonNegative, Positive, Section, rule
from impactdyn.debris import _mat3 as m3

STATE_SIZE = 33
H_SLICE = slice(0, 9)
F_SLICE = slice(9, 18)
EP_SLICE = slice(18, 27)
P_SLICE = slice(27, 30)
C_SLICE = slice(30, 33)
STATE_ROWS = 11
H_ROWS, F_ROWS, EP_ROWS, P_ROW, C_ROW = slice(0, 3), slice(3, 6), slice(6, 9), 9, 10

# Packed material parameters (``ParticleMaterial.packed()``), read by every kernel.
P_MU, P_KB, P_RELAX, P_RELAX_PER_VOLUME, P_ZETA = range(5)
N_PARAMS = 5

# Scratch 3×3 matrices per particle, see scratch_views.
N_WORK = 7

# error_model="numpy": a degenerate trial state must give inf/NaN (which the
# integrators detect and report), not raise ZeroDivisionError inside prange.
kernel = partial(njit, cache=True, error_model="numpy")
# Small kernels called in the step loops are inlined by numba, so that the views
# passed to them cost no reference counting (about 2.5× per step).
inline_kernel = partial(njit, cache=True, error_model="numpy", inline="always")


def check_bulk_modulus(lam: float | None, mu: float | None, names: tuple[str, str] = ("lam", "mu")) -> None:
    """λ + ⅔μ > 0 where both are given (a validator's ValueError naming ``names`` otherwise).

    :class:`ParticleMaterial`'s rule, called by the debris and Whipple cases' material tables too.
    """
    if lam is not None and mu is not None and lam + 2.0 * mu / 3.0 <= 0:
        raise ValueError(f"{names[0]} + 2/3 {names[1]} must be > 0 (bulk modulus)")


LIGHT_SPEED = 29.9792458
"""The speed of light, cm/µs (exact)."""


def check_wave_speed(lam: float | None, mu: float | None, rho_ref: float | None,
                     names: tuple[str, str, str] = ("lam", "mu", "rho_ref")) -> None:
    """The longitudinal wave speed √((λ + 2μ)/ρ_ref) is below the speed of light, where all are given (a
    validator's ValueError naming ``names`` otherwise).

    No material's moduli come near it; beyond it the stiffness that sets the integrators' step
    overflows.  :class:`ParticleMaterial`'s rule, called by the debris and Whipple cases' material
    tables too.  (Mbar over g/cm³ is (cm/µs)², so the speed is in cm/µs.)
    """
    if lam is None or mu is None or rho_ref is None:
        return
    speed = math.sqrt((lam + 2.0 * mu) / rho_ref) if lam + 2.0 * mu > 0 else 0.0
    if not speed < LIGHT_SPEED:
        raise ValueError(f"({names[0]} + 2 {names[1]}) / {names[2]} gives a longitudinal wave speed of "
                         f"{speed:.4g} cm/µs, faster than light ({LIGHT_SPEED} cm/µs)")


class ParticleMaterial(Section):
    """Elastic–viscoplastic debris material of DC3D (listing common /props/).

    mu, lam: Lamé constants μ, λ (Mbar), with a positive bulk modulus λ + ⅔μ
    (:func:`check_bulk_modulus`) and waves slower than light (:func:`check_wave_speed`);
    rho_ref: reference density ρ_ref (g/cm³); eta: plastic viscosity η (Mbar·µs; ``inf``
    switches plasticity off); zeta: artificial bulk viscosity ζ ≥ 0 (Mbar·µs);
    legacy_eta_per_volume: use the listing's Ėₚ = V₀(2μ/η)(E' − Eₚ).  The one home of
    these defaults and bounds: a bad value raises :class:`~impactdyn._errors.InputError`
    naming the field; the case tables declare them with :func:`~impactdyn._config.field_of`.
    """

    mu: Positive
    lam: float
    rho_ref: Positive
    eta: Annotated[float, Field(gt=0, allow_inf_nan=True)] = math.inf
    zeta: NonNegative = 0.0
    legacy_eta_per_volume: bool = False

    _bulk = rule(check_bulk_modulus, "lam", "mu")
    _causal = rule(check_wave_speed, "lam", "mu", "rho_ref")

    @property
    def bulk_modulus(self) -> float:
        """K_b = λ + ⅔μ (Mbar)."""
        return self.lam + 2.0 * self.mu / 3.0

    @property
    def relaxation_rate(self) -> float:
        """2μ/η (1/µs; per unit reference volume with ``legacy_eta_per_volume``)."""
        return 2.0 * self.mu / self.eta

    def packed(self) -> np.ndarray:
        """Parameters for the kernels, shape ``(N_PARAMS,)``, indexed by ``P_*``."""
        out = np.empty(N_PARAMS)
        out[P_MU] = self.mu
        out[P_KB] = self.bulk_modulus
        out[P_RELAX] = self.relaxation_rate
        out[P_RELAX_PER_VOLUME] = 1.0 if self.legacy_eta_per_volume else 0.0
        out[P_ZETA] = self.zeta
        return out

    def reference_volume(self, m: np.ndarray, phi: np.ndarray | float = 0.0) -> np.ndarray:
        """V₀ = m / ((1 − φ) ρ_ref) (cm³), the volume whose stiffness the particle has."""
        return np.asarray(m, dtype=float) / ((1.0 - np.asarray(phi, dtype=float)) * self.rho_ref)

    def stiffness_bound(self) -> float:
        """Largest eigenvalue of ∂²U/∂F² at F = I per unit V₀: max(2μ, 3K_b) (Mbar)."""
        return max(2.0 * self.mu, 3.0 * self.bulk_modulus)


def pack_state(H, F, Ep, p, c) -> np.ndarray:
    """Packed states ``(..., 33)`` from H, F, Eₚ ``(..., 3, 3)`` and p, c ``(..., 3)``."""
    H = np.asarray(H, dtype=float)
    lead = H.shape[:-2]
    y = np.empty(lead + (STATE_SIZE,))
    y[..., H_SLICE] = H.reshape(lead + (9,))
    y[..., F_SLICE] = np.asarray(F, dtype=float).reshape(lead + (9,))
    y[..., EP_SLICE] = np.asarray(Ep, dtype=float).reshape(lead + (9,))
    y[..., P_SLICE] = p
    y[..., C_SLICE] = c
    return y


def unpack_state(y: np.ndarray):
    """Views (H, F, Eₚ, p, c) of packed states ``(..., 33)``; shapes ``(..., 3, 3)``, ``(..., 3)``."""
    y = np.asarray(y)
    lead = y.shape[:-1]
    return (y[..., H_SLICE].reshape(lead + (3, 3)), y[..., F_SLICE].reshape(lead + (3, 3)),
            y[..., EP_SLICE].reshape(lead + (3, 3)), y[..., P_SLICE], y[..., C_SLICE])


# --- 3×3 algebra on arrays (outputs never alias inputs), by the 9-tuple formulas of _mat3 ---


@inline_kernel
def _put(A, out):
    for i in range(3):
        for j in range(3):
            out[i, j] = A[3 * i + j]


@inline_kernel
def det3(A):
    """det A of a 3×3 matrix."""
    return m3.det(m3.mat(A))


@inline_kernel
def inv3(A, out):
    """out = A⁻¹ by cofactors; returns det A (inf/NaN entries when A is singular)."""
    a = m3.mat(A)
    _put(m3.inv(a), out)
    return m3.det(a)


@inline_kernel
def matmul3(A, B, out):
    """out = A B."""
    _put(m3.mm(m3.mat(A), m3.mat(B)), out)


@inline_kernel
def matmul3_tn(A, B, out):
    """out = Aᵀ B."""
    _put(m3.mtm(m3.mat(A), m3.mat(B)), out)


@inline_kernel
def trace_of_product(A, B):
    """tr(A B) = Σᵢⱼ Aᵢⱼ Bⱼᵢ."""
    return m3.trace_of_product(m3.mat(A), m3.mat(B))


# --- views ------------------------------------------------------------------------------


@inline_kernel
def state_views(Y):
    """(H, F, Eₚ, p, c) of a state's rows ``Y (11, 3)``: three ``(3, 3)`` and two ``(3,)`` views."""
    return Y[H_ROWS], Y[F_ROWS], Y[EP_ROWS], Y[P_ROW], Y[C_ROW]


@inline_kernel
def scratch_views(w):
    """Named scratch (C, C⁻¹, E', S, F⁻¹, B, T) from ``w (N_WORK, 3, 3)``.

    The constitutive kernels fill C = FᵀF, C⁻¹, E', S and F⁻¹; B and T are
    the integrators'.
    """
    return w[0], w[1], w[2], w[3], w[4], w[5], w[6]


# --- constitutive kernels ----------------------------------------------------------


@inline_kernel
def strain_measures(F, sc):
    """Fill C = FᵀF, C⁻¹ and E' = ½(C − ⅓ tr C I) of the scratch ``sc``; return J_F = det F.

    (E' = E − ⅓ tr(E) I with E = ½(C − I): the identity has no deviator.)
    """
    C, Cinv, Edev = sc[0], sc[1], sc[2]
    matmul3_tn(F, F, C)
    inv3(C, Cinv)
    third_trace = (C[0, 0] + C[1, 1] + C[2, 2]) / 3.0
    for i in range(3):
        for j in range(3):
            Edev[i, j] = 0.5 * C[i, j]
        Edev[i, i] -= 0.5 * third_trace
    return det3(F)


@inline_kernel
def stress_from_strain(detF, Ep, V0, params, sc):
    """Fill S = V₀ [2μ (E' − Eₚ) − K_b (1/J_F − 1)(1/J_F) C⁻¹] (FCN's rk; energy units).

    Reads E', C⁻¹ from ``sc`` (see strain_measures).
    """
    Cinv, Edev, S = sc[1], sc[2], sc[3]
    two_mu = 2.0 * params[P_MU]
    pressure_term = params[P_KB] * (1.0 / detF - 1.0) / detF
    for i in range(3):
        for j in range(3):
            S[i, j] = V0 * (two_mu * (Edev[i, j] - Ep[i, j]) - pressure_term * Cinv[i, j])


@inline_kernel
def stress_into(F, Ep, V0, params, sc):
    """Fill C, C⁻¹, E' and S(F, Eₚ) of the scratch ``sc``; return J_F."""
    detF = strain_measures(F, sc)
    stress_from_strain(detF, Ep, V0, params, sc)
    return detF


@kernel
def stored_energy_of(F, Ep, V0, params, sc):
    """U = V₀ [μ |E' − Eₚ|² + K_b (J_F − 1)² / (2 J_F²)] (g cm²/µs²)."""
    detF = strain_measures(F, sc)
    Edev = sc[2]
    dev2 = 0.0
    for i in range(3):
        for j in range(3):
            dev2 += (Edev[i, j] - Ep[i, j]) ** 2
    return V0 * (params[P_MU] * dev2 + params[P_KB] * (detF - 1.0) ** 2 / (2.0 * detF * detF))


@kernel
def kinetic_energy_of(H, Jinv, p, m):
    """T = ½ tr(Ḟ J Ḟᵀ) + ½|p|²/m = ½ tr(H J⁻¹ Hᵀ) + ½|p|²/m (eq. 5b)."""
    t = 0.0
    for i in range(3):
        for a in range(3):
            for b in range(3):
                t += H[i, a] * Jinv[a, b] * H[i, b]
    return 0.5 * t + 0.5 * (p[0] ** 2 + p[1] ** 2 + p[2] ** 2) / m


@inline_kernel
def relaxation_rate(V0, params):
    """Rate of Ėₚ = r (E' − Eₚ): r = 2μ/η, or V₀·2μ/η with legacy_eta_per_volume."""
    if params[P_RELAX_PER_VOLUME] != 0.0:
        return V0 * params[P_RELAX]
    return params[P_RELAX]


@kernel
def rates_into(Y, Jinv, m, V0, params, Ydot, w):
    """Ẏ of the state equations (module docstring).

    ``Y``, ``Ydot (11, 3)``: rows of the state and of its rate (overwritten);
    ``Jinv (3, 3)``: J⁻¹; ``w (N_WORK, 3, 3)``: scratch. (Called once per stage,
    so it takes arrays: passing tuples of views to a compiled call costs more
    than making the views here.)
    """
    H, F, Ep, p, _ = state_views(Y)
    Hdot, Fdot, Epdot, pdot, cdot = state_views(Ydot)
    sc = scratch_views(w)
    Edev, S, Finv = sc[2], sc[3], sc[4]

    matmul3(H, Jinv, Fdot)
    detF = stress_into(F, Ep, V0, params, sc)
    matmul3(F, S, Hdot)
    for i in range(3):
        for j in range(3):
            Hdot[i, j] = -Hdot[i, j]
    zeta = params[P_ZETA]
    if zeta > 0.0:
        inv3(F, Finv)
        # tr D = tr(Ḟ F⁻¹); the viscous force is along F⁻ᵀ.
        viscous = zeta * V0 * detF * trace_of_product(Fdot, Finv) / 3.0
        for i in range(3):
            for j in range(3):
                Hdot[i, j] -= viscous * Finv[j, i]
    r = relaxation_rate(V0, params)
    for i in range(3):
        for j in range(3):
            Epdot[i, j] = r * (Edev[i, j] - Ep[i, j])
    for k in range(3):
        pdot[k] = 0.0
        cdot[k] = p[k] / m


# --- vectorised wrappers (numpy in, numpy out) -----------------------------------


@kernel
def _stress_batch(F, Ep, V0, params, S):
    sc = scratch_views(np.empty((N_WORK, 3, 3)))
    for n in range(F.shape[0]):
        stress_into(F[n], Ep[n], V0[n], params, sc)
        S[n] = sc[3]


@kernel
def _stored_energy_batch(F, Ep, V0, params, U):
    sc = scratch_views(np.empty((N_WORK, 3, 3)))
    for n in range(F.shape[0]):
        U[n] = stored_energy_of(F[n], Ep[n], V0[n], params, sc)


@kernel
def _kinetic_energy_batch(Y, Jinv, m, T):
    for n in range(Y.shape[0]):
        T[n] = kinetic_energy_of(Y[n, H_ROWS], Jinv[n], Y[n, P_ROW], m[n])


@kernel
def _rates_batch(Y, Jinv, m, V0, params, Ydot):
    w = np.empty((N_WORK, 3, 3))
    for n in range(Y.shape[0]):
        rates_into(Y[n], Jinv[n], m[n], V0[n], params, Ydot[n], w)


def _batch(a, tail: tuple[int, ...]) -> np.ndarray:
    return np.ascontiguousarray(np.asarray(a, dtype=float).reshape((-1,) + tail))


def _per_particle(a, n: int) -> np.ndarray:
    return np.ascontiguousarray(np.broadcast_to(np.asarray(a, dtype=float).reshape(-1), (n,)))


def stress(F, Ep, V0, material: ParticleMaterial) -> np.ndarray:
    """Second Piola–Kirchhoff-type stress S = ∂U/∂E (energy units, g cm²/µs²).

    F, Eₚ ``(..., 3, 3)``; V₀ ``(...)`` (cm³); returns S ``(..., 3, 3)``.
    """
    F3 = _batch(F, (3, 3))
    S = np.empty_like(F3)
    _stress_batch(F3, _batch(Ep, (3, 3)), _per_particle(V0, len(F3)), material.packed(), S)
    return S.reshape(np.shape(F))


def stored_energy(F, Ep, V0, material: ParticleMaterial) -> np.ndarray:
    """U(F, Eₚ) = V₀ [μ |E' − Eₚ|² + K_b (J_F − 1)²/(2J_F²)] (g cm²/µs²).

    Shapes as :func:`stress`; returns ``(...)``.
    """
    F3 = _batch(F, (3, 3))
    U = np.empty(len(F3))
    _stored_energy_batch(F3, _batch(Ep, (3, 3)), _per_particle(V0, len(F3)), material.packed(), U)
    return U.reshape(np.shape(F)[:-2])


def kinetic_energy(states, J, m) -> np.ndarray:
    """T = ½ tr(Ḟ J Ḟᵀ) + ½ |p|²/m with Ḟ = H J⁻¹ (eq. 5b).

    states ``(..., 33)``, J ``(..., 3, 3)``, m ``(...)``; returns ``(...)``.
    """
    Y = _batch(states, (STATE_ROWS, 3))
    T = np.empty(len(Y))
    _kinetic_energy_batch(Y, np.linalg.inv(_batch(J, (3, 3))), _per_particle(m, len(Y)), T)
    return T.reshape(np.shape(states)[:-1])


def total_energy(states, J, m, V0, material: ParticleMaterial) -> np.ndarray:
    """T + U, conserved when η = ∞ and ζ = 0; shapes as :func:`kinetic_energy`."""
    H, F, Ep, _, _ = unpack_state(states)
    return kinetic_energy(states, J, m) + stored_energy(F, Ep, V0, material)


def state_rates(states, J, m, V0, material: ParticleMaterial) -> np.ndarray:
    """ẏ = f(y) of the state equations (module docstring).

    states ``(..., 33)``; J ``(..., 3, 3)``; m, V₀ ``(...)``; returns ``(..., 33)``.
    """
    Y = _batch(states, (STATE_ROWS, 3))
    Ydot = np.empty_like(Y)
    _rates_batch(Y, np.linalg.inv(_batch(J, (3, 3))), _per_particle(m, len(Y)),
                 _per_particle(V0, len(Y)), material.packed(), Ydot)
    return Ydot.reshape(np.shape(states))
