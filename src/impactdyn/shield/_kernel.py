"""The M4 cubic-spline smoothing kernel in three dimensions (Monaghan 1992, eq. 2.6; Monaghan 2005 §2).

With q = r/h::

    W(r, h) = σ/h³ · w(q),   σ = 1/π,
    w(q) = 1 − 3/2 q² + 3/4 q³     0 ≤ q < 1
         = 1/4 (2 − q)³            1 ≤ q < 2
         = 0                       q ≥ 2

normalised so that ∫ W dV = 1; support radius 2h. The gradient is
∇ᵢW(rᵢⱼ, h) = σ/h⁵ · g(q) · (xᵢ − xⱼ) with g(q) = w'(q)/q, which stays finite at
q = 0 (g(0) = −3), so coincident particles need no special case.
"""

from __future__ import annotations

import math

from numba import njit

SIGMA_3D = 1.0 / math.pi
SUPPORT = 2.0


@njit(cache=True)
def w_shape(q: float) -> float:
    """Dimensionless kernel shape w(q) (without σ/h³)."""
    if q < 1.0:
        return 1.0 - 1.5 * q * q + 0.75 * q * q * q
    if q < 2.0:
        t = 2.0 - q
        return 0.25 * t * t * t
    return 0.0


@njit(cache=True)
def g_shape(q: float) -> float:
    """g(q) = w'(q)/q: ∇ᵢW = σ/h⁵ · g(q) · (xᵢ − xⱼ)."""
    if q < 1.0:
        return -3.0 + 2.25 * q
    if q < 2.0:
        t = 2.0 - q
        return -0.75 * t * t / q
    return 0.0


@njit(cache=True)
def kernel(r: float, h: float) -> float:
    """W(r, h), 1/cm³."""
    return SIGMA_3D / (h * h * h) * w_shape(r / h)


@njit(cache=True)
def gradient_factor(r: float, h: float) -> float:
    """F(r, h) with ∇ᵢW(rᵢⱼ, h) = F · (xᵢ − xⱼ), 1/cm⁵."""
    h2 = h * h
    return SIGMA_3D / (h2 * h2 * h) * g_shape(r / h)
