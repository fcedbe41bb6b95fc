"""Tetrahedra of a cell, inertia tensor, affine velocity fit, initial state (docs/theory/debris.md)."""

from math import factorial

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from impactdyn.debris import _tets as T
from impactdyn.debris._particle import kinetic_energy, unpack_state

# docs/theory/debris.md (seeding), transcribed by name: the node coordinates and the five tetrahedra.
NODES = {"n1": (0, 0, 0), "n2": (1, 0, 0), "n3": (1, 1, 0), "n4": (0, 1, 0),
         "n5": (0, 0, 1), "n6": (1, 0, 1), "n7": (1, 1, 1), "n8": (0, 1, 1)}
TETS = [("n1", "n2", "n4", "n5"), ("n3", "n4", "n2", "n7"), ("n4", "n2", "n7", "n5"),
        ("n8", "n5", "n7", "n4"), ("n6", "n7", "n5", "n2")]

# Degree-2 exact 4-point rule on a tetrahedron (Keast 1986), barycentric (a, b, b, b).
_A, _B = (5 + 3 * np.sqrt(5)) / 20, (5 - np.sqrt(5)) / 20
QUAD_BARY = np.full((4, 4), _B) + np.eye(4) * (_A - _B)

finite = st.floats(-10, 10, allow_nan=False, allow_infinity=False)


def well_shaped(x):
    """|V| not tiny against the edge length cubed (a degenerate tetrahedron has no fit)."""
    edges = np.linalg.norm(x[:, None] - x[None], axis=-1).max()
    return abs(T.signed_volume(x)) > 1e-3 * edges**3


tetrahedra = arrays(float, (4, 3), elements=finite).filter(well_shaped)


def test_tetrahedra_are_the_listing_ones():
    lower, spacing = np.array([[2.0, -1.0, 0.5]]), np.array([0.3, 0.5, 0.7])
    x = T.tet_vertices(lower, spacing)[0]
    for t, names in enumerate(TETS):
        expected = [lower[0] + np.array(NODES[n]) * spacing for n in names]
        np.testing.assert_allclose(x[t], expected, rtol=0, atol=1e-15)


@pytest.mark.parametrize("spacing", [(1.0, 1.0, 1.0), (0.03175, 0.02, 0.05), (3.0, 0.1, 0.7)])
def test_five_tetrahedra_fill_the_cell(spacing):
    spacing = np.array(spacing)
    lower = np.array([[0.4, -0.2, 1.1]])
    x = T.tet_vertices(lower, spacing)[0]
    cell_volume = np.prod(spacing)
    v = T.signed_volume(x)
    np.testing.assert_allclose(np.abs(v).sum(), cell_volume, rtol=1e-13)
    np.testing.assert_allclose(abs(v[T.CENTRAL_TET]), cell_volume / 3, rtol=1e-13)
    corners = np.delete(np.abs(v), T.CENTRAL_TET)
    np.testing.assert_allclose(corners, cell_volume / 6, rtol=1e-13)
    # the listing's vertex order: the last two are left-handed (module docstring)
    np.testing.assert_array_equal(np.sign(v), [1, 1, 1, -1, -1])

    # no overlap, no gap: every point of the cell lies in exactly one tetrahedron
    rng = np.random.default_rng(0)
    pts = lower[0] + rng.random((20000, 3)) * spacing
    edges = x[:, 1:] - x[:, :1]                                   # (5, 3, 3) rows = edges
    lam = np.linalg.solve(np.swapaxes(edges, 1, 2)[None], (pts[:, None] - x[None, :, 0])[..., None])[..., 0]
    bary = np.concatenate([1 - lam.sum(-1, keepdims=True), lam], axis=-1)   # (npts, 5, 4)
    inside = np.all(bary >= -1e-12, axis=-1)
    np.testing.assert_array_equal(inside.sum(axis=1), 1)


def monomial_integral(a, b, c):
    """∫ x^a y^b z^c over the unit right-corner tetrahedron = a! b! c! / (a+b+c+3)!."""
    return factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 3)


def test_inertia_of_unit_right_corner_tetrahedron():
    x = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    rho = 2.7
    volume = monomial_integral(0, 0, 0)
    m = rho * volume
    c = monomial_integral(1, 0, 0) / volume                      # centroid coordinate (all equal)
    second = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            powers = np.zeros(3, dtype=int)
            powers[i] += 1
            powers[j] += 1
            second[i, j] = monomial_integral(*powers)
    central = rho * (second - volume * c * c)                   # ∫ρ(x−c)(x−c)ᵀ, all c_i equal
    np.testing.assert_allclose(T.inertia_tensor(x, m), central, rtol=1e-14)


@settings(max_examples=60, deadline=None)
@given(x=tetrahedra, m=st.floats(1e-6, 1e3))
def test_inertia_matches_exact_quadrature(x, m):
    q = QUAD_BARY @ x                                           # quadrature points
    c = x.mean(axis=0)
    d = q - c
    expected = m * np.einsum("q,qi,qj->ij", np.full(4, 0.25), d, d)
    scale = m * np.abs(x - c).max() ** 2
    np.testing.assert_allclose(T.inertia_tensor(x, m), expected, rtol=0, atol=1e-13 * scale)


