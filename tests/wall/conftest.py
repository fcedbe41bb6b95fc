"""Shared helpers of the wall-solver tests: small meshes, an elastic card, stepping by hand."""

from __future__ import annotations

import numpy as np
import pytest

from impactdyn import wall
from impactdyn.materials import AL_6061_T6_MAT13, Mat13Card
from impactdyn.wallgrid import WallDeposition, WallGrid

#: A small wall grid (4 × 3 × 4 elements of 0.1 cm) for the tests that run a whole wall.
SMALL_WALL = WallGrid.uniform((0.0, 0.4), (0.0, 0.3), (0.0, 0.4), (5, 4, 5))


def two_records(impulse: float = 1e-6) -> WallDeposition:
    """Two deposition records on SMALL_WALL's face, at 1 and 2.5 µs, each an impulse ``impulse`` along y."""
    return WallDeposition(element=np.array([0, 6]), time=np.array([1.0, 2.5]),
                          impulse=np.array([[0.0, impulse, 0.0]] * 2))


#: The report's card with a yield stress no test load reaches: linear elastic (K 0.72, G 0.276 Mbar).
ELASTIC_CARD = Mat13Card(density=AL_6061_T6_MAT13.density, shear_modulus=AL_6061_T6_MAT13.shear_modulus,
                         bulk_modulus=AL_6061_T6_MAT13.bulk_modulus, yield_stress=10.0, hardening_modulus=0.0,
                         failure_strain=0.0, failure_pressure=-1.0e30)


def elastic_model(name: str) -> wall.WallModel:
    """An elastic (at the tests' small strains) model of each registered kind."""
    if name == "mat13":
        return wall.Mat13Model(ELASTIC_CARD, source="test: elastic card")
    return wall.wall_model(name, "al6061-t6", damage=None, spall=False, erosion=False)


def one_element(model: wall.WallModel) -> wall.WallSolver:
    """A solver over one free 0.1-cm brick of ``model``, without bulk viscosity."""
    grid = WallGrid.uniform((0.0, 0.1), (0.0, 0.1), (0.0, 0.1), (2, 2, 2))
    mesh = wall.build_mesh(grid, model.density, supports="free")
    return wall.WallSolver(mesh, model, wall.WallOptions(supports="free", material_model=model.name, q1=0.0, q2=0.0))


def drive(s: wall.WallSolver, gradient, steps: int, dt: float = 0.005, stop=None) -> None:
    """Move the nodes with the homogeneous velocity field v = A x for ``steps`` steps (by hand),
    until ``stop(s)`` is true."""
    for _ in range(steps):
        s.v[:] = s.x @ np.asarray(gradient).T
        s.x[:] += dt * s.v
        status, _ = s.element_pass(dt, dt)
        assert status == 0
        if stop is not None and stop(s):
            break


def elastic_moduli(model: wall.WallModel) -> tuple[float, float, float]:
    """(ρ₀, K, G) of the elastic models above."""
    if isinstance(model, wall.Mat13Model):
        c = model.card
        return c.density, c.bulk_modulus, c.shear_modulus
    m = model.material
    return m.rho0, m.rho0 * m.c0 ** 2, m.shear_modulus


def distorted_grid_mesh(model: wall.WallModel, seed: int = 3, amplitude: float = 0.15,
                        nodes: tuple[int, int, int] = (4, 3, 4)) -> wall.WallMesh:
    """A free brick mesh of 0.1-cm bricks (3 × 2 × 3 by default; ``nodes`` per axis) whose nodes are
    moved randomly (a distorted patch)."""
    g = WallGrid.uniform(*((0.0, 0.1 * (n - 1)) for n in nodes), nodes)
    mesh = wall.build_mesh(g, model.density, supports="free")
    rng = np.random.default_rng(seed)
    coords = mesh.coordinates.copy()
    coords += amplitude * 0.1 * rng.uniform(-1.0, 1.0, coords.shape)
    conn = mesh.connectivity
    from impactdyn.wall._hex import element_volumes

    vol = element_volumes(coords, conn)
    assert np.all(vol > 0)
    return wall.WallMesh(parent=mesh.parent, grid=mesh.grid, refinement=mesh.refinement, coordinates=coords,
                         connectivity=conn, volume=vol, element_mass=model.density * vol,
                         node_mass=mesh.node_mass, fixed=mesh.fixed, supports=mesh.supports,
                         node_element_ptr=mesh.node_element_ptr, node_element_entry=mesh.node_element_entry,
                         density=mesh.density)


@pytest.fixture(params=sorted(wall.MODELS))
def model_name(request) -> str:
    """Every registered wall model."""
    return request.param
