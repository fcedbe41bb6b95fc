"""Seeding, arrival times, deposition and DCPOST's areal density (docs/theory/debris.md)."""

import numpy as np
import pytest

from impactdyn.debris import (
    AL_6061_T6_MAT13, CRATERING_MOMENTUM, POINTS_PER_PARTICLE, ArrivalWindow, ComputeOptions, DepositionOptions,
    HydroGrid, ParticleMaterial, SeedFilter, WallGrid, areal_density, arrival_times, cratering_factor, cratering_momentum, deposit,
    element_impulse, element_records, face_areas, face_element,
    propagate_chunked, remap_impulse, run_debris, seed_cells, seed_particles, signed_volume)

AL = ParticleMaterial(mu=0.276, lam=0.536, rho_ref=2.703, eta=1.0)


def slab_grid(shape=(4, 3, 4), spacing=0.1, velocity=(0.0, 0.5, 0.0), origin=(0.0, -1.0, 0.0),
              density=2.703, phi=0.2, staggered=False) -> HydroGrid:
    """A uniform block of material moving at one velocity (cm/µs)."""
    nodes = [origin[d] + spacing * np.arange(shape[d] + 1) for d in range(3)]
    ones = np.ones(shape)
    volume = spacing**3
    return HydroGrid(*nodes, density=density * ones, void_fraction=phi * ones,
                     mass=(1 - phi) * density * volume * ones, pressure=0 * ones, temperature=300 * ones,
                     specific_energy=0 * ones, sound_speed=0.5 * ones,
                     velocity=np.broadcast_to(np.asarray(velocity, float), shape + (3,)), staggered=staggered)


def test_five_particles_per_cell_carry_the_cell_mass_and_momentum():
    g = slab_grid()
    cloud = seed_particles(g, AL)
    assert len(cloud) == 5 * 4 * 3 * 4
    np.testing.assert_allclose(cloud.mass.sum(), g.total_mass(), rtol=1e-13)
    np.testing.assert_allclose(cloud.momentum.sum(axis=0), g.total_momentum(), rtol=1e-13, atol=1e-15)
    # tetrahedra of one cell fill it: |volumes| sum to the cell volume, the central one a third
    vol = np.abs(signed_volume(cloud.vertices)).reshape(-1, 5)
    np.testing.assert_allclose(vol.sum(axis=1), 0.1**3, rtol=1e-12)
    np.testing.assert_allclose(vol[:, 2], 0.1**3 / 3, rtol=1e-12)
    # a rigid translation: F = I and no velocity gradient (H = 0)
    assert np.abs(cloud.states[:, :9]).max() < 1e-14


def test_cell_filters_density_void_and_dencut():
    g = slab_grid(shape=(3, 1, 1), phi=0.0)
    density = np.array([2.703, 2.703 * 0.005, 2.703]).reshape(3, 1, 1)
    phi = np.array([0.0, 0.0, 0.9995]).reshape(3, 1, 1)
    g2 = HydroGrid(g.x, g.y, g.z, density=density, void_fraction=phi, mass=g.mass, pressure=g.pressure,
                   temperature=g.temperature, specific_energy=g.specific_energy, sound_speed=g.sound_speed,
                   velocity=g.velocity)
    assert seed_cells(g2, AL.rho_ref).ravel().tolist() == [True, False, False]
    assert not seed_cells(g2, AL.rho_ref, SeedFilter(dencut=1.5)).any()
    # a staggered (CTH) grid keeps the listing's interior cells 2..n-1 only
    stag = slab_grid(shape=(4, 4, 4), staggered=True)
    assert seed_cells(stag, AL.rho_ref).sum() == 2 * 2 * 2


def test_arrival_times_are_ballistic_and_one_sided():
    g = slab_grid(velocity=(0.0, 0.5, 0.0))
    cloud = seed_particles(g, AL)
    t = arrival_times(cloud, 0.0)
    np.testing.assert_allclose(t, -cloud.centroid[:, 1] / 0.5, rtol=1e-13)
    away = seed_particles(slab_grid(velocity=(0.0, -0.5, 0.0)), AL)
    assert np.all(np.isinf(arrival_times(away, 0.0)))
    # the listing's |.| counts particles flying away as arriving (an erratum, legacy only)
    np.testing.assert_allclose(arrival_times(away, 0.0, legacy_abs_arrival=True), t, rtol=1e-13)


