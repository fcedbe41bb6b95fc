"""The deposition as nodal impulses: every spread and depth conserves the impulse exactly; spread
over a depth, the energy an impulse brings converges as the thickness is refined (on the front
face alone it grows with the refinement); the default depth is the report's nodal load at
refinement 1."""

import numpy as np
import pytest

from impactdyn import wall
from impactdyn.wallgrid import WallDeposition, WallGrid

GRID = WallGrid.uniform((0.0, 0.8), (0.0, 0.3175), (-0.4, 0.4), (6, 3, 6))   # 5 × 2 × 5 elements


def deposition(times=None, seed=0) -> WallDeposition:
    rng = np.random.default_rng(seed)
    n = 40
    element = rng.integers(0, GRID.n_face_elements, n)            # interior and edge elements
    impulse = rng.normal(size=(n, 3)) * 1e-5
    impulse[:, 1] = np.abs(impulse[:, 1]) * 3
    time = np.full(n, 2.0) if times is None else rng.uniform(*times, n)
    return WallDeposition(element=element, time=time, impulse=impulse)


@pytest.mark.parametrize("spread", wall.SPREADS)
@pytest.mark.parametrize("refinement", [1, 2])
@pytest.mark.parametrize("depth", [0.0, None, 0.2])
def test_impulse_taken_equals_impulse_deposited(spread, refinement, depth):
    model = wall.wall_model("mat13")
    mesh = wall.build_mesh(GRID, model.density, refinement, refinement)
    dep = deposition()
    load = wall.nodal_load(mesh, dep, spread, depth)
    np.testing.assert_allclose(np.add.reduceat(load.weight, load.ptr[:-1]), 1.0, rtol=1e-15)
    s = wall.WallSolver(mesh, model, wall.WallOptions(spread=spread, deposition_depth_cm=depth), load=load,
                        t_start=2.0)
    s.advance(np.inf, max_steps=1)          # all records arrive at the first step, on a wall at rest
    assert s.loads_done
    deposited = dep.impulse.sum(axis=0)
    applied = s.acc[1:4]
    support = s.acc[4:7]
    assert np.abs(support).max() > 0                           # edge records: the supports took a share
    np.testing.assert_allclose(applied + support, deposited, rtol=1e-12, atol=1e-12 * np.abs(deposited).max())
    # the wall's momentum after the jump is the impulse applied to its free translations
    momentum = (mesh.node_mass[:, None] * s.v).sum(axis=0)
    np.testing.assert_allclose(momentum, applied, rtol=1e-12, atol=1e-12 * np.abs(deposited).max())


def test_records_arrive_in_time_order_and_all_are_taken():
    model = wall.wall_model("mat13")
    dep = deposition(times=(1.0, 3.0), seed=4)
    options = wall.WallOptions(supports="free", end_time_us=3.5, material_model="mat13")
    res = wall.run_wall(GRID, dep, model, options)
    np.testing.assert_allclose(res.measures["impulse_applied"], dep.impulse.sum(axis=0), rtol=1e-12)
    assert np.allclose(res.measures["impulse_supports"], 0.0)
    # free wall: internal forces conserve momentum, so it stays equal to the impulse
    assert res.history["momentum_y"][-1] == pytest.approx(dep.impulse[:, 1].sum(), rel=1e-12)


def test_spread_weights():
    model = wall.wall_model("mat13")
    one = WallDeposition(element=np.array([2 + 5 * 2]), time=np.array([0.0]), impulse=np.array([[0.0, 1e-4, 0.0]]))
    m1 = wall.build_mesh(GRID, model.density)
    corners, area = wall.nodal_load(m1, one, "corners"), wall.nodal_load(m1, one, "area")
    np.testing.assert_allclose(corners.weight, 0.25)
    assert sorted(corners.node) == sorted(area.node[area.weight > 0])
    np.testing.assert_allclose(np.sort(area.weight[area.weight > 0]), 0.25)
    m3 = wall.build_mesh(GRID, model.density, 1, 3)
    corners3 = wall.nodal_load(m3, one, "corners")
    area3 = wall.nodal_load(m3, one, "area")
    assert corners3.node.size == 4 and area3.node.size == 16
    # area weights of a uniform 3 × 3 sub-grid: 1, 2, 2, 1 over 36 in each direction product
    np.testing.assert_allclose(np.sort(area3.weight), np.sort(np.outer([1, 2, 2, 1], [1, 2, 2, 1]).ravel() / 36.0))
    mass3 = wall.nodal_load(m3, one, "mass")
    dv = mass3.weight / m3.node_mass[mass3.node]               # the same velocity jump on every node
    np.testing.assert_allclose(dv, dv[0], rtol=1e-13)


