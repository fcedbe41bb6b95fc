"""Five tetrahedra per rectilinear cell and their initial particle state (DC3D NDDATA, JCALC, IVCALC).

Cell (i, j, k) has the lower corner node (i, j, k) and the nodes (docs/theory/debris.md, seeding)::

    n1 = (i, j, k)      n2 = (i+1, j, k)      n3 = (i+1, j+1, k)      n4 = (i, j+1, k)
    n5 = (i, j, k+1)    n6 = (i+1, j, k+1)    n7 = (i+1, j+1, k+1)    n8 = (i, j+1, k+1)

split into the listing's five tetrahedra (NDDATA, element ll = 1…5)::

    (n1, n2, n4, n5)  (n3, n4, n2, n7)  (n4, n2, n7, n5) [central, V/3]  (n8, n5, n7, n4)  (n6, n7, n5, n2)

The four corner tetrahedra have volume V/6 each. In the listing's vertex order
the last two are left-handed (negative signed volume); the model does not care
(mass, inertia and the velocity fit are orientation-free), but a writer that
needs positive orientation must swap two of their vertices.

Arrays: ``ncell`` cells, 5 tetrahedra per cell, 4 vertices, 3 coordinates; any
leading shape ``...`` is accepted where a docstring says so.
"""

from __future__ import annotations

import numpy as np

from impactdyn.debris._particle import pack_state

NODE_OFFSETS = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                         [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]])
"""Index offsets of nodes n1…n8 from the cell's lower corner, shape ``(8, 3)``."""

TET_NODES = np.array([[0, 1, 3, 4], [2, 3, 1, 6], [3, 1, 6, 4], [7, 4, 6, 3], [5, 6, 4, 1]])
"""0-based node numbers (n1 → 0) of the five tetrahedra, shape ``(5, 4)``."""

CENTRAL_TET = 2

# JCALC's reference tetrahedron and its centroid (listing xx1…xx4, xxc).
_LISTING_REFERENCE_TET = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0],
                                   [0.5, np.sqrt(0.75), 0.0], [0.5, np.sqrt(0.75) / 3.0, 1.0]])


def cell_nodes(lower, spacing) -> np.ndarray:
    """Node positions n1…n8 of rectilinear cells.

    lower ``(ncell, 3)``: lower corner (node n1) of each cell, cm; spacing ``(3,)``
    or ``(ncell, 3)``: cell edge lengths Δx, Δy, Δz. Returns ``(ncell, 8, 3)``.
    """
    lower = np.asarray(lower, dtype=float)
    spacing = np.asarray(spacing, dtype=float)
    return lower[..., None, :] + NODE_OFFSETS * spacing[..., None, :]


def gather_tets(nodal) -> np.ndarray:
    """Per-tetrahedron vertex values from per-node values of cells.

    nodal ``(ncell, 8, k)`` (positions, velocities, … at n1…n8) → ``(ncell, 5, 4, k)``.
    """
    return np.asarray(nodal)[..., TET_NODES, :]


def tet_vertices(lower, spacing) -> np.ndarray:
    """Vertex positions of the five tetrahedra of each cell, ``(ncell, 5, 4, 3)``.

    Arguments as :func:`cell_nodes`.
    """
    return gather_tets(cell_nodes(lower, spacing))


def signed_volume(x) -> np.ndarray:
    """V = det[x₂ − x₁, x₃ − x₁, x₄ − x₁] / 6 of tetrahedra ``x (..., 4, 3)``; returns ``(...)``.

    Positive when (x₂ − x₁, x₃ − x₁, x₄ − x₁) is right-handed.
    """
    x = np.asarray(x, dtype=float)
    return np.linalg.det(x[..., 1:, :] - x[..., :1, :]) / 6.0