def wall_over(x=(0.0, 0.4), z=(0.0, 0.4), n=(5, 2, 5)):
    return WallGrid.uniform(x, (0.0, 0.3), z, n)


def test_face_element_lookup_and_upper_edges():
    w = wall_over()
    pts = np.array([[0.0, 0, 0.0], [0.09, 0, 0.39], [0.4, 0, 0.4], [0.41, 0, 0.2], [-1e-9, 0, 0.2]])
    assert face_element(w, pts).tolist() == [0, 12, 15, -1, -1]


def test_deposited_impulse_equals_momentum_of_points_on_the_wall():
    rng = np.random.default_rng(3)
    n = 200
    points = rng.uniform(-0.1, 0.5, size=(n, 5, 3))
    p = rng.normal(size=(n, 3))
    dep, on = deposit(points, p, rng.uniform(1, 2, n), wall_over())
    expected = (p[:, None, :] / POINTS_PER_PARTICLE * on[..., None]).sum(axis=(0, 1))
    np.testing.assert_allclose(dep.impulse.sum(axis=0), expected, rtol=1e-12)
    assert 0 < on.sum() < on.size
    # DCPOST: per-element sums keep the total; the areal density integrates to Σ|p_e|
    w = wall_over()
    imp = element_impulse(dep, w)
    np.testing.assert_allclose(imp.reshape(-1, 3).sum(axis=0), expected, rtol=1e-12)
    np.testing.assert_allclose((areal_density(imp, w) * face_areas(w)).sum(),
                               np.linalg.norm(imp, axis=-1).sum(), rtol=1e-12)
    cards = element_records(imp, factor=0.5)
    np.testing.assert_allclose(cards.impulse.sum(axis=0), 0.5 * expected, rtol=1e-12)
    assert np.all(cards.time == 0.0)


@pytest.mark.parametrize("target", [
    dict(x=(0.0, 0.4), z=(0.0, 0.4), n=(3, 2, 9)),     # coarser in x, finer in z, same extent
    dict(x=(-1.0, 1.0), z=(-0.5, 2.0), n=(7, 2, 4)),   # covering, misaligned
])
def test_remap_is_conservative_when_the_target_covers_the_source(target):
    src = wall_over()
    imp = np.random.default_rng(0).normal(size=src.shape[::2] + (3,))
    moved = remap_impulse(imp, src, wall_over(**target))
    np.testing.assert_allclose(moved.reshape(-1, 3).sum(axis=0), imp.reshape(-1, 3).sum(axis=0), rtol=1e-12)


def test_uniform_slab_toward_the_wall_deposits_a_uniform_areal_density():
    # 16 x 16 cells of 0.1 cm under 0.4 cm wall elements.  An element whose vertex columns are all
    # interior nodes of the slab collects the same momentum; those holding the slab's outer node
    # columns collect less (fewer tetrahedra meet at a boundary node).
    g = slab_grid(shape=(16, 2, 16), velocity=(0.0, 0.4, 0.0), origin=(0.0, -0.6, 0.0))
    wall = WallGrid.uniform((-0.4, 2.0), (0.0, 0.3), (-0.4, 2.0), (7, 2, 7))
    r = run_debris(g, wall, AL, window=ArrivalWindow(0.0, 10.0))
    s = r.summary()
    assert s["n_arrived"] == s["n_particles"] == 5 * 16 * 2 * 16
    # everything lands on the wall: deposited = arrived momentum (1e-12), here the slab's momentum
    np.testing.assert_allclose(s["momentum_deposited"], s["momentum_arrived"], rtol=1e-12, atol=1e-16)
    np.testing.assert_allclose(s["momentum_in"], g.total_momentum(), rtol=1e-12)
    interior = r.areal[2:4, 2:4]
    np.testing.assert_allclose(interior, interior[0, 0], rtol=1e-12)
    np.testing.assert_allclose(interior[0, 0], g.total_momentum()[1] / (1.6 * 1.6), rtol=1e-12)
    np.testing.assert_allclose((r.areal * face_areas(wall)).sum(), g.total_momentum()[1], rtol=1e-12)
    # below the footprint nothing lands (the slab's upper edge nodes belong to the next element up)
    assert r.areal[0].sum() == 0 and r.areal[:, 0].sum() == 0


