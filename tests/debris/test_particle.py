"""Constitutive law and state equations of a DC3D particle (docs/theory/debris.md)."""

import numpy as np
import pytest

from impactdyn.debris import _particle as P
from impactdyn.debris import _tets as T

AL = P.ParticleMaterial(mu=0.276, lam=0.56, rho_ref=2.703)


def random_state(rng, n, strain=0.05):
    """States with F near I (det F > 0), traceless Eₚ, arbitrary H, p, c."""
    F = np.eye(3) + strain * rng.standard_normal((n, 3, 3))
    Ep = strain * rng.standard_normal((n, 3, 3))
    Ep = 0.5 * (Ep + np.swapaxes(Ep, 1, 2))
    Ep -= np.trace(Ep, axis1=1, axis2=2)[:, None, None] * np.eye(3) / 3
    return P.pack_state(rng.standard_normal((n, 3, 3)), F, Ep,
                        rng.standard_normal((n, 3)), rng.standard_normal((n, 3)))


def particle(rng, n):
    x = T.tet_vertices(rng.random((n, 3)), np.array([0.03175, 0.025, 0.02]))[:, 1]
    m = AL.rho_ref * np.abs(T.signed_volume(x))
    return T.inertia_tensor(x, m), m


def design_energy(F, Ep, V0, mat):
    """U of docs/theory/debris.md, eq. (2), written out with numpy, independently of the kernels."""
    E = 0.5 * (np.swapaxes(F, -1, -2) @ F - np.eye(3))
    Edev = E - np.trace(E, axis1=-2, axis2=-1)[..., None, None] * np.eye(3) / 3
    detF = np.linalg.det(F)
    return V0 * (mat.mu * np.sum((Edev - Ep) ** 2, axis=(-2, -1))
                 + mat.bulk_modulus * (detF - 1) ** 2 / (2 * detF**2))


def test_material_validation():
    for bad in [dict(mu=0.0), dict(mu=np.nan), dict(lam=-1.0), dict(rho_ref=0.0),
                dict(eta=0.0), dict(zeta=-1.0), dict(zeta=np.inf)]:
        with pytest.raises(ValueError):
            P.ParticleMaterial(**{**dict(mu=0.276, lam=0.56, rho_ref=2.703), **bad})
    assert P.ParticleMaterial(mu=1.0, lam=1.0, rho_ref=1.0, eta=np.inf).relaxation_rate == 0.0


def test_pack_unpack_roundtrip():
    rng = np.random.default_rng(0)
    parts = [rng.standard_normal((4, 3, 3)) for _ in range(3)] + [rng.standard_normal((4, 3)) for _ in range(2)]
    y = P.pack_state(*parts)
    assert y.shape == (4, P.STATE_SIZE)
    for a, b in zip(P.unpack_state(y), parts):
        np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(y[2, 3 * 1 + 2], parts[0][2, 1, 2])   # H[i, j] = y[3i + j]


def test_energy_is_the_design_formula_and_frame_indifferent():
    rng = np.random.default_rng(1)
    _, F, Ep, _, _ = P.unpack_state(random_state(rng, 20))
    V0 = rng.random(20)
    U = P.stored_energy(F, Ep, V0, AL)
    np.testing.assert_allclose(U, design_energy(F, Ep, V0, AL), rtol=1e-12)
    Q, _ = np.linalg.qr(rng.standard_normal((3, 3)))
    Q *= np.sign(np.linalg.det(Q))
    np.testing.assert_allclose(P.stored_energy(Q @ F, Ep, V0, AL), U, rtol=1e-12)
    assert P.stored_energy(np.eye(3), np.zeros((3, 3)), 1.0, AL) == 0.0


def test_stress_is_the_energy_gradient():
    """∂U/∂F = F S (S symmetric, conjugate to E), by central differences."""
    rng = np.random.default_rng(2)
    _, F, Ep, _, _ = P.unpack_state(random_state(rng, 5, strain=0.2))
    V0 = rng.random(5) + 0.5
    S = P.stress(F, Ep, V0, AL)
    np.testing.assert_allclose(S, np.swapaxes(S, 1, 2), rtol=0, atol=1e-15)
    h = 1e-6
    grad = np.empty_like(F)
    for i in range(3):
        for j in range(3):
            dF = np.zeros((3, 3))
            dF[i, j] = h
            grad[:, i, j] = (P.stored_energy(F + dF, Ep, V0, AL) - P.stored_energy(F - dF, Ep, V0, AL)) / (2 * h)
    np.testing.assert_allclose(F @ S, grad, rtol=1e-7, atol=1e-8 * np.abs(grad).max())


def test_small_strain_limit_is_hookes_law():
    """S/V₀ → λ tr(ε) I + 2μ ε for F = I + ε, ε small and symmetric."""
    rng = np.random.default_rng(3)
    eps = rng.standard_normal((3, 3))
    eps = 0.5 * (eps + eps.T)
    for a in (1e-4, 1e-5):
        e = a * eps
        hooke = AL.lam * np.trace(e) * np.eye(3) + 2 * AL.mu * e
        S = P.stress(np.eye(3) + e, np.zeros((3, 3)), 1.0, AL)
        # the error is second order in the strain
        assert np.abs(S - hooke).max() < 10 * a**2 * (AL.lam + 2 * AL.mu) * np.abs(eps).max() ** 2


