"""The coupled model's foreshortening and curvature integrals (``_modes``) and the
mass matrix and quartic energy built from them (``_model``), against independent
quadratures of their definitions."""

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid, quad

from impactdyn.beam import BeamModel, modal_integrals, shapes
from impactdyn.beam._modes import _ORDER, _gauss_legendre, _panels, _running_integral, large_deflection_integrals


def test_running_integral_is_exact_for_polynomials():
    """∫₀^ξ of ξᵏ, k < 24 (the panel rule's order), to rounding, panel by panel."""
    xi, _ = _gauss_legendre(8, _ORDER)
    powers = np.arange(_ORDER)
    f = xi[None, :] ** powers[:, None]
    exact = xi[None, :] ** (powers[:, None] + 1) / (powers[:, None] + 1)
    np.testing.assert_allclose(_running_integral(f, 8, _ORDER), exact, rtol=0, atol=1e-15)


@pytest.mark.parametrize("n", [4, 20])
def test_running_products_and_c_agree_with_the_one_dimensional_integrals(n):
    """With S = ∫₀^ξ φⱼ'φₖ' from the running integral: ∫S = h and ∫ξS = k (INTEG's
    integrals, an independent quadrature), and ∫φᵢS = c, which ``_modes`` computes by
    parts as −βᵢ⁻⁴∫φᵢ'''φⱼ'φₖ' — for β up to 61 (n = 20)."""
    mi, fi = modal_integrals(n), large_deflection_integrals(n)
    n_panels = _panels(mi.beta)
    xi, w = _gauss_legendre(n_panels, _ORDER)
    d1 = shapes(mi.beta, xi, 1)
    S = _running_integral(d1[:, None, :] * d1[None, :, :], n_panels, _ORDER)
    np.testing.assert_allclose(S @ w, mi.h, rtol=0, atol=1e-12 * np.abs(mi.h).max())
    np.testing.assert_allclose(S @ (w * xi), mi.k, rtol=0, atol=1e-12 * np.abs(mi.k).max())
    c_direct = np.einsum("ix,jkx->ijk", shapes(mi.beta, xi) * w, S)
    np.testing.assert_allclose(fi.c, c_direct, rtol=0, atol=1e-12 * np.abs(c_direct).max())


def test_symmetries():
    fi = large_deflection_integrals(5)
    np.testing.assert_array_equal(fi.c, fi.c.transpose(0, 2, 1))
    for t in (fi.e, fi.f, fi.d):
        np.testing.assert_allclose(t, t.transpose(1, 0, 2, 3), rtol=1e-14, atol=0)
        np.testing.assert_allclose(t, t.transpose(0, 1, 3, 2), rtol=1e-14, atol=0)
        np.testing.assert_allclose(t, t.transpose(2, 3, 0, 1), rtol=1e-14, atol=0)
    np.testing.assert_allclose(fi.d, fi.d.transpose(0, 2, 1, 3), rtol=1e-13, atol=1e-13 * np.abs(fi.d).max())


@pytest.mark.parametrize("i,j,k,l", [(0, 0, 0, 0), (0, 1, 2, 1), (3, 2, 0, 3)])
def test_entries_against_adaptive_quadrature(i, j, k, l):
    """c, e, f, d against SciPy's adaptive quad of their definitions (S inside by a
    one-panel Gauss rule)."""
    beta = modal_integrals(4).beta
    fi = large_deflection_integrals(4)

    def d(m, order, x):
        return float(shapes(beta[m : m + 1], np.float64(x), order)[0])

    t80, w80 = np.polynomial.legendre.leggauss(80)

    def S(a, b, x):  # one 80-point Gauss–Legendre rule on [0, x]: exact to rounding for β ≤ 11
        t = 0.5 * x * (t80 + 1.0)
        return 0.5 * x * w80 @ (shapes(beta[a : a + 1], t, 1)[0] * shapes(beta[b : b + 1], t, 1)[0])

    opts = dict(epsabs=1e-13, epsrel=1e-11, limit=400)
    c = quad(lambda x: d(i, 0, x) * S(j, k, x), 0.0, 1.0, **opts)[0]
    e = quad(lambda x: S(i, j, x) * S(k, l, x), 0.0, 1.0, **opts)[0]
    f = quad(lambda x: 0.5 * (d(i, 2, x) * d(j, 2, x) * d(k, 1, x) * d(l, 1, x)
                              + d(k, 2, x) * d(l, 2, x) * d(i, 1, x) * d(j, 1, x)), 0.0, 1.0, **opts)[0]
    assert fi.c[i, j, k] == pytest.approx(c, rel=1e-10, abs=1e-12)
    assert fi.e[i, j, k, l] == pytest.approx(e, rel=1e-10, abs=1e-12)
    assert fi.f[i, j, k, l] == pytest.approx(f, rel=1e-10, abs=1e-12)
    d_ = quad(lambda x: (1.0 - x) * d(i, 1, x) * d(j, 1, x) * d(k, 1, x) * d(l, 1, x), 0.0, 1.0, **opts)[0]
    assert fi.d[i, j, k, l] == pytest.approx(d_, rel=1e-10, abs=1e-12)