def test_slab_moving_away_deposits_nothing():
    g = slab_grid(velocity=(0.0, -0.4, 0.1))
    r = run_debris(g, wall_over(), AL)
    s = r.summary()
    assert s["n_propagated"] == 0 and s["n_not_reaching_wall"] == s["n_particles"]
    assert s["momentum_deposited"] == [0.0, 0.0, 0.0] and not r.areal.any()


def test_failed_particles_are_counted_not_deposited():
    g = slab_grid(shape=(2, 1, 2), velocity=(0.0, 0.5, 0.0))
    r = run_debris(g, wall_over(), AL, integrator=__import__("impactdyn.debris", fromlist=["x"]).IntegratorOptions(
        max_steps=3))
    s = r.summary()
    assert s["integrator"]["n_failed"] == s["n_propagated"] > 0
    assert s["integrator"]["failures"] == {"STEP_BUDGET": s["n_propagated"]}
    assert s["n_arrived"] == 0 and s["momentum_deposited"] == [0.0, 0.0, 0.0]
    np.testing.assert_allclose(s["momentum_failed"], s["momentum_in"], rtol=1e-13)


def test_chunks_give_bit_identical_states():
    g = slab_grid(shape=(3, 2, 3), velocity=(0.02, 0.5, -0.03))
    # a velocity gradient, so that the particles vibrate and the integration has work to do
    v = np.array(g.velocity)
    v[..., 0] += 0.05 * np.linspace(-1, 1, 3)[:, None, None]
    g = HydroGrid(g.x, g.y, g.z, g.density, g.void_fraction, g.mass, g.pressure, g.temperature,
                  g.specific_energy, g.sound_speed, v)
    cloud = seed_particles(g, AL)
    t = np.linspace(0.5, 2.0, len(cloud))
    whole, s1 = propagate_chunked(cloud, t, AL)
    pieces, s2 = propagate_chunked(cloud, t, AL, compute=ComputeOptions(chunk_size=7))
    assert np.array_equal(whole, pieces) and np.array_equal(s1.steps, s2.steps)
    assert np.abs(whole[:, 9:18] - np.eye(3).ravel()).max() > 1e-6  # F moved


def test_wall_material_of_the_report():
    # the wall the decks describe (App. D); E and nu follow from G and K
    assert AL_6061_T6_MAT13.youngs_modulus == pytest.approx(0.734, abs=1e-3)