COLUMN = WallGrid.uniform((0.0, 0.1), (0.0, 0.32), (0.0, 0.1), (2, 3, 2))    # one column, two layers


def load_work_on_a_column(refinement: int, depth: float | None) -> float:
    """The work of one impulse I_y = 1e-4 on the column's face element at rest, refined
    ``refinement`` times through the thickness (uniaxial: only y moves)."""
    model = wall.wall_model("mat13")
    mesh = wall.build_mesh(COLUMN, model.density, refinement, 1, supports="uniaxial")
    one = WallDeposition(element=np.array([0]), time=np.array([0.0]), impulse=np.array([[0.0, 1e-4, 0.0]]))
    options = wall.WallOptions(supports="uniaxial", material_model="mat13", deposition_depth_cm=depth)
    s = wall.WallSolver(mesh, model, options, load=wall.nodal_load(mesh, one, options.spread, depth))
    s.advance(np.inf, max_steps=1)
    return s.energies()["load_work"]


def test_load_work_over_a_depth_converges_where_on_the_face_it_grows():
    """Spread over δ = n h (a uniform body force, lumped), an impulse on nodes at rest brings
    Σ (w_j I)²/2m_j = |I|²/(2ρAδ)·(1 − 1/(4n)): front node w = h/2δ, m = ρAh/2; the n − 1
    inside w = h/δ, m = ρAh; the last w = h/2δ, m = ρAh.  On the front-face nodes alone it is
    |I|²/(ρAh), proportional to the refinement."""
    rho, area, depth, impulse = wall.wall_model("mat13").density, 0.01, 0.16, 1e-4
    for refinement, n in ((1, 1), (2, 2), (4, 4)):
        expected = impulse ** 2 / (2.0 * rho * area * depth) * (1.0 - 1.0 / (4 * n))
        assert load_work_on_a_column(refinement, depth) == pytest.approx(expected, rel=1e-12)
        front = load_work_on_a_column(refinement, 0.0)
        assert front == pytest.approx(impulse ** 2 / (rho * area * depth / n), rel=1e-12)


def test_depth_weights():
    mesh = wall.build_mesh(COLUMN, wall.wall_model("mat13").density, 4, 1)        # h = 0.04
    np.testing.assert_allclose(wall.depth_weights(mesh, 0.16), [1, 2, 2, 2, 1] / np.float64(8), rtol=1e-14)
    np.testing.assert_allclose(wall.depth_weights(mesh, 0.01), [1.0])           # inside the first half layer
    np.testing.assert_allclose(wall.depth_weights(mesh, 0.0), [1.0])            # the front face alone
    np.testing.assert_allclose(wall.depth_weights(mesh, 0.05), [0.4, 0.6], rtol=1e-14)
    np.testing.assert_allclose(wall.depth_weights(mesh, 0.32).sum(), 1.0, rtol=1e-15)
    from impactdyn._errors import InputError
    with pytest.raises(InputError, match="deposition_depth_cm"):
        wall.depth_weights(mesh, 0.33)


def test_default_depth_is_the_reports_nodal_load_at_refinement_1_and_the_same_depth_when_refined():
    model = wall.wall_model("mat13")
    dep = deposition()
    coarse = wall.build_mesh(GRID, model.density)
    assert wall.default_depth(coarse) == pytest.approx(0.5 * 0.3175 / 2)
    default, front = wall.nodal_load(coarse, dep, "area"), wall.nodal_load(coarse, dep, "area", 0.0)
    np.testing.assert_array_equal(default.node, front.node)
    np.testing.assert_array_equal(default.weight, front.weight)
    fine = wall.build_mesh(GRID, model.density, 4, 1)            # the parent's half layer = 2 fine layers
    assert wall.default_depth(fine) == wall.default_depth(coarse)
    np.testing.assert_allclose(wall.depth_weights(fine, wall.default_depth(fine)), [0.25, 0.5, 0.25], rtol=1e-14)
