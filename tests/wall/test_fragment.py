"""One compact fragment on the wall: its deposition records, and the crater they make against (S1).

The wall stage is loaded by momentum records only; these tests check that a compact aluminium
sphere laid on a fine face grid by :func:`impactdyn.wallgrid.sphere_deposition` carries the
sphere's momentum at the rate and over the time a stopped rod would, and that the wall it
strikes perforates on the near side of the Cour-Palais single-wall limit (S1,
:mod:`impactdyn.ble`) and not far below it (studies/fragments/fragment_crater.py, docs/vv/convergence.md "The wall: one
compact fragment under mesh refinement").
"""

from __future__ import annotations

import numpy as np
import pytest

from impactdyn import ble, wall
from impactdyn._errors import InputError
from impactdyn.materials import get_material
from impactdyn.wallgrid import WallGrid, sphere_deposition

RHO_P = 2.7


def half_model(cell: float, thickness: float = 0.16, half_width: float = 0.4) -> WallGrid:
    n = int(round(half_width / cell))
    return WallGrid.uniform((0.0, n * cell), (0.0, thickness), (-n * cell, n * cell),
                            (n + 1, int(round(thickness / cell)) + 1, 2 * n + 1))


@pytest.mark.parametrize("cells_across, rel", [(4, 3e-3), (8, 3e-4), (16, 3e-4)])
def test_sphere_records_carry_the_half_spheres_momentum_over_its_transit(cells_across, rel):
    d, v = 0.06, 0.6
    dep = sphere_deposition(half_model(d / cells_across), d, v, RHO_P, t0_us=1.0)
    half_momentum = RHO_P * np.pi * d**3 / 12.0 * v
    assert dep.impulse[:, 1].sum() == pytest.approx(half_momentum, rel=rel)
    assert np.all(dep.impulse[:, [0, 2]] == 0.0) and np.all(dep.impulse[:, 1] > 0.0)
    assert dep.time.min() >= 1.0 and dep.time.max() <= 1.0 + d / v


def test_sphere_records_arrive_at_a_stopped_rods_rate():
    """The central cell's column (length ≈ d) takes ρ V² per unit area per unit time over d / V."""
    cell, d, v = 0.005, 0.06, 0.6
    grid = half_model(cell, half_width=0.05)
    dep = sphere_deposition(grid, d, v, RHO_P, t0_us=0.0)
    nx = grid.x.size - 1
    centre = nx * (int(np.searchsorted(grid.z, 0.0, side="right")) - 1)      # i = 0, the cell at z 0…h
    rows = dep.element == centre
    time = dep.time[rows]
    rate = dep.impulse[rows, 1] / (cell * cell * (cell / v))
    interior = (time > 0.2 * d / v) & (time < 0.8 * d / v)
    assert interior.sum() >= 6
    assert rate[interior] == pytest.approx(RHO_P * v * v, rel=0.02)


@pytest.mark.parametrize("bad", [{"diameter_cm": 0.0}, {"speed_cm_us": -1.0}, {"density_g_cm3": np.nan},
                                 {"samples": 0}])
def test_sphere_deposition_rejects_bad_input(bad):
    kwargs = {"diameter_cm": 0.06, "speed_cm_us": 0.6, "density_g_cm3": RHO_P, **bad}
    with pytest.raises(InputError, match=next(iter(bad))):
        sphere_deposition(half_model(0.02), **kwargs)


def test_a_compact_fragment_perforates_near_the_single_wall_limit_and_not_far_below_it():
    """A 0.16-cm 2024 wall at 6 km/s, 0.02-cm cells: (S1) puts the perforation limit at d_c ≈ 0.060 cm;
    the wall stage perforates at 1.2 d_c and stays whole at 0.5 d_c (its own limit, by bisection:
    0.77 d_c at this mesh, 0.67–0.82 d_c at 0.01–0.04 cm; docs/vv/convergence.md)."""
    grid = half_model(0.02)
    v_km_s = 6.0
    single = ble.SingleWall(0.16, get_material("al2024-t4").rho0, ble.BRINELL_HARDNESS["al2024-t4"])
    d_c = float(ble.single_wall_critical_diameter(single, v_km_s, 0.0, RHO_P))
    verdicts = {}
    for factor in (0.5, 1.2):
        d = factor * d_c
        dep = sphere_deposition(grid, d, 0.1 * v_km_s, RHO_P, t0_us=1.0)
        options = wall.WallOptions(material_model="johnson_cook", supports="clamped",
                                   end_time_us=float(dep.time.max()) + 4.0, deposition_depth_cm=d)
        verdicts[factor] = wall.run_wall(grid, dep, "al2024-t4", options).verdict
    assert verdicts == {0.5: wall.NO_PERFORATION, 1.2: wall.PERFORATION}