def inertia_tensor(x, m, *, legacy_inertia_transform: bool = False) -> np.ndarray:
    """J = (m/20) Σₖ (xₖ − c)(xₖ − c)ᵀ of uniform tetrahedra (paper eq. 3d; JCALC/JREF).

    This is the second-moment tensor J = ∫ρ (r − c)⊗(r − c) dV of a uniform
    tetrahedron about its centroid c = ¼ Σₖ xₖ (exact: the integral of a
    quadratic over a simplex is (m/20)[Σₖ xₖxₖᵀ + (Σₖ xₖ)(Σₖ xₖ)ᵀ] − m ccᵀ).
    It is not the rigid-body inertia tensor I = tr(J) 𝟙 − J (g cm²), which
    follows from it; J is what the affine kinematics needs (T = ½ tr(Ḟ J Ḟᵀ)).

    x ``(..., 4, 3)`` vertices (cm), m ``(...)`` masses (g); returns ``(..., 3, 3)``.

    ``legacy_inertia_transform``: JCALC's erratum J = g⁻ᵀ J_ref g⁻¹, where g maps
    the listing's reference tetrahedron onto x (xₖ − c = g (rₖ − r_c)) and J_ref
    is the reference tetrahedron's tensor for mass m; the model is g J_ref gᵀ.
    """
    x = np.asarray(x, dtype=float)
    m = np.asarray(m, dtype=float)
    if legacy_inertia_transform:
        g, _ = affine_velocity_fit(np.broadcast_to(_LISTING_REFERENCE_TET, x.shape), x)
        J_ref = m[..., None, None] * inertia_tensor(_LISTING_REFERENCE_TET, 1.0)
        g_inv = np.linalg.inv(g)
        return np.swapaxes(g_inv, -1, -2) @ J_ref @ g_inv
    d = x - x.mean(axis=-2, keepdims=True)
    return (m[..., None, None] / 20.0) * np.einsum("...ki,...kj->...ij", d, d)


def affine_velocity_fit(x, v):
    """L, v_c of the affine field vₖ = L (xₖ − c) + v_c through four vertex velocities (IVCALC).

    x, v ``(..., 4, 3)``; returns L ``(..., 3, 3)`` (1/µs for v in cm/µs) and
    v_c ``(..., 3)``. The 12 equations in 12 unknowns decouple exactly: summing
    them gives v_c = ¼ Σₖ vₖ because Σₖ (xₖ − c) = 0, and the edge differences give
    [v₂ − v₁, v₃ − v₁, v₄ − v₁] = L [x₂ − x₁, x₃ − x₁, x₄ − x₁], one 3×3 solve.
    Singular (degenerate) tetrahedra raise ``numpy.linalg.LinAlgError``.
    """
    x = np.asarray(x, dtype=float)
    v = np.asarray(v, dtype=float)
    dx = x[..., 1:, :] - x[..., :1, :]  # rows are edges: dx = Xᵀ with X = [x₂−x₁, …]
    dv = v[..., 1:, :] - v[..., :1, :]
    # L X = V  ⇔  Xᵀ Lᵀ = Vᵀ, and dx, dv already hold Xᵀ, Vᵀ.
    L = np.swapaxes(np.linalg.solve(dx, dv), -1, -2)
    return L, v.mean(axis=-2)


def initial_state(x, v, m, *, legacy_fdot_scaling: bool = False, density_ratio=None,
                  legacy_inertia_transform: bool = False):
    """Initial particle states of tetrahedra (JCALC, INITLZ, IVCALC; docs/theory/debris.md, eq. (1)).

    F(0) = I,  H(0) = Ḟ(0) J = L J,  Eₚ(0) = 0,  p = m v_c,  c = ¼ Σₖ xₖ,
    with L, v_c from :func:`affine_velocity_fit` and J from :func:`inertia_tensor`.

    x, v ``(..., 4, 3)`` vertex positions (cm) and velocities (cm/µs); m ``(...)`` (g).
    Returns (states ``(..., 33)``, J ``(..., 3, 3)``), states packed as in
    :mod:`impactdyn.debris._particle`.

    ``legacy_fdot_scaling``: IVCALC's Ḟ(0) = L (ρ_ref/ρ)/3; needs
    ``density_ratio`` ρ/ρ_ref ``(...)``. ``legacy_inertia_transform``: see
    :func:`inertia_tensor`.
    """
    x = np.asarray(x, dtype=float)
    m = np.asarray(m, dtype=float)
    L, v_c = affine_velocity_fit(x, v)
    if legacy_fdot_scaling:
        if density_ratio is None:
            raise ValueError("legacy_fdot_scaling needs density_ratio = rho/rho_ref")
        L = L * (1.0 / (3.0 * np.asarray(density_ratio, dtype=float)))[..., None, None]
    J = inertia_tensor(x, m, legacy_inertia_transform=legacy_inertia_transform)
    identity = np.broadcast_to(np.eye(3), L.shape)
    states = pack_state(L @ J, identity, np.zeros(L.shape), m[..., None] * v_c, x.mean(axis=-2))
    return states, J