def test_legacy_inertia_transform():
    ref = T._LISTING_REFERENCE_TET
    theta = 0.7
    R = np.array([[np.cos(theta), -np.sin(theta), 0], [np.sin(theta), np.cos(theta), 0], [0, 0, 1]])
    rotated = ref @ R.T + np.array([1.0, 2.0, 3.0])
    # g orthogonal: g⁻ᵀ J_ref g⁻¹ = g J_ref gᵀ, the erratum is invisible
    np.testing.assert_allclose(T.inertia_tensor(rotated, 1.3, legacy_inertia_transform=True),
                               T.inertia_tensor(rotated, 1.3), rtol=1e-12, atol=1e-15)
    # g = 2I: the model scales J_ref by 4, the listing by 1/4
    J_ref = T.inertia_tensor(ref, 1.3)
    np.testing.assert_allclose(T.inertia_tensor(2 * ref, 1.3), 4 * J_ref, rtol=1e-13)
    np.testing.assert_allclose(T.inertia_tensor(2 * ref, 1.3, legacy_inertia_transform=True),
                               J_ref / 4, rtol=1e-13, atol=1e-16)


@settings(max_examples=80, deadline=None)
@given(x=tetrahedra, v=arrays(float, (4, 3), elements=finite))
def test_affine_fit_reproduces_vertex_velocities(x, v):
    L, v_c = T.affine_velocity_fit(x, v)
    c = x.mean(axis=0)
    fitted = (x - c) @ L.T + v_c
    np.testing.assert_allclose(fitted, v, rtol=0, atol=1e-12 * max(1.0, np.abs(v).max()))

    # the 12×12 system of IVCALC, solved directly
    A = np.zeros((12, 12))
    for k in range(4):
        for i in range(3):
            A[3 * k + i, 3 * i:3 * i + 3] = x[k] - c
            A[3 * k + i, 9 + i] = 1.0
    s = np.linalg.solve(A, v.reshape(12))
    np.testing.assert_allclose(L, s[:9].reshape(3, 3), rtol=1e-8, atol=1e-8 * max(1.0, np.abs(L).max()))
    np.testing.assert_allclose(v_c, s[9:], rtol=1e-8, atol=1e-8 * max(1.0, np.abs(v).max()))


def test_affine_fit_recovers_an_affine_field():
    rng = np.random.default_rng(3)
    x = T.tet_vertices(rng.random((6, 3)), np.array([0.03, 0.02, 0.04]))
    A, b = rng.standard_normal((3, 3)), rng.standard_normal(3)
    L, v_c = T.affine_velocity_fit(x, x @ A.T + b)
    np.testing.assert_allclose(L, np.broadcast_to(A, L.shape), rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(v_c, x.mean(axis=-2) @ A.T + b, rtol=1e-12)


def test_initial_state_and_its_kinetic_energy():
    rng = np.random.default_rng(4)
    x = T.tet_vertices(rng.random((3, 3)), np.array([0.03175, 0.03, 0.02]))      # (3, 5, 4, 3)
    v = np.array([0.0, 0.7, 0.0]) + 0.02 * rng.standard_normal(x.shape)
    m = 2.703 * np.abs(T.signed_volume(x))
    states, J = T.initial_state(x, v, m)
    H, F, Ep, p, c = unpack_state(states)
    L, v_c = T.affine_velocity_fit(x, v)
    np.testing.assert_array_equal(F, np.broadcast_to(np.eye(3), F.shape))
    np.testing.assert_array_equal(Ep, 0.0)
    np.testing.assert_allclose(H, L @ J, rtol=1e-13)
    np.testing.assert_allclose(p, m[..., None] * v_c, rtol=1e-14)
    np.testing.assert_allclose(c, x.mean(axis=-2), rtol=1e-14)
    # T = ½ tr(Ḟ J Ḟᵀ) + ½|p|²/m equals ½∫ρ|v|² of the affine field (exact quadrature)
    q = np.einsum("qk,...ki->...qi", QUAD_BARY, x)
    vq = np.einsum("...ij,...qj->...qi", L, q - c[..., None, :]) + v_c[..., None, :]
    expected = 0.5 * m * np.mean(np.sum(vq**2, axis=-1), axis=-1)
    np.testing.assert_allclose(kinetic_energy(states, J, m), expected, rtol=1e-12)


def test_legacy_fdot_scaling():
    rng = np.random.default_rng(5)
    x = T.tet_vertices(np.zeros((1, 3)), np.full(3, 0.03))[0]
    v = rng.standard_normal(x.shape)
    m = np.abs(T.signed_volume(x))
    ratio = np.array([0.5, 1.0, 2.0, 4.0, 0.25])
    model, J = T.initial_state(x, v, m)
    legacy, _ = T.initial_state(x, v, m, legacy_fdot_scaling=True, density_ratio=ratio)
    expected = unpack_state(model)[0] / (3 * ratio)[:, None, None]
    # (L·s)J and (LJ)·s differ by rounding only
    np.testing.assert_allclose(unpack_state(legacy)[0], expected, rtol=1e-13,
                               atol=1e-14 * np.abs(expected).max())
    np.testing.assert_array_equal(legacy[:, 9:], model[:, 9:])
    with pytest.raises(ValueError, match="density_ratio"):
        T.initial_state(x, v, m, legacy_fdot_scaling=True)
