"""Patch tests of the one-point hexahedron with Flanagan–Belytschko hourglass control.

* A linear velocity field on a distorted mesh gives the same velocity gradient in every
  element, no hourglass force and, with the stress it produces, no force on interior nodes.
* A rigid rotation strains nothing: a pre-stressed mesh spun through 90° carries its stress
  rotated with it (Jaumann rate), with no pressure, plastic strain or change of the invariants.
"""

import numpy as np
import pytest

from impactdyn import wall
from impactdyn.wall._state import EPS_P, P

from .conftest import distorted_grid_mesh, elastic_model


def solver_for(model, mesh, **opts):
    options = wall.WallOptions(supports="free", material_model=model.name, **opts)
    return wall.WallSolver(mesh, model, options)


# 18 bricks: one short block; 60: a full block of BLOCK = 32 and a short one (the block kernels run over
# all BLOCK bricks and compute on stale rows past the end, which must never reach an element)
@pytest.mark.parametrize("nodes", [(4, 3, 4), (6, 4, 5)], ids=["18 bricks", "60 bricks"])
@pytest.mark.parametrize("hourglass", wall.HOURGLASS_FORMS)
def test_linear_velocity_field(model_name, hourglass, nodes):
    model = elastic_model(model_name)
    mesh = distorted_grid_mesh(model, nodes=nodes)
    s = solver_for(model, mesh, hourglass=hourglass, q1=0.0, q2=0.0)
    A = np.array([[2.0, -1.0, 0.5], [0.7, 1.0, -0.3], [0.2, 0.4, 1.5]]) * 1e-3   # 1/µs, tr A > 0
    v0 = np.array([0.01, -0.02, 0.005])
    dt = 0.01
    # a velocity field linear in the midstep coordinates x_mid; x_start (the mesh) and x_end follow
    x_mid = (np.linalg.inv(np.eye(3) - 0.5 * dt * A) @ (mesh.coordinates + 0.5 * dt * v0).T).T
    v = x_mid @ A.T + v0
    s.x[:] = x_mid + 0.5 * dt * v
    s.v[:] = v
    status, _ = s.element_pass(dt)
    assert status == 0
    L = s.elements.Lbuf
    np.testing.assert_allclose(L, np.broadcast_to(A, L.shape), rtol=0, atol=1e-13 * np.abs(A).max())
    # no hourglass velocity, so no hourglass force
    hg_scale = model.density * model.wave_speed() * 0.1 ** 2 * np.abs(A).max() * 0.1
    assert np.abs(s.elements.Qhg).max() <= 1e-12 * hg_scale
    # uniform stress, and no force on interior nodes
    np.testing.assert_allclose(s.S, np.broadcast_to(s.S[0], s.S.shape), rtol=1e-10, atol=1e-18)
    np.testing.assert_allclose(s.es[:, P], s.es[0, P], rtol=1e-10)
    f = np.zeros((mesh.n_nodes, 3))
    np.add.at(f, mesh.connectivity.ravel(), s.elements.F.reshape(-1, 3))
    ijk = mesh.node_ijk()
    nx, ny, nz = mesh.shape
    interior = (ijk[:, 0] > 0) & (ijk[:, 0] < nx) & (ijk[:, 1] > 0) & (ijk[:, 1] < ny) & (ijk[:, 2] > 0) & (
        ijk[:, 2] < nz)
    assert interior.any()
    scale = np.abs(s.elements.F).max()
    assert scale > 0
    assert np.abs(f[interior]).max() <= 1e-9 * scale   # round-off of the cancelling corner forces


def rotation(axis, theta):
    axis = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(theta) * K + (1 - np.cos(theta)) * K @ K


def sym(s6):
    xx, yy, zz, xy, yz, zx = s6
    return np.array([[xx, xy, zx], [xy, yy, yz], [zx, yz, zz]])


@pytest.mark.parametrize("axis", [(0.0, 0.0, 1.0), (1.0, 2.0, -0.5)])
def test_rigid_rotation_leaves_the_stress_unchanged(model_name, axis):
    model = elastic_model(model_name)
    mesh = distorted_grid_mesh(model)
    s = solver_for(model, mesh, q1=0.0, q2=0.0)
    S0 = np.array([1.0e-3, -0.4e-3, -0.6e-3, 0.3e-3, -0.2e-3, 0.5e-3])   # deviatoric, Mbar
    s.S[:] = S0
    X0 = mesh.coordinates
    c = X0.mean(axis=0)
    n, theta = 2000, np.pi / 2
    dt = 1.0e-3
    x_prev = X0.copy()
    for step in range(1, n + 1):
        x_new = (X0 - c) @ rotation(axis, theta * step / n).T + c
        s.v[:] = (x_new - x_prev) / dt
        s.x[:] = x_new
        status, _ = s.element_pass(dt, dt)
        assert status == 0
        x_prev = x_new
    R = rotation(axis, theta)
    expected = R @ sym(S0) @ R.T
    norm = np.linalg.norm(sym(S0))
    for e in range(mesh.n_elements):
        assert np.linalg.norm(sym(s.S[e]) - expected) <= 5e-3 * norm
    # no strain: no pressure, no plastic flow, invariants kept
    assert np.abs(s.es[:, P]).max() <= 1e-12
    assert np.abs(s.es[:, EPS_P]).max() == 0.0
    vm0 = np.sqrt(1.5 * np.sum(sym(S0) ** 2))
    vm = np.sqrt(1.5 * np.array([np.sum(sym(se) ** 2) for se in s.S]))
    np.testing.assert_allclose(vm, vm0, rtol=2e-3)
    # the spin-free midstep strain rate of a rigid rotation is zero to round-off
    L = s.elements.Lbuf
    assert np.abs(L + L.transpose(0, 2, 1)).max() <= 1e-12 * np.abs(L).max()
