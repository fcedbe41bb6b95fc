"""Cubic-spline kernel and the cell-list neighbour search of the SPH shield stage."""

import itertools

import numpy as np
import pytest
from scipy.integrate import quad

from impactdyn._errors import InputError
from impactdyn.shield import Domain, neighbour_pairs
from impactdyn.shield._kernel import SUPPORT, gradient_factor, kernel


@pytest.mark.parametrize("h", [0.01, 0.3, 2.0])
def test_kernel_normalised(h):
    total, _ = quad(lambda r: 4 * np.pi * r * r * kernel(r, h), 0, SUPPORT * h, points=[h], epsabs=0, epsrel=1e-12)
    assert total == pytest.approx(1.0, rel=1e-10)
    assert kernel(2.0 * h, h) == 0.0 and kernel(3.0 * h, h) == 0.0


def test_kernel_lattice_partition_of_unity():
    dx, h = 0.1, 0.13
    k = np.arange(-4, 5)
    g = dx * np.stack(np.meshgrid(k, k, k, indexing="ij"), -1).reshape(-1, 3)
    x0 = np.array([0.013, -0.021, 0.037])
    r = np.linalg.norm(x0 - g, axis=1)
    assert dx**3 * sum(kernel(ri, h) for ri in r) == pytest.approx(1.0, abs=5e-3)
    # the SPH gradient of a linear field f = a·x on the lattice recovers a
    a = np.array([0.3, -1.2, 2.0])
    grad = sum(dx**3 * (a @ (gj - x0)) * gradient_factor(ri, h) * (x0 - gj) for gj, ri in zip(g, r))
    np.testing.assert_allclose(grad, a, rtol=2e-2, atol=2e-2)


@pytest.mark.parametrize("q", [0.0, 0.3, 0.99, 1.0, 1.01, 1.7, 1.999])
def test_kernel_gradient_matches_finite_difference(q):
    h, eps = 0.2, 1e-7
    direction = np.array([0.48, -0.6, 0.64])
    dx = q * h * direction
    fd = np.array([(kernel(np.linalg.norm(dx + eps * e), h) - kernel(np.linalg.norm(dx - eps * e), h)) / (2 * eps)
                   for e in np.eye(3)])
    np.testing.assert_allclose(gradient_factor(q * h, h) * dx, fd, rtol=1e-5, atol=1e-6 / h**4)


def brute_force_pairs(x, h, domain):
    signs, offsets = domain.transforms()
    rows = []
    for i, (t, (s, o)) in itertools.product(range(len(x)), enumerate(zip(signs, offsets))):
        d = np.linalg.norm(x[i] - (s * x + o), axis=1)
        for j in np.nonzero(d < h[i] + h)[0]:
            if not (t == 0 and j == i):
                rows.append((i, j, t))
    return np.array(sorted(rows)).reshape(-1, 3)


@pytest.mark.parametrize("domain", [
    Domain(),
    Domain(mirror=((0, 0.0),)),
    Domain(periodic=((0, 0.0, 1.0), (2, -0.5, 0.5))),
    Domain(mirror=((0, 0.0),), periodic=((1, 0.0, 1.0),)),
], ids=["free", "mirror", "periodic", "mirror+periodic"])
def test_neighbour_search_matches_brute_force(domain):
    rng = np.random.default_rng(7)
    x = rng.random((400, 3)) * [1.0, 1.0, 1.0] - [0.0, 0.0, 0.5]
    x[:20] = x[20:40] + 1e-3  # near-coincident particles
    h = rng.uniform(0.03, 0.09, 400)
    got = neighbour_pairs(x, h, domain)
    want = brute_force_pairs(x, h, domain)
    assert len(want) > 1000
    np.testing.assert_array_equal(got, want)


def test_neighbour_search_with_far_outlier():
    """A far outlier enlarges the cells (bounded table) but the pairs stay exact."""
    rng = np.random.default_rng(3)
    x = rng.random((300, 3))
    x[0] = [1e4, -3e4, 2e4]
    h = np.full(300, 0.06)
    np.testing.assert_array_equal(neighbour_pairs(x, h), brute_force_pairs(x, h, Domain()))


def test_domain_validation():
    with pytest.raises(InputError):
        Domain(mirror=((0, 0.0),), periodic=((0, 0.0, 1.0),))
    with pytest.raises(InputError):
        Domain(periodic=((1, 1.0, 1.0),))
    signs, offsets = Domain(mirror=((0, 0.5),)).transforms()
    np.testing.assert_array_equal(signs, [[1, 1, 1], [-1, 1, 1]])
    np.testing.assert_array_equal(offsets, [[0, 0, 0], [1.0, 0, 0]])
