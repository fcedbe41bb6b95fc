"""Sphere-on-plate half model: conservation, set-up geometry, binning to a HydroGrid, input errors."""

import math

import numpy as np
import pytest

from impactdyn import shield
from impactdyn._errors import InputError
from impactdyn.materials import AL_6061_T6, AL_2024_T4

D, DX, T_END = 0.2, 0.025, 0.3


@pytest.fixture(scope="module")
def impact():
    problem = shield.sphere_on_plate(AL_2024_T4, AL_6061_T6, diameter_cm=D, velocity_km_s=5.0, obliquity_deg=30.0,
                                     plate_thickness_cm=0.05, spacing_cm=DX, plate_radius_cm=0.3)
    calls = []
    result = shield.run(problem, T_END, snapshot_times_us=(0.1,), progress=lambda t, t_end: calls.append(t))
    return problem, result, calls


def test_setup_geometry():
    problem = shield.sphere_on_plate("al6061-t6", "al6061-t6", diameter_cm=0.5, velocity_km_s=7.0,
                                     obliquity_deg=25.0, plate_thickness_cm=0.127, spacing_cm=0.05)
    p = problem.particles
    assert p.materials == ("al6061-t6",) and problem.domain.mirror == ((0, 0.0),)
    assert np.all(p.position[:, 0] > 0)
    moving = np.linalg.norm(p.velocity, axis=1) > 0
    # the half sphere has the exact half-sphere mass and moves at 0.7 cm/µs along (0, cos 25°, sin 25°)
    assert p.mass[moving].sum() == pytest.approx(2.703 * math.pi * 0.5**3 / 12, rel=1e-12)
    np.testing.assert_allclose(p.velocity[moving][0], 0.7 * np.array([0, math.cos(0.436332313), math.sin(0.436332313)]))
    # the plate's areal density is exact: 0.127 cm of Al over the half disc (to the lattice's area error)
    plate = ~moving
    assert p.position[plate, 1].min() > 0 and p.position[plate, 1].max() < 0.127
    assert p.mass[plate].sum() == pytest.approx(2.703 * 0.127 * math.pi * 1.0**2 / 2, rel=0.03)
    assert p.position[moving, 1].max() < 0


def test_momentum_and_energy_conserved(impact):
    _, result, calls = impact
    h = result.history
    assert len(calls) == result.steps == len(h.time) - 1 and calls[-1] == T_END
    assert np.all(h.mass == h.mass[0])
    p0 = np.linalg.norm(h.momentum[0])
    # the symmetry plane exchanges x-momentum with the mirror half; y and z are conserved to round-off
    assert np.abs(h.momentum[:, 1:] - h.momentum[0, 1:]).max() / p0 < 1e-10
    assert np.abs(h.total_energy / h.total_energy[0] - 1).max() < 0.01
    assert h.internal[-1] > 0.05 * h.total_energy[0]  # the impact has happened
    state = result.state
    assert state.time == T_END and result.snapshots[0].time == 0.1
    assert state.failed.any() and state.plastic_strain.max() > 0
    assert np.all(state.position[:, 0] > 0)


def test_binned_grid_carries_particle_mass_and_momentum(impact):
    _, result, _ = impact
    state = result.state
    grid = shield.bin_to_hydrogrid(state, cell_size_cm=0.03)
    assert grid.total_mass() == pytest.approx(state.total_mass(), rel=1e-13)
    np.testing.assert_allclose(grid.total_momentum(), state.total_momentum(), rtol=1e-12,
                               atol=1e-13 * np.abs(state.total_momentum()).max())
    assert grid.x[0] == 0.0 and not grid.staggered and grid.time == T_END
    filled = grid.mass > 0
    assert np.all((grid.void_fraction >= 0) & (grid.void_fraction <= 1)) and np.all(grid.void_fraction[~filled] == 1)
    # bulk density (1 − φ) ρ times the cell volume gives back the cell mass
    np.testing.assert_allclose(((1 - grid.void_fraction) * grid.density * grid.cell_volumes())[filled],
                               grid.mass[filled], rtol=1e-9)
    # a region that holds part of the particles holds exactly their mass
    region = ((0.0, 0.3), (-0.1, 0.2), (-0.3, 0.3))
    sub = shield.bin_to_hydrogrid(state, 0.03, region=region)
    x = state.position
    inside = np.all((x >= [r[0] for r in region]) & (x <= [r[1] for r in region]), axis=1)
    assert sub.total_mass() == pytest.approx(state.mass[inside].sum(), rel=1e-13)