def test_rates_are_hamiltonian():
    """Ḟ = ∂T/∂H = H J⁻¹ and Ḣ = −∂U/∂F when η = ∞, ζ = 0; ṗ = 0, ċ = p/m."""
    rng = np.random.default_rng(4)
    J, m = particle(rng, 4)
    y = random_state(rng, 4)
    V0 = AL.reference_volume(m)
    ydot = P.state_rates(y, J, m, V0, AL)
    H, F, Ep, p, c = P.unpack_state(y)
    Hd, Fd, Epd, pd, cd = P.unpack_state(ydot)
    np.testing.assert_allclose(Fd, H @ np.linalg.inv(J), rtol=1e-12)
    h = 1e-7
    for i in range(3):
        for j in range(3):
            dF = np.zeros((3, 3))
            dF[i, j] = h
            dUdF = (P.stored_energy(F + dF, Ep, V0, AL) - P.stored_energy(F - dF, Ep, V0, AL)) / (2 * h)
            np.testing.assert_allclose(Hd[:, i, j], -dUdF, rtol=1e-6, atol=1e-7 * np.abs(Hd).max())
    np.testing.assert_array_equal(Epd, 0.0)
    np.testing.assert_array_equal(pd, 0.0)
    np.testing.assert_allclose(cd, p / m[:, None], rtol=1e-15)


@pytest.mark.parametrize("legacy", [False, True])
def test_relaxation_rate_and_trace(legacy):
    mat = P.ParticleMaterial(mu=0.276, lam=0.56, rho_ref=2.703, eta=0.7, legacy_eta_per_volume=legacy)
    rng = np.random.default_rng(5)
    J, m = particle(rng, 3)
    y = random_state(rng, 3)
    V0 = mat.reference_volume(m, phi=np.array([0.0, 0.2, 0.5]))
    _, F, Ep, _, _ = P.unpack_state(y)
    Epd = P.unpack_state(P.state_rates(y, J, m, V0, mat))[2]
    E = 0.5 * (np.swapaxes(F, 1, 2) @ F - np.eye(3))
    Edev = E - np.trace(E, axis1=1, axis2=2)[:, None, None] * np.eye(3) / 3
    rate = 2 * mat.mu / mat.eta * (V0 if legacy else np.ones(3))
    np.testing.assert_allclose(Epd, rate[:, None, None] * (Edev - Ep), rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(np.trace(Epd, axis1=1, axis2=2), 0.0, atol=1e-15)


def test_dissipation_rates():
    """dE/dt along the flow = −(2μ/η)·2μV₀|E' − Eₚ|² − ζ V₀ J_F (tr D)²/3."""
    mat = P.ParticleMaterial(mu=0.276, lam=0.56, rho_ref=2.703, eta=0.3, zeta=0.05)
    rng = np.random.default_rng(6)
    J, m = particle(rng, 3)
    y = random_state(rng, 3, strain=0.1)
    Fdot = rng.standard_normal((3, 3, 3))
    y[:, P.H_SLICE] = (Fdot @ J).reshape(3, 9)
    y[:, P.P_SLICE] = 0.0                  # ½|p|²/m is constant and would only add rounding
    V0 = mat.reference_volume(m)
    ydot = P.state_rates(y, J, m, V0, mat)
    h = 1e-6
    dEdt = (P.total_energy(y + h * ydot, J, m, V0, mat) - P.total_energy(y - h * ydot, J, m, V0, mat)) / (2 * h)
    H, F, Ep, _, _ = P.unpack_state(y)
    E = 0.5 * (np.swapaxes(F, 1, 2) @ F - np.eye(3))
    Edev = E - np.trace(E, axis1=1, axis2=2)[:, None, None] * np.eye(3) / 3
    Fd = H @ np.linalg.inv(J)
    trD = np.trace(Fd @ np.linalg.inv(F), axis1=1, axis2=2)
    expected = (-mat.relaxation_rate * 2 * mat.mu * V0 * np.sum((Edev - Ep) ** 2, axis=(1, 2))
                - mat.zeta * V0 * np.linalg.det(F) * trD**2 / 3)
    assert np.all(expected < 0)
    np.testing.assert_allclose(dEdt, expected, rtol=1e-5)


def test_rigid_rotation_has_no_strain_rate():
    """F = R (rotation), Ḟ = W R with W skew: Ė = sym(FᵀḞ) = 0 and the stress vanishes."""
    rng = np.random.default_rng(7)
    J, m = particle(rng, 1)
    W = np.array([[0.0, -0.3, 0.2], [0.3, 0.0, -0.1], [-0.2, 0.1, 0.0]])
    Q, _ = np.linalg.qr(rng.standard_normal((3, 3)))
    R = Q * np.sign(np.linalg.det(Q))
    y = P.pack_state(W @ R @ J[0], R, np.zeros((3, 3)), np.zeros(3), np.zeros(3))
    ydot = P.state_rates(y, J[0], m[0], AL.reference_volume(m[0]), AL)
    Fd = P.unpack_state(ydot)[1]
    Edot = 0.5 * (R.T @ Fd + Fd.T @ R)
    np.testing.assert_allclose(Edot, 0.0, atol=1e-15)
    np.testing.assert_allclose(P.stress(R, np.zeros((3, 3)), 1.0, AL), 0.0, atol=1e-15)
    np.testing.assert_allclose(P.unpack_state(ydot)[0], 0.0, atol=1e-15)
