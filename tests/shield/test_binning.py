"""Binning SPH particles onto the hand-off HydroGrid: kernel (default) and cloud-in-cell assignment.

Parametrised over every binning method of :data:`impactdyn.shield.BinningMethod`."""

import tomllib
import typing
from pathlib import Path

import numpy as np
import pytest
import tomli_w

from impactdyn import shield
from impactdyn._errors import InputError
from impactdyn.whipple import load_whipple_case
from impactdyn.whipple._pipeline import settings

CELL = 0.1
BOX = ((0.0, 1.0), (0.0, 1.0), (0.0, 1.0))
METHODS = typing.get_args(shield.BinningMethod)
EXAMPLES = Path(__file__).parents[2] / "examples" / "whipple"


def particles(position, h, mass=None, velocity=None, density=None, seed=0):
    """Particles at ``position`` (N, 3) with smoothing lengths ``h`` and random other fields."""
    position = np.atleast_2d(np.asarray(position, dtype=float))
    n = len(position)
    rng = np.random.default_rng(seed)
    return shield.Particles(
        position=position, velocity=rng.normal(size=(n, 3)) if velocity is None else velocity,
        mass=rng.uniform(0.5, 2.0, n) if mass is None else mass,
        density=rng.uniform(2.0, 3.0, n) if density is None else density, pressure=rng.normal(size=n),
        specific_energy=rng.uniform(0, 1, n), deviatoric_stress=np.zeros((n, 6)), plastic_strain=np.zeros(n),
        failed=np.zeros(n, dtype=bool), smoothing_length=np.broadcast_to(h, (n,)), sound_speed=rng.uniform(0, 1, n),
        temperature=rng.uniform(300, 900, n), material=np.zeros(n, dtype=int), materials=("al6061-t6",), time=2.0)


def single(position, h, region=BOX, **kw):
    """Cell masses of one unit-mass particle: its weights w_pc."""
    return shield.bin_to_hydrogrid(particles(position, h, mass=np.ones(1)), CELL, region=region, **kw).mass


@pytest.mark.parametrize("method", METHODS)
def test_every_particle_deposits_its_mass_and_momentum(method):
    """Weights sum to 1 per particle, also where the kernel reaches past the symmetry plane and the other faces."""
    rng = np.random.default_rng(1)
    n = 400
    p = particles(rng.uniform(0, 1, (n, 3)), rng.uniform(0.002, 0.3, n))
    grid = shield.bin_to_hydrogrid(p, CELL, region=BOX, method=method)
    assert grid.total_mass() == pytest.approx(p.total_mass(), rel=1e-14)
    np.testing.assert_allclose(grid.total_momentum(), p.total_momentum(), rtol=0,
                               atol=1e-14 * np.abs(p.mass[:, None] * p.velocity).sum())
    for x, h in (([0.01, 0.5, 0.5], 0.25), ([0.97, 0.02, 0.99], 0.15), ([0.5, 0.5, 0.5], 0.004)):
        assert single(x, h, method=method).sum() == pytest.approx(1.0, abs=1e-13)  # round-off of ~10⁴ terms


@pytest.mark.parametrize("method", METHODS)
def test_weights_across_the_symmetry_plane_are_the_image_particles(method):
    """Half grid from x = 0 with the particle = the full grid with the particle and its image (−x, y, z)."""
    x, h = np.array([0.07, 0.43, 0.61]), 0.17
    half = single(x, h, method=method)
    image = x * [-1, 1, 1]
    full = shield.bin_to_hydrogrid(particles([x, image], h, mass=np.ones(2)), CELL,
                                   region=((-1.0, 1.0),) + BOX[1:], method=method).mass
    np.testing.assert_allclose(half, full[10:], rtol=1e-12, atol=1e-15)
    assert np.count_nonzero(half[0]) > 0 and half[1:].sum() > 0


