"""ROOTM / INTEG against the verification table and the listing's printed integrals."""

import numpy as np
import pytest

from impactdyn import InputError, SimulationError
from impactdyn.beam import BeamModel, eigenvalues, modal_integrals, shapes
from impactdyn.beam._modes import MAX_MODES, _newton_root


BETA = [1.875104068712, 4.694091132974, 7.854757438238, 10.99554073488, 14.13716839105, 17.27875953209]
SIGMA = [0.734095513759, 1.018467318760, 0.999224496517, 1.000033553, 0.999998550]
# INTEG's printed values (listing EQNS, CEN and SR), 6 decimals
K_DIAG = [1.193336, 6.478225, 17.859520, 36.055388, 60.801076, 92.129142, 130.036752]
H_DIAG = [1.570878, 8.647143, 24.952113, 51.459105, 87.792327, 133.999024, 190.075040]
A_INT = [0.568826, 0.090767, 0.032416, 0.016542, 0.010007, 0.006699, 0.004796]
B_INT = [0.782992, 0.433936, 0.254425, 0.181898, 0.141471, 0.115749, 0.097942]


def test_eigenvalues_match_table_and_equation():
    beta = eigenvalues(20)
    np.testing.assert_allclose(beta[:6], BETA, atol=1e-10, rtol=0)
    # every root satisfies cos β cosh β + 1 = 0 in its scaled form, and lies near (2i−1)π/2
    assert np.max(np.abs(np.cos(beta) + 1 / np.cosh(beta))) < 1e-14
    np.testing.assert_allclose(beta[6:], (2 * np.arange(7, 21) - 1) * np.pi / 2, atol=1e-6)


def test_newton_failure_is_a_simulation_error():
    with pytest.raises(SimulationError, match="near 1.875: Newton's method did not converge in 2 iterations"):
        _newton_root(1.875, maxiter=2)


@pytest.mark.parametrize(("call", "names"), [(lambda: eigenvalues(MAX_MODES + 1), f"n = {MAX_MODES + 1}"),
                                             (lambda: shapes(eigenvalues(2), np.float64(0.5), 4), "derivative = 4")])
def test_arguments_out_of_range_are_input_errors(call, names):
    with pytest.raises(InputError, match=names):
        call()


def test_sigma_and_analytic_integrals():
    mi = modal_integrals(7)
    np.testing.assert_allclose(mi.sigma[:5], SIGMA, atol=1e-9)
    np.testing.assert_allclose(mi.a, A_INT, atol=1e-6)
    np.testing.assert_allclose(mi.b, B_INT, atol=1e-6)


def test_centrifugal_integrals_match_listing():
    mi = modal_integrals(7)
    np.testing.assert_allclose(np.diag(mi.k), K_DIAG, atol=1e-6)
    np.testing.assert_allclose(np.diag(mi.h), H_DIAG, atol=1e-6)


@pytest.mark.parametrize("n", [1, 10, 20, 50])
def test_shapes_normalised_and_stable(n):
    """∫φ² = 1, φ(0) = φ'(0) = 0, φ(1) = ±2, φ''(1) = φ'''(1) = 0 even for β ≈ 155."""
    mi = modal_integrals(n)
    x, w = np.polynomial.legendre.leggauss(200)
    xi = np.concatenate([(x + 2 * k + 1) / (2 * 60) for k in range(60)])
    wt = np.tile(w, 60) / 120
    phi = shapes(mi.beta, xi)
    np.testing.assert_allclose(phi**2 @ wt, 1.0, atol=1e-11)
    np.testing.assert_allclose(phi @ wt, mi.b, atol=1e-11)
    end = np.array([0.0, 1.0])
    np.testing.assert_allclose(shapes(mi.beta, end)[:, 0], 0.0, atol=1e-12)
    np.testing.assert_allclose(shapes(mi.beta, end, 1)[:, 0], 0.0, atol=1e-10)
    np.testing.assert_allclose(np.abs(shapes(mi.beta, end)[:, 1]), 2.0, atol=1e-11)
    np.testing.assert_allclose(shapes(mi.beta, end, 2)[:, 1] / mi.beta**2, 0.0, atol=1e-10)
    np.testing.assert_allclose(shapes(mi.beta, end, 3)[:, 1] / mi.beta**3, 0.0, atol=1e-10)


def test_quadrature_converged():
    """k and h agree with an independent, much finer quadrature of the same integrands."""
    mi = modal_integrals(12)
    x, w = np.polynomial.legendre.leggauss(64)
    xi = np.concatenate([(x + 2 * k + 1) / (2 * 200) for k in range(200)])
    wt = np.tile(w, 200) / 400
    d1 = shapes(mi.beta, xi, 1)
    np.testing.assert_allclose((d1 * wt * 0.5 * (1 - xi**2)) @ d1.T, mi.k, atol=1e-9, rtol=1e-12)
    np.testing.assert_allclose((d1 * wt * (1 - xi)) @ d1.T, mi.h, atol=1e-9, rtol=1e-12)


ROTATING = {10: (5.0489, 32.120, 73.976), 12: (5.4269, 35.638, 78.705), 2: (3.6218, 22.526, 62.241)}


@pytest.mark.parametrize("omega_bar", sorted(ROTATING))
def test_rotating_cantilever_frequencies(omega_bar, make_case):
    """In-plane frequencies of the model's linearised equations at constant hub speed."""
    case = make_case("impactb_sample.toml", model={"n_modes": 14}, beam={"hub_radius_m": 0.0})
    m = BeamModel.from_case(case)
    rho, L, EI = case.beam.mass_per_length_kg_m, case.beam.length_m, case.beam.EI_N_m2
    scale = np.sqrt(rho * L**4 / EI)
    w_bar = m.rotating_frequencies(omega_bar / scale)[:3] * scale
    np.testing.assert_allclose(w_bar, ROTATING[omega_bar], rtol=1e-3)


def test_diagonal_centrifugal_is_the_legacy_value(make_case):
    case = make_case("impactb_sample.toml", model={"n_modes": 14}, legacy={"diagonal_centrifugal": True})
    m = BeamModel.from_case(case)
    scale = np.sqrt(case.beam.mass_per_length_kg_m * case.beam.length_m**4 / case.beam.EI_N_m2)
    assert abs(m.rotating_frequencies(10 / scale)[0] * scale - 5.6299) < 1e-3