def test_binning_of_a_uniform_block():
    """A lattice block at ρ₀ binned on aligned cells of two spacings: interior cells are full and at ρ₀."""
    problem = shield.planar_impact("al6061-t6", "al6061-t6", 1.0, 0.08, 0.08, 0.01, width_particles=8)
    grid = shield.bin_to_hydrogrid(problem.particles, 0.02, region=((0, 0.08), (-0.08, 0.08), (0, 0.08)))
    interior = (slice(1, -1),) * 3
    np.testing.assert_allclose(grid.density[interior], 2.703, rtol=1e-12)
    np.testing.assert_allclose(grid.void_fraction[interior], 0.0, atol=1e-12)
    np.testing.assert_allclose(grid.pressure, 0.0)
    assert grid.total_mass() == pytest.approx(problem.particles.total_mass(), rel=1e-13)


@pytest.mark.parametrize("change, message", [
    (dict(obliquity_deg=90.0), "obliquity_deg"),
    (dict(diameter_cm=0.0), "diameter_cm"),
    (dict(projectile="unobtainium"), "unknown material .unobtainium.; choose one of"),
    (dict(spacing_cm=0.2), "spacing_cm"),
    (dict(velocity_km_s=float("nan")), "velocity_km_s"),
    (dict(plate_radius_cm=0.1), "plate_radius_cm"),
])
def test_bad_input(change, message):
    args = dict(projectile="al6061-t6", plate="al6061-t6", diameter_cm=0.5, velocity_km_s=7.0, obliquity_deg=25.0,
                plate_thickness_cm=0.127, spacing_cm=0.05) | change
    with pytest.raises(InputError, match=message):
        shield.sphere_on_plate(**args)


def test_bad_run_arguments():
    problem = shield.planar_impact("al6061-t6", "al6061-t6", 1.0, 0.05, 0.05, 0.01)
    with pytest.raises(InputError, match="t_end_us"):
        shield.run(problem, -1.0)
    with pytest.raises(InputError, match="snapshot_times_us"):
        shield.run(problem, 1.0, snapshot_times_us=(2.0,))
    with pytest.raises(InputError, match="flow_stress"):
        shield.SPHOptions(flow_stress="steinberg")


def test_johnson_cook_and_hydrodynamic_options_run():
    """The options change the material response but not the conservation properties."""
    problem = shield.sphere_on_plate("al6061-t6", "al2024-t4", diameter_cm=0.15, velocity_km_s=3.0, obliquity_deg=0.0,
                                     plate_thickness_cm=0.05, spacing_cm=0.025, plate_radius_cm=0.2)
    for options in (shield.SPHOptions(flow_stress="johnson_cook"),
                    shield.SPHOptions(artificial_stress=0.0, failure=False, alpha=1.5, beta=1.5)):
        h = shield.run(problem, 0.1, options=options).history
        assert np.abs(h.momentum[:, 1:] - h.momentum[0, 1:]).max() < 1e-10 * np.abs(h.momentum[0]).max()
        assert np.abs(h.total_energy / h.total_energy[0] - 1).max() < 0.01


def test_particles_and_problem_validation():
    problem = shield.planar_impact("al6061-t6", "al6061-t6", 1.0, 0.03, 0.03, 0.01)
    p = problem.particles
    with pytest.raises(InputError, match="Particles.density"):
        p.replace(density=np.full(len(p) + 1, 2.7))
    with pytest.raises(InputError, match="not finite"):
        p.replace(specific_energy=np.full(len(p), np.nan))
    with pytest.raises(InputError, match="Problem"):
        shield.Problem(particles=p, materials=(AL_2024_T4,), spacing_cm=problem.spacing_cm)
    with pytest.raises(InputError, match="Problem.spacing_cm"):
        shield.Problem(particles=p, materials=problem.materials, spacing_cm=0.0)
    assert p.position.flags.writeable is False
