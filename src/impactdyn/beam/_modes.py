"""Clamped–free cantilever modes and modal integrals (the 1988 ROOTM and INTEG).

Eigenvalues βᵢ are the roots of ``cos β cosh β + 1 = 0`` (the 1988 report, ROOTM),
found by Newton's method on the scaled, well-conditioned form
``f(β) = cos β + 1/cosh β`` started from the listing's seeds and
``(2i − 1)π/2`` beyond the fifth.

Mode shapes, ξ = x/L ∈ [0, 1] (docs/theory/beam.md, eq. (2))::

    φᵢ(ξ) = cosh βξ − cos βξ − σᵢ (sinh βξ − sin βξ),
    σᵢ = (cosh β + cos β)/(sinh β + sin β),      ∫₀¹ φᵢ² dξ = 1,  φᵢ(1) = ±2.

The textbook form cancels catastrophically for large β (cosh βξ − σ sinh βξ is
a difference of two numbers ~e^{βξ}). Writing 1 − σ exactly,

    cosh βξ − σ sinh βξ = E₊ + E₋,   sinh βξ − σ cosh βξ = E₊ − E₋,
    E₊ = ½ e^{β(ξ−1)} r,   E₋ = ½ e^{−βξ}(1 + σ),
    r = e^{β}(1 − σ) = (sin β − cos β − e^{−β}) / (½(1 − e^{−2β}) + e^{−β} sin β),

every term is O(1) and the shapes are exact to rounding for any β (the listing
factors out e^{βξ} for the same reason).

Modal integrals (INTEG; primes are d/dξ)::

    bᵢ = ∫ φᵢ dξ = 2σᵢ/βᵢ,      aᵢ = ∫ ξ φᵢ dξ = 2/βᵢ²,
    kᵢⱼ = ∫ ½(1 − ξ²) φᵢ' φⱼ' dξ,      hᵢⱼ = ∫ (1 − ξ) φᵢ' φⱼ' dξ.

k and h are computed by composite Gauss–Legendre quadrature (exact to rounding
for these smooth integrands; INTEG used Romberg), any number of modes.

Large-deflection integrals (the ``coupled`` model, ``impactdyn.beam._model``). The
inextensible beam's axial displacement is u = −½∫₀ˣ w'² − ⅛∫₀ˣ w'⁴ − …, i.e. in modes
u(ξ) = −(1/2L) Σⱼₖ Sⱼₖ(ξ) qⱼqₖ + O(q⁴) with the running product integrals::

    Sⱼₖ(ξ) = ∫₀^ξ φⱼ' φₖ' dη      (Sⱼₖ(1) = ∫φⱼ'φₖ',  ∫₀¹ Sⱼₖ = hⱼₖ,  ∫₀¹ ξ Sⱼₖ = kⱼₖ),
    cᵢⱼₖ  = ∫₀¹ φᵢ Sⱼₖ dξ = −βᵢ⁻⁴ ∫₀¹ φᵢ''' φⱼ' φₖ' dξ,
    eᵢⱼₖₗ = ∫₀¹ Sᵢⱼ Sₖₗ dξ,
    fᵢⱼₖₗ = ½ ∫₀¹ (φᵢ''φⱼ''φₖ'φₗ' + φₖ''φₗ''φᵢ'φⱼ') dξ      (the curvature's quartic term),
    dᵢⱼₖₗ = ∫₀¹ (1 − ξ) φᵢ'φⱼ'φₖ'φₗ' dξ                   (∫₀¹ of the w'⁴ term of u).

The second form of c integrates by parts with Φᵢ(ξ) = ∫_ξ¹ φᵢ = −φᵢ'''(ξ)/βᵢ⁴ (from
φᵢ'''' = βᵢ⁴φᵢ and the free end's φᵢ'''(1) = 0), a single quadrature like k and h.
e and f have the symmetries of an inner product of symmetric pairs: (i j), (k l) and
(i j) ↔ (k l); d is symmetric in all four indices. S is accumulated panel by panel
with the Gauss–Legendre integration matrix (the antiderivative of the interpolant
through a panel's nodes, exact for polynomials below the rule's order), so every
integrand is built from the stable shapes and all four are exact to rounding for any β.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from impactdyn._errors import InputError, SimulationError

MAX_MODES = 50
_LISTING_SEEDS = (1.875, 4.693, 7.855, 10.996, 14.137)


def _newton_root(beta0: float, tol: float = 1e-15, maxiter: int = 60) -> float:
    """Root of cos β + 1/cosh β near ``beta0`` (Newton, ROOTM's DRTNI)."""
    b = beta0
    for _ in range(maxiter):
        sech = 1.0 / np.cosh(b)
        f = np.cos(b) + sech
        df = -np.sin(b) - sech * np.tanh(b)
        step = f / df
        b -= step
        if abs(step) <= tol * max(1.0, abs(b)):
            return float(b)
    raise SimulationError(f"cantilever eigenvalue near {beta0}: Newton's method did not converge in "
                          f"{maxiter} iterations")


@lru_cache(maxsize=None)
def _eigenvalues_cached(n: int) -> tuple[float, ...]:
    seeds = list(_LISTING_SEEDS[:n]) + [(2 * i - 1) * np.pi / 2 for i in range(6, n + 1)]
    return tuple(_newton_root(s) for s in seeds)


def eigenvalues(n: int) -> np.ndarray:
    """The first ``n`` clamped–free eigenvalues βᵢ, shape ``(n,)``."""
    if not 0 <= n <= MAX_MODES:
        raise InputError(f"number of modes n = {n}: must be in 0..{MAX_MODES}")
    return np.array(_eigenvalues_cached(n), dtype=float)


def sigma(beta: np.ndarray) -> np.ndarray:
    """σᵢ = (cosh β + cos β)/(sinh β + sin β), evaluated without overflow."""
    beta = np.asarray(beta, dtype=float)
    e = np.exp(-beta)
    return (1.0 + e * e + 2.0 * e * np.cos(beta)) / (1.0 - e * e + 2.0 * e * np.sin(beta))


def shapes(beta: np.ndarray, xi: np.ndarray, derivative: int = 0) -> np.ndarray:
    """d^k φᵢ/dξ^k at ξ, stable for any β; shape ``(len(beta),) + xi.shape``.

    ``derivative`` k ∈ {0, 1, 2, 3}; ξ is the position over the length, 0 at the root.
    """
    beta = np.asarray(beta, dtype=float).reshape((-1,) + (1,) * np.ndim(xi))
    xi = np.asarray(xi, dtype=float)
    s = sigma(beta)
    eb = np.exp(-beta)
    r = (np.sin(beta) - np.cos(beta) - eb) / (0.5 * (1.0 - eb * eb) + eb * np.sin(beta))
    bx = beta * xi
    e_plus = 0.5 * np.exp(beta * (xi - 1.0)) * r
    e_minus = 0.5 * np.exp(-bx) * (1.0 + s)
    c, sn = np.cos(bx), np.sin(bx)
    if derivative == 0:
        return (e_plus + e_minus) - c + s * sn
    if derivative == 1:
        return beta * ((e_plus - e_minus) + sn + s * c)
    if derivative == 2:
        return beta**2 * ((e_plus + e_minus) + c - s * sn)
    if derivative == 3:
        return beta**3 * ((e_plus - e_minus) - sn - s * c)
    raise InputError(f"derivative = {derivative}: must be 0, 1, 2 or 3")


def _gauss_legendre(n_panels: int, order: int) -> tuple[np.ndarray, np.ndarray]:
    """Composite Gauss–Legendre nodes and weights on [0, 1] (equal panels, panel by panel)."""
    x, w = np.polynomial.legendre.leggauss(order)
    edges = np.linspace(0.0, 1.0, n_panels + 1)
    half = 0.5 * np.diff(edges)
    mid = 0.5 * (edges[1:] + edges[:-1])
    nodes = (mid[:, None] + half[:, None] * x[None, :]).ravel()
    weights = (half[:, None] * w[None, :]).ravel()
    return nodes, weights


_ORDER = 24  # Gauss–Legendre points per panel


def _panels(beta: np.ndarray) -> int:
    """Panels shorter than a quarter of the shortest mode half-wavelength (π/β)."""
    return max(8, int(np.ceil(4 * (beta.max() if beta.size else 1.0) / np.pi)))


def _integration_matrix(order: int) -> np.ndarray:
    """Q (order, order): ∫₋₁^{xₘ} p(t) dt = Σₗ Qₘₗ p(xₗ) at the Gauss–Legendre nodes xₘ, exact
    for polynomials p of degree < order.

    p = Σₖ cₖ Pₖ with cₖ = (2k + 1)/2 Σₗ wₗ Pₖ(xₗ) p(xₗ) (the rule is exact for Pₖ Pⱼ), and
    ∫₋₁ˣ Pₖ = (Pₖ₊₁(x) − Pₖ₋₁(x))/(2k + 1) for k ≥ 1, x + 1 for k = 0.
    """
    x, w = np.polynomial.legendre.leggauss(order)
    P = np.polynomial.legendre.legvander(x, order)  # P[m, k] = Pₖ(xₘ), k = 0…order
    antiderivative = np.empty((order, order))  # (2k + 1)/2 ∫₋₁^{xₘ} Pₖ
    antiderivative[:, 0] = 0.5 * (x + 1.0)
    antiderivative[:, 1:] = 0.5 * (P[:, 2:] - P[:, :-2])
    return antiderivative @ (P[:, :order].T * w)


def _running_integral(f: np.ndarray, n_panels: int, order: int) -> np.ndarray:
    """∫₀^ξ f at the nodes of :func:`_gauss_legendre` from f at those nodes (last axis, panel by panel)."""
    half = 0.5 / n_panels
    panels = f.reshape(f.shape[:-1] + (n_panels, order))
    within = half * panels @ _integration_matrix(order).T
    _, w = np.polynomial.legendre.leggauss(order)
    before = np.cumsum(half * panels @ w, axis=-1) - half * panels @ w  # ∫ over the earlier panels
    return (within + before[..., None]).reshape(f.shape)


@dataclass(frozen=True)
class ModalIntegrals:
    """Cantilever modal data for ``n`` modes, normalised to L = 1.

    Attributes
    ----------
    beta, sigma : (n,)  eigenvalues and shape constants.
    a : (n,)  ∫ ξ φᵢ dξ.
    b : (n,)  ∫ φᵢ dξ.
    k : (n, n)  ∫ ½(1 − ξ²) φᵢ' φⱼ' dξ  (centrifugal stiffening, root at the hub axis).
    h : (n, n)  ∫ (1 − ξ) φᵢ' φⱼ' dξ  (the additional hub-radius term).
    """

    beta: np.ndarray
    sigma: np.ndarray
    a: np.ndarray
    b: np.ndarray
    k: np.ndarray
    h: np.ndarray

    @property
    def n(self) -> int:
        return len(self.beta)

    def as_dict(self) -> dict:
        return {f: getattr(self, f).tolist() for f in ("beta", "sigma", "a", "b", "k", "h")}


@lru_cache(maxsize=16)
def modal_integrals(n: int) -> ModalIntegrals:
    """Eigenvalues and modal integrals for ``n`` modes (ROOTM + INTEG, any n ≤ 50).

    The quadrature uses 24-point Gauss–Legendre on panels shorter than a quarter of
    the shortest mode half-wavelength, so the integrands are resolved for every n.
    """
    beta = eigenvalues(n)
    s = sigma(beta)
    xi, w = _gauss_legendre(_panels(beta), _ORDER)
    d1 = shapes(beta, xi, 1)
    k = (d1 * (w * 0.5 * (1.0 - xi**2))) @ d1.T
    h = (d1 * (w * (1.0 - xi))) @ d1.T
    for m in (k, h):
        m[:] = 0.5 * (m + m.T)
    for arr in (beta, s, k, h):
        arr.setflags(write=False)
    a = 2.0 / beta**2
    b = 2.0 * s / beta
    a.setflags(write=False)
    b.setflags(write=False)
    return ModalIntegrals(beta=beta, sigma=s, a=a, b=b, k=k, h=h)


@dataclass(frozen=True)
class LargeDeflectionIntegrals:
    """The three- and four-index integrals of the large-deflection model (module
    docstring), L = 1.

    Attributes
    ----------
    c : (n, n, n)  cᵢⱼₖ = ∫ φᵢ Sⱼₖ dξ, symmetric in (j, k).
    e : (n, n, n, n)  eᵢⱼₖₗ = ∫ Sᵢⱼ Sₖₗ dξ.
    f : (n, n, n, n)  fᵢⱼₖₗ = ½∫ (φᵢ''φⱼ''φₖ'φₗ' + φₖ''φₗ''φᵢ'φⱼ') dξ.
    d : (n, n, n, n)  dᵢⱼₖₗ = ∫ (1 − ξ) φᵢ'φⱼ'φₖ'φₗ' dξ.
    """

    c: np.ndarray
    e: np.ndarray
    f: np.ndarray
    d: np.ndarray


def _pair_symmetric(t: np.ndarray) -> np.ndarray:
    """½(tᵢⱼₖₗ + tₖₗᵢⱼ), (n, n, n, n)."""
    return 0.5 * (t + t.transpose(2, 3, 0, 1))


@lru_cache(maxsize=4)
def large_deflection_integrals(n: int) -> LargeDeflectionIntegrals:
    """c, e, f and d for ``n`` modes, on the quadrature of :func:`modal_integrals`
    (n⁴ numbers each for e, f and d: 50 MB each at the largest n = 50)."""
    beta = eigenvalues(n)
    n_panels = _panels(beta)
    xi, w = _gauss_legendre(n_panels, _ORDER)
    slope, curvature, shear = (shapes(beta, xi, k) for k in (1, 2, 3))
    slope2 = slope[:, None, :] * slope[None, :, :]  # φⱼ'φₖ' (n, n, nodes)
    S = _running_integral(slope2, n_panels, _ORDER)
    c = np.einsum("ix,jkx->ijk", -shear / beta[:, None] ** 4 * w, slope2)
    # e and d are Gram tensors, symmetric under (ij) ↔ (kl) by definition; a BLAS product does not
    # promise that symmetry bitwise (on an AVX-512 OpenBLAS kernel e came out 2e-14 relative off it), so it is
    # imposed, as f's definition imposes it
    e = _pair_symmetric(np.tensordot(S * w, S, axes=(2, 2)))
    f = _pair_symmetric(np.tensordot(curvature[:, None, :] * curvature[None, :, :] * w, slope2, axes=(2, 2)))
    d = _pair_symmetric(np.tensordot(slope2 * (w * (1.0 - xi)), slope2, axes=(2, 2)))
    for arr in (c, e, f, d):
        arr.setflags(write=False)
    return LargeDeflectionIntegrals(c=c, e=e, f=f, d=d)