@pytest.mark.parametrize("method", METHODS)
def test_weights_beyond_other_faces_are_folded_onto_the_boundary_cells(method):
    x, h = [0.46, 0.98, 0.52], 0.12
    small = single(x, h, method=method)
    large = single(x, h, region=(BOX[0], (0.0, 1.5), BOX[2]), method=method)
    assert large[:, 10:].sum() > 0.05  # the kernel does reach past y = 1
    np.testing.assert_allclose(small[:, :-1], large[:, :9], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(small[:, -1], large[:, 9:].sum(axis=1), rtol=1e-12, atol=1e-15)
    # without the symmetry plane the lower x face folds as well
    near = [0.03, 0.5, 0.5]
    folded = single(near, 0.2, mirror_x0=False, method=method)
    wide = single(np.add(near, [1, 0, 0]), 0.2, region=((0.0, 2.0),) + BOX[1:], method=method)
    np.testing.assert_allclose(folded[0], wide[:11].sum(axis=0), rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(folded[1:], wide[11:20], rtol=1e-12, atol=1e-15)


def test_a_particle_much_smaller_than_a_cell_stays_in_its_own_cell():
    w = single([0.33, 0.56, 0.45], 0.001)
    assert w[3, 5, 4] == 1.0 and np.count_nonzero(w) == 1
    # next to a face the part of its kernel across the face goes to the neighbour
    w = single([0.33, 0.598, 0.45], 0.002)
    assert np.count_nonzero(w) == 2 and 0.5 < w[3, 5, 4] < 1.0 and w[3, 6, 4] == pytest.approx(1.0 - w[3, 5, 4])
    # cloud-in-cell spreads the same particle over eight cells, whatever its h
    assert np.count_nonzero(single([0.33, 0.56, 0.47], 0.001, method="cic")) == 8


def test_kernel_spreads_a_particle_over_its_support():
    """Weights fall off with distance from the particle and vanish beyond 2h (plus the cell's half diagonal)."""
    x, h = np.array([0.52, 0.47, 0.5]), 0.2
    w = single(x, h)
    centres = (np.indices(w.shape).transpose(1, 2, 3, 0) + 0.5) * CELL
    r = np.linalg.norm(centres - x, axis=-1)
    assert np.all(w[r > 2 * h + np.sqrt(3) / 2 * CELL] == 0) and np.count_nonzero(w) > 100
    order = np.argsort(r.ravel())
    assert w.ravel()[order[0]] == w.max() and w.ravel()[order[0]] > 2 * w.ravel()[order[30]] > 0


@pytest.mark.parametrize("method, ratio, tolerance", [
    *((m, 2.0, 1e-12) for m in METHODS),  # cells of 2 × 2 × 2 particles: uniform by symmetry
    ("kernel", 1.25, 2e-3),  # the Whipple cases' cell/spacing (0.03175/0.0254)
])
def test_a_uniform_lattice_gives_a_uniform_interior(method, ratio, tolerance):
    dx, n, rho = 0.01, 24, 2.7
    a = dx * (np.arange(n) + 0.5)
    pos = np.stack(np.meshgrid(a, a, a, indexing="ij"), axis=-1).reshape(-1, 3)
    v = np.array([0.1, 0.6, -0.2])
    p = particles(pos, 1.3 * dx, mass=np.full(len(pos), rho * dx**3), velocity=np.tile(v, (len(pos), 1)),
                  density=np.full(len(pos), rho))
    cell = ratio * dx
    grid = shield.bin_to_hydrogrid(p, cell, region=((0, n * dx),) * 3, method=method)
    k = int(np.ceil(2 * 1.3 * dx / cell)) + 1  # cells that the lattice's edges (other than x = 0) reach
    inner = (slice(0, -k),) + (slice(k, -k),) * 2
    np.testing.assert_allclose(grid.mass[inner] / cell**3, rho, rtol=tolerance)
    np.testing.assert_allclose(grid.density[inner], rho, rtol=tolerance)
    assert grid.void_fraction[inner].max() <= tolerance
    np.testing.assert_allclose(grid.velocity[grid.mass > 0], np.broadcast_to(v, (np.count_nonzero(grid.mass), 3)),
                               rtol=1e-13)


def test_cloud_in_cell_is_not_uniform_on_a_lattice_of_another_pitch():
    """Why kernel binning: CIC at cell = 1.25 × spacing leaves ±10 % density bands in a uniform block."""
    dx, n = 0.01, 24
    a = dx * (np.arange(n) + 0.5)
    pos = np.stack(np.meshgrid(a, a, a, indexing="ij"), axis=-1).reshape(-1, 3)
    p = particles(pos, 1.3 * dx, mass=np.full(len(pos), 2.7 * dx**3))
    mass = shield.bin_to_hydrogrid(p, 1.25 * dx, region=((0, n * dx),) * 3, method="cic").mass[:-3, 3:-3, 3:-3]
    assert mass.max() / mass.min() > 1.2


@pytest.mark.parametrize("method", METHODS)
def test_cell_fields_are_mass_weighted_means_of_the_particles(method):
    """The grid is linear in the particles: cell sums are Σ_p of single-particle grids' sums."""
    rng = np.random.default_rng(5)
    p = particles(rng.uniform(0.3, 0.7, (4, 3)), rng.uniform(0.05, 0.15, 4), seed=5)
    grid = shield.bin_to_hydrogrid(p, CELL, region=BOX, method=method)
    w = np.stack([single(x, h, method=method) for x, h in zip(p.position, p.smoothing_length)])  # (4, nx, ny, nz)
    wm = w * p.mass[:, None, None, None]
    np.testing.assert_allclose(grid.mass, wm.sum(axis=0), rtol=1e-12, atol=1e-15)
    has = grid.mass > 0
    assert np.all(grid.void_fraction[~has] == 1) and np.all(grid.density[~has] == 0)
    assert np.all(grid.velocity[~has] == 0) and np.all(grid.pressure[~has] == 0)
    for field, q in (("pressure", p.pressure), ("specific_energy", p.specific_energy),
                     ("sound_speed", p.sound_speed), ("temperature", p.temperature)):
        expected = np.einsum("p...,p->...", wm, q)[has] / grid.mass[has]
        np.testing.assert_allclose(getattr(grid, field)[has], expected, rtol=1e-12, err_msg=field)
    expected = np.einsum("p...,pd->...d", wm, p.velocity)[has] / grid.mass[has][:, None]
    np.testing.assert_allclose(grid.velocity[has], expected, rtol=1e-12, atol=1e-14)
    # solid volume Σ w m/ρ: φ = 1 − V_s/V, ρ = M/V_s, and the bulk density gives back the cell mass
    solid = np.einsum("p...,p->...", wm, 1.0 / p.density)
    np.testing.assert_allclose(grid.void_fraction, np.clip(1 - solid / CELL**3, 0, 1), rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(grid.density[has], grid.mass[has] / np.minimum(solid[has], CELL**3), rtol=1e-12)
    np.testing.assert_allclose((1 - grid.void_fraction) * grid.density * CELL**3, grid.mass, rtol=1e-12, atol=1e-15)


def test_a_compressed_clump_makes_full_cells():
    """V_s > V_cell: φ = 0 and ρ = M/V_cell."""
    p = particles([[0.55, 0.55, 0.55]] * 3, 0.01, mass=np.full(3, 0.003), density=np.full(3, 2.7))
    grid = shield.bin_to_hydrogrid(p, CELL, region=BOX)
    assert grid.void_fraction[5, 5, 5] == 0 and grid.density[5, 5, 5] == pytest.approx(0.009 / CELL**3)


def test_particles_outside_the_region_are_left_out_and_bad_input_fails():
    p = particles([[0.5, 0.5, 0.5], [1.5, 0.5, 0.5]], 0.1, mass=np.array([1.0, 4.0]))
    assert shield.bin_to_hydrogrid(p, CELL, region=BOX).total_mass() == pytest.approx(1.0, rel=1e-14)
    with pytest.raises(InputError, match="method"):
        shield.bin_to_hydrogrid(p, CELL, method="ngp")
    with pytest.raises(InputError, match="smoothing lengths"):
        shield.bin_to_hydrogrid(particles([0.5, 0.5, 0.5], 0.0), CELL, region=BOX)


def test_whipple_case_chooses_the_method_and_records_it(tmp_path):
    data = tomllib.loads((EXAMPLES / "table2_7a.toml").read_text())

    def case(name, **binning):
        path = tmp_path / name
        path.write_text(tomli_w.dumps(data | {"binning": data["binning"] | binning}))
        return load_whipple_case(path)

    assert case("default.toml").binning.method == "kernel"
    chosen = {m: case(f"{m}.toml", method=m) for m in METHODS}
    for m, c in chosen.items():
        assert c.binning.method == m and settings(c, "binning")["binning"]["method"] == m
    # the binning stage's recorded settings differ, so a restart past binning detects the change
    assert len({str(settings(c, "binning")) for c in chosen.values()}) == len(METHODS)
    with pytest.raises(InputError, match="binning.method"):
        case("ngp.toml", method="ngp")
