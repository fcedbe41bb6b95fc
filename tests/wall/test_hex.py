"""The one-point hexahedron: FB's volume gradient against Gauss quadrature, and the hourglass vectors."""

import itertools

import numpy as np
import pytest

from impactdyn.wall._hex import ETA, XI, ZETA, brick_gradient, brick_hourglass


def distorted_brick(seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    X = 0.5 * (np.stack([XI, ETA, ZETA], axis=1) + 1.0) * [0.16, 0.079, 0.16]
    return X + rng.normal(scale=0.015, size=(8, 3))


def gauss_gradient(X: np.ndarray) -> tuple[np.ndarray, float]:
    """∫ ∂N_a/∂x_i dV and V by 2 × 2 × 2 Gauss quadrature (exact for the trilinear brick)."""
    g = 1.0 / np.sqrt(3.0)
    B = np.zeros((8, 3))
    vol = 0.0
    for xi, eta, zeta in itertools.product((-g, g), repeat=3):
        dN = np.stack([XI * (1 + ETA * eta) * (1 + ZETA * zeta), ETA * (1 + XI * xi) * (1 + ZETA * zeta),
                       ZETA * (1 + XI * xi) * (1 + ETA * eta)], axis=1) / 8.0
        J = dN.T @ X
        det = np.linalg.det(J)
        B += np.linalg.solve(J, dN.T).T * det
        vol += det
    return B, vol


@pytest.mark.parametrize("seed", range(5))
def test_volume_gradient_is_the_exact_mean_gradient(seed):
    X = distorted_brick(seed)
    B, vol = brick_gradient(X)
    Bg, vg = gauss_gradient(X)
    assert vol == pytest.approx(vg, rel=1e-13)
    assert np.abs(B - Bg).max() <= 1e-13 * np.abs(Bg).max()
    # the mean gradient integrates linear fields exactly: Σ_a b_ia x_ja = δ_ij, Σ_a b_ia = 0
    np.testing.assert_allclose(B.T @ X / vol, np.eye(3), atol=1e-13)
    np.testing.assert_allclose(B.sum(axis=0), 0.0, atol=1e-16)


def test_reference_brick_volume_and_orientation():
    X = 0.5 * (np.stack([XI, ETA, ZETA], axis=1) + 1.0) * [2.0, 3.0, 5.0]
    B, vol = brick_gradient(X)
    assert vol == pytest.approx(30.0, rel=1e-15)
    # DYNGEN's order (back face first, then front) is positive too: ξ → x, η → z, ζ → −y
    Xd = 0.5 * (np.stack([XI, -ZETA, ETA], axis=1) + 1.0) * [2.0, 3.0, 5.0]
    assert brick_gradient(Xd)[1] == pytest.approx(30.0, rel=1e-15)


@pytest.mark.parametrize("seed", range(3))
def test_hourglass_vectors_are_orthogonal_to_linear_fields(seed):
    X = distorted_brick(seed)
    G = brick_hourglass(X)
    scale = np.abs(G).max()
    np.testing.assert_allclose(G.sum(axis=1), 0.0, atol=1e-14 * scale)
    np.testing.assert_allclose(G @ X, 0.0, atol=1e-14 * scale * np.abs(X).max())
    # four independent modes
    assert np.linalg.matrix_rank(G) == 4