@pytest.mark.parametrize("transfer", ["arrival", "cratering"])
def test_the_clouds_momentum_is_accounted_for_in_full(transfer):
    """momentum in = arrived + failed + outside the window + never reaching the wall plane, and
    arrived + added at the wall = deposited + off the face grid, to round-off, on a cloud that takes
    every path; the crater ejecta add (β − 1) times the normal momentum that lands on the face grid."""
    shape = (8, 2, 8)
    g = slab_grid(shape=shape, origin=(0.0, -0.6, 0.0))
    v = np.zeros(shape + (3,))
    v[:2, ..., 1] = -0.3                     # away from the wall: never reaches its plane
    v[2:5, ..., 1] = 0.01                    # arrives after ~60 µs, outside the 10-µs window
    v[5:, ..., 1] = 0.4                      # arrives in the window, partly beyond the face grid's edge
    v[5:, :, 6:, 2] = 0.2
    g = HydroGrid(g.x, g.y, g.z, density=g.density, void_fraction=g.void_fraction, mass=g.mass,
                  pressure=g.pressure, temperature=g.temperature, specific_energy=g.specific_energy,
                  sound_speed=g.sound_speed, velocity=v)
    wall = WallGrid.uniform((0.0, 0.8), (0.0, 0.3), (0.0, 0.8), (5, 2, 5))
    result = run_debris(g, wall, AL, window=ArrivalWindow(0.0, 10.0),
                        deposition=DepositionOptions(momentum_transfer=transfer))
    s = result.summary()
    parts = {k: np.array(s[f"momentum_{k}"]) for k in ("arrived", "failed", "outside_window", "not_reaching",
                                                       "deposited", "off_wall", "added_at_wall")}
    assert all(np.abs(parts[k]).sum() > 0 for k in ("arrived", "outside_window", "not_reaching", "off_wall"))
    assert s["mass_outside_window_g"] > 0 and s["mass_not_reaching_g"] > 0
    np.testing.assert_allclose(parts["arrived"] + parts["failed"] + parts["outside_window"] + parts["not_reaching"],
                               s["momentum_in"], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(parts["deposited"] + parts["off_wall"], parts["arrived"] + parts["added_at_wall"],
                               rtol=1e-12, atol=1e-15)
    moving = result.cloud.subset(result.propagated)
    on_share = result.on_wall.mean(axis=1)
    beta = cratering_factor(10.0 * moving.momentum[:, 1] / moving.mass) if transfer == "cratering" else 1.0
    expected = ((beta - 1.0) * moving.momentum[:, 1] * on_share).sum()
    assert parts["added_at_wall"][1] == pytest.approx(expected, rel=1e-12, abs=1e-15)
    assert (expected > 0) == (transfer == "cratering")
    np.testing.assert_array_equal(parts["added_at_wall"][[0, 2]], 0.0)


def test_cratering_scales_the_normal_momentum_by_beta_of_the_normal_speed():
    speeds, betas = CRATERING_MOMENTUM
    np.testing.assert_allclose(cratering_factor(np.array(speeds)), betas, rtol=0, atol=0)
    mid = 0.5 * (speeds[2] + speeds[3])
    assert cratering_factor(mid) == pytest.approx(0.5 * (betas[2] + betas[3]), rel=1e-14)
    assert cratering_factor(0.5 * speeds[0]) == betas[0] and cratering_factor(2.0 * speeds[-1]) == betas[-1]
    assert cratering_factor(-3.0) == 1.0 and cratering_factor(0.0) == 1.0      # not moving toward the wall
    assert all(b > 1.0 for b in betas)
    mass = np.array([2.0, 0.5])
    p = np.array([[0.3, 1.4, -0.2], [0.1, -0.05, 0.0]])        # 7 km/s toward the wall; 1 km/s away from it
    out = cratering_momentum(p, mass)
    np.testing.assert_array_equal(out[:, [0, 2]], p[:, [0, 2]])
    assert out[0, 1] == pytest.approx(1.4 * float(cratering_factor(7.0)), rel=1e-14)
    assert out[1, 1] == p[1, 1]


def test_the_points_deposited_again_on_the_case_grid_are_its_records_and_conserved_on_a_finer_one():
    g = slab_grid(shape=(6, 2, 6), velocity=(0.05, 0.4, 0.02), origin=(0.0, -0.6, 0.0))
    wall = WallGrid.uniform((-0.2, 1.0), (0.0, 0.3), (-0.2, 1.0), (5, 2, 5))
    r = run_debris(g, wall, AL, window=ArrivalWindow(0.0, 10.0))
    again = r.deposition_on(wall)
    for name in ("element", "time", "impulse"):
        np.testing.assert_array_equal(getattr(again, name), getattr(r.deposition, name))
    fine = WallGrid.uniform((-0.2, 1.0), (0.0, 0.3), (-0.2, 1.0), (25, 2, 25))
    np.testing.assert_allclose(r.deposition_on(fine).impulse.sum(axis=0), r.summary()["momentum_deposited"],
                               rtol=1e-12)