@pytest.fixture(scope="module")
def deflected(make_case):
    """A coupled model with a hub radius (no gravity), and a state with a 15 % tip deflection."""
    case = make_case("impactc_sample.toml", beam={"hub_radius_m": 0.05},
                     model={"n_modes": 4, "coupled": True, "gravity_m_s2": 0.0})
    m = BeamModel.from_case(case)
    y = np.zeros(m.n_state)
    y[1 : m.n + 1] = [0.025, -0.010, 0.004, -0.002]
    y[m.n + 1] = 7.0
    y[m.n + 2 : 2 * m.n + 2] = [1.5, -2.0, 0.7, 0.4]
    return case, m, y


def test_mass_matrix_is_the_gram_matrix_of_the_velocity_fields(deflected):
    """M(q) of the kernel against the definition on a fine grid (trapezoid, 200,001 points):
    M₀₀ = J_h + ∫ρ(w² + R²), M₀ᵢ = ∫ρ(w sᵢ + φᵢR), Mᵢⱼ = ∫ρ(φᵢφⱼ + sᵢsⱼ), R = A + x + u,
    u = −½∫w'², sᵢ = ∫w'φᵢ'/L — no modal integrals. Positive definite."""
    case, m, y = deflected
    bm = case.beam
    rho, L, A = bm.mass_per_length_kg_m, bm.length_m, bm.hub_radius_m
    beta = modal_integrals(m.n).beta
    xi = np.linspace(0.0, 1.0, 200_001)
    q = y[1 : m.n + 1]
    phi, slope = shapes(beta, xi), shapes(beta, xi, 1) / L
    w, wp = q @ phi, q @ slope
    u = -0.5 * cumulative_trapezoid(wp**2, xi * L, initial=0.0)
    s = cumulative_trapezoid(wp * slope, xi * L, initial=0.0)
    R = A + xi * L + u

    def integral(f):
        return np.trapezoid(rho * f, xi * L, axis=-1)

    M = np.empty((m.n + 1, m.n + 1))
    M[0, 0] = bm.inertia_ratio * rho * L * (A * A + A * L + L * L / 3.0) + integral(w**2 + R**2)
    M[0, 1:] = M[1:, 0] = integral(w * s + phi * R)
    M[1:, 1:] = integral(phi[:, None] * phi[None, :] + s[:, None] * s[None, :])
    np.testing.assert_allclose(m.mass_matrix(y), M, rtol=1e-8, atol=1e-10 * np.abs(M).max())
    np.linalg.cholesky(m.mass_matrix(y))
    assert not np.allclose(m.mass_matrix(y), m.mass_matrix(np.zeros_like(y)), rtol=1e-3)


def test_energy_holds_the_quartic_bending_term(deflected):
    """E − ½ẋᵀMẋ − ½ΣKq² of the model (no gravity) = ½EI∫w''²w'² on a fine grid, here 8.7 %
    of the quadratic bending energy."""
    case, m, y = deflected
    bm = case.beam
    L = bm.length_m
    q = y[1 : m.n + 1]
    xi = np.linspace(0.0, 1.0, 200_001)
    beta = modal_integrals(m.n).beta
    wp, wpp = q @ shapes(beta, xi, 1) / L, q @ shapes(beta, xi, 2) / L**2
    quartic = 0.5 * bm.EI_N_m2 * np.trapezoid(wpp**2 * wp**2, xi * L)
    v = y[m.n + 1 : 2 * m.n + 2]
    rest = m.energy(y) - 0.5 * v @ m.mass_matrix(y) @ v - 0.5 * np.sum(m.kd * q**2)
    assert rest == pytest.approx(quartic, rel=1e-8)
    assert quartic > 0.05 * 0.5 * np.sum(m.kd * q**2)


def test_energy_holds_the_gravity_potential_to_fourth_order(make_case):
    """With gravity, E − ½ẋᵀMẋ − ½ΣKq² − ½EI∫w''²w'² = ρg∫[(A + x + u) sin θ + w cos θ] dx
    with u = −½∫w'² − ⅛∫w'⁴ on a fine grid; the w'⁴ term is here 3.6 % of the w'² one."""
    case = make_case("impactc_sample.toml", beam={"hub_radius_m": 0.05}, model={"n_modes": 4, "coupled": True})
    m = BeamModel.from_case(case)
    bm = case.beam
    rho, L, A, g = bm.mass_per_length_kg_m, bm.length_m, bm.hub_radius_m, case.model.gravity_m_s2
    y = np.zeros(m.n_state)
    y[0] = 0.9
    y[1 : m.n + 1] = q = np.array([0.025, -0.010, 0.004, -0.002])
    xi = np.linspace(0.0, 1.0, 200_001)
    beta = modal_integrals(m.n).beta
    w, wp, wpp = q @ shapes(beta, xi), q @ shapes(beta, xi, 1) / L, q @ shapes(beta, xi, 2) / L**2
    u2 = -0.5 * cumulative_trapezoid(wp**2, xi * L, initial=0.0)
    u4 = -0.125 * cumulative_trapezoid(wp**4, xi * L, initial=0.0)
    gravity = rho * g * np.trapezoid((A + xi * L + u2 + u4) * np.sin(y[0]) + w * np.cos(y[0]), xi * L)
    bending = 0.5 * np.sum(m.kd * q**2) + 0.5 * bm.EI_N_m2 * np.trapezoid(wpp**2 * wp**2, xi * L)
    assert m.energy(y) - bending == pytest.approx(gravity, rel=1e-9)
    quartic = rho * g * np.sin(y[0]) * np.trapezoid(u4, xi * L)
    assert abs(quartic) > 0.03 * abs(rho * g * np.sin(y[0]) * np.trapezoid(u2, xi * L))
