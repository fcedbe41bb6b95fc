"""Fragments of the debris cloud: friends-of-friends over the intact particles, their mass, motion and shape."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from impactdyn._errors import InputError
from impactdyn.shield._fragments import (FRAGMENT_COLUMNS, Fragments, cumulative_mass, cumulative_number, find_fragments,
                                         fragment_rows, join_fragments, origin_masses, plot_fragment_masses)

D = 0.1  # lattice spacing, cm
B = 1.5 * D  # link length


def lattice(nx, ny, nz, origin=(0.0, 0.0, 0.0), spacing=D):
    """Points of an nx × ny × nz lattice from ``origin``, (n, 3)."""
    axes = [origin[a] + spacing * np.arange(k) for a, k in enumerate((nx, ny, nz))]
    return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)


def fragments(position, velocity=None, mass=None, intact=None, b=B, spacing=D):
    """find_fragments with unit defaults: at rest, mass 1, solid volume Δ³ (the lattice cell), all intact."""
    n = len(position)
    return find_fragments(position, np.zeros((n, 3)) if velocity is None else velocity,
                          np.ones(n) if mass is None else mass, np.full(n, spacing**3),
                          np.ones(n, dtype=bool) if intact is None else intact, link_length_cm=b)


@pytest.mark.parametrize("gap, expected", [(2.0 * D, 2), (1.2 * D, 1)])
def test_two_cubes_are_two_fragments_unless_they_touch(gap, expected):
    """Two 4³ cubes whose facing planes are ``gap`` apart: 2 fragments if gap > b, else 1."""
    a = lattice(4, 4, 4)
    b = lattice(4, 4, 4, origin=(3 * D + gap, 0.0, 0.0))
    position = np.concatenate([a, b])
    velocity = np.concatenate([np.tile([0.1, 0.0, 0.0], (64, 1)), np.tile([0.0, -0.2, 0.3], (64, 1))])
    mass = np.concatenate([np.full(64, 2.0), np.full(64, 1.0)])  # the first cube the heavier
    f = fragments(position, velocity, mass)
    assert len(f) == expected
    if expected == 2:
        np.testing.assert_array_equal(f.mass, [128.0, 64.0])
        np.testing.assert_allclose(f.position, [[1.5 * D] * 3, [4.5 * D + gap, 1.5 * D, 1.5 * D]], rtol=1e-14)
        np.testing.assert_allclose(f.velocity, [[0.1, 0.0, 0.0], [0.0, -0.2, 0.3]], rtol=1e-14, atol=1e-16)
        np.testing.assert_allclose(f.spin, 0.0, atol=1e-14)
        np.testing.assert_array_equal(f.count, [64, 64])
        np.testing.assert_array_equal(f.indices(0), np.arange(64))
        np.testing.assert_array_equal(f.indices(1), np.arange(64, 128))
    else:
        assert f.mass[0] == 192.0
        np.testing.assert_allclose(f.velocity[0], (128 * np.array([0.1, 0, 0]) + 64 * np.array([0, -0.2, 0.3])) / 192)


def test_a_damaged_slab_splits_a_bar_and_mass_is_conserved():
    """A 20 × 3 × 3 bar with the slab x = 10 Δ damaged: two fragments of 10 and 9 layers; the slab is spray."""
    position = lattice(20, 3, 3)
    rng = np.random.default_rng(3)
    mass = rng.uniform(0.5, 1.5, len(position))
    layer = np.rint(position[:, 0] / D).astype(int)
    intact = layer != 10
    f = fragments(position, mass=mass, intact=intact)
    assert len(f) == 2
    assert sorted(f.count) == [81, 90]
    for i in range(2):  # each fragment lies on one side of the slab
        side = layer[f.indices(i)]
        assert np.all(side < 10) or np.all(side > 10)
    assert f.total_mass() + mass[~intact].sum() == pytest.approx(mass.sum(), rel=1e-14)
    assert f.total_mass() < mass.sum()


def test_a_rigid_rotation_gives_its_spin():
    """v = v_c + ω × (r − r_c) for an irregular body (random points, unequal masses, no symmetry): spin = ω."""
    rng = np.random.default_rng(7)
    position = lattice(6, 4, 3) + rng.uniform(-0.2 * D, 0.2 * D, (72, 3))
    position = position[rng.random(72) < 0.85]  # holes: no symmetry left
    position[:5] += [0.0, 0.0, 0.3 * D]
    mass = rng.uniform(0.5, 2.0, len(position))
    omega = np.array([0.013, -0.041, 0.027])  # rad/µs
    v_c = np.array([0.6, -0.1, 0.25])
    r_c = mass @ position / mass.sum()
    velocity = v_c + np.cross(omega, position - r_c)
    f = fragments(position, velocity, mass, b=2.0 * D)
    assert len(f) == 1
    np.testing.assert_allclose(f.velocity[0], v_c, rtol=1e-13)
    np.testing.assert_allclose(f.spin[0], omega, rtol=1e-11)


def test_a_pair_spins_about_its_perpendicular_and_a_single_particle_not_at_all():
    """Two particles: ω ⊥ the line comes back exactly, the part along it is not seen (0); one particle: ω = 0."""
    position = np.array([[0.0, 0.0, 0.0], [D, 0.0, 0.0]])
    omega = np.array([0.5, 0.02, -0.03])
    velocity = np.cross(omega, position - position.mean(axis=0))
    f = fragments(position, velocity)
    np.testing.assert_allclose(f.spin[0], [0.0, 0.02, -0.03], rtol=1e-12, atol=1e-15)
    one = fragments(position[:1], velocity[:1] + 1.0)
    np.testing.assert_array_equal(one.spin, 0.0)
    assert np.all(np.isfinite(one.axes_cm)) and one.axes_cm[0, 0] > 0


def test_a_long_rod_is_long_and_a_sphere_is_round():
    """Rod 40 × 2 × 2: a/c ≫ 1. Lattice ball of radius R: a ≈ b ≈ c ≈ R and diameter ≈ 2R."""
    rod = fragments(lattice(40, 2, 2))
    a, b, c = rod.axes_cm[0]
    assert a >= b >= c and a / c > 10
    radius = 12 * D
    cube = lattice(25, 25, 25, origin=(-radius,) * 3)
    ball = fragments(cube[np.linalg.norm(cube, axis=1) <= radius])
    assert len(ball) == 1
    np.testing.assert_allclose(ball.axes_cm[0], radius, rtol=0.02)
    assert ball.axes_cm[0, 2] / ball.axes_cm[0, 0] > 0.999
    assert ball.diameter_cm[0] == pytest.approx(2 * radius, rel=0.01)


def test_the_equivalent_ellipsoid_of_a_box_has_the_box_inertia():
    """A lattice box of n_x × n_y × n_z cells Δ³: M/5 (b² + c²) = M/12 (L_y² + L_z²), … to 0.5 %.

    The particles' own a²/5 per axis stands for the cell's Δ²/12 (0.08 Δ²/L² off); points alone would be Δ²/L²
    off, 2.8 % on the short side L = 6 Δ.
    """
    shape = (16, 10, 6)
    f = fragments(lattice(*shape))
    mass = f.mass[0]
    length = np.array(shape) * D
    box = mass / 12 * (np.sum(length**2) - length**2)  # I_xx, I_yy, I_zz of the solid box
    semi = f.axes_cm[0]
    np.testing.assert_allclose(np.sort(mass / 5 * (np.sum(semi**2) - semi**2)), np.sort(box), rtol=5e-3)
    assert f.diameter_cm[0] == pytest.approx((6 / np.pi * np.prod(length)) ** (1 / 3), rel=1e-12)


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 200), st.floats(0.05, 0.4), st.floats(0.0, 1.0), st.integers(0, 2**32 - 1))
def test_fragments_and_spray_hold_all_the_mass_and_momentum(n, b, damaged, seed):
    """Σ M + Σ_damaged m = Σ m and Σ M v_c + Σ_damaged m v = Σ m v for random particles and intact masks."""
    rng = np.random.default_rng(seed)
    position = rng.uniform(0, 1, (n, 3))
    velocity = rng.normal(size=(n, 3))
    mass = rng.uniform(0.1, 3.0, n)
    intact = rng.random(n) >= damaged
    f = find_fragments(position, velocity, mass, mass / 2.7, intact, link_length_cm=b)
    assert f.total_mass() + mass[~intact].sum() == pytest.approx(mass.sum(), rel=1e-13)
    scale = mass @ np.abs(velocity)
    np.testing.assert_allclose(f.momentum() + mass[~intact] @ velocity[~intact], mass @ velocity,
                               rtol=0, atol=1e-13 * scale.max())
    assert np.all(np.isfinite(f.spin)) and np.all(np.isfinite(f.axes_cm))


def random_cloud(seed, n, intact_share):
    """n particles at random in the unit cube, masses in [0.5, 2], a random ``intact_share`` of them intact."""
    rng = np.random.default_rng(seed)
    return rng.uniform(0, 1, (n, 3)), rng.uniform(0.5, 2.0, n), rng.random(n) < intact_share


def test_sorted_by_mass_and_the_members_partition_the_intact_particles():
    """Masses descending, count = diff(ptr), every intact particle in exactly one fragment, no damaged one."""
    n = 3000
    position, mass, intact = random_cloud(11, n, 0.7)
    f = find_fragments(position, np.zeros((n, 3)), mass, mass / 2.7, intact, link_length_cm=0.06)
    assert len(f) > 10 and np.any(f.count == 1) and f.count[0] > 10  # singles, and a large cluster
    assert np.all(np.diff(f.mass) <= 0)
    np.testing.assert_array_equal(np.diff(f.ptr), f.count)
    np.testing.assert_array_equal(np.sort(f.members), np.flatnonzero(intact))
    for i in range(len(f)):
        assert mass[f.indices(i)].sum() == pytest.approx(f.mass[i], rel=1e-13)
    top = f.largest(3)
    assert len(top) == 3 and top.ptr[-1] == f.ptr[3]
    np.testing.assert_array_equal(top.members, f.members[:f.ptr[3]])


def test_joined_fragments_keep_their_members_and_origin_sorted_by_mass():
    """Two disjoint records (intact and failed particles of one set) joined: largest first, each fragment
    with its own particles and origin, and the CSR index whole."""
    n = 2000
    position, mass, intact = random_cloud(3, n, 0.5)
    a = find_fragments(position, np.zeros((n, 3)), mass, mass / 2.7, intact, link_length_cm=0.06)
    b = find_fragments(position, np.zeros((n, 3)), mass, mass / 2.7, ~intact, link_length_cm=0.06)
    b = Fragments(**{name: getattr(b, name) for name in ("mass", "position", "velocity", "spin", "diameter_cm",
                                                         "axes_cm", "count", "ptr", "members")},
                  from_failed=np.ones(len(b), dtype=bool))
    joined = join_fragments(a, b)
    assert len(joined) == len(a) + len(b) and np.all(np.diff(joined.mass) <= 0)
    np.testing.assert_array_equal(np.sort(joined.members), np.arange(n))
    np.testing.assert_array_equal(np.diff(joined.ptr), joined.count)
    for f in range(len(joined)):
        members = joined.indices(f)
        assert mass[members].sum() == pytest.approx(joined.mass[f], rel=1e-13)
        assert np.all(intact[members] != joined.from_failed[f])
    header, rows = fragment_rows(joined)
    assert rows[0][header.index("origin")] == ("failed" if joined.from_failed[0] else "intact")


def test_linked_means_closer_than_the_link_length():
    """Particles a distance b apart are not linked; b(1 + 10⁻⁹) apart with a longer b, they are."""
    position = np.array([[0.0, 0.0, 0.0], [0.25, 0.0, 0.0]])
    assert len(fragments(position, b=0.25)) == 2
    assert len(fragments(position, b=0.25 * (1 + 1e-9))) == 1


@pytest.mark.parametrize("argument, change", [
    ("link_length_cm", dict(link_length_cm=0.0)),
    ("link_length_cm", dict(link_length_cm=-1.0)),
    ("link_length_cm", dict(link_length_cm=float("inf"))),
    ("link_length_cm", dict(link_length_cm=float("nan"))),
    ("position", dict(position=np.zeros((4, 2)))),
    ("position", dict(position=np.full((4, 3), np.nan))),
    ("velocity", dict(velocity=np.zeros((3, 3)))),
    ("mass", dict(mass=np.ones(5))),
    ("mass", dict(mass=np.array([1.0, 0.0, 1.0, 1.0]))),
    ("mass", dict(mass=np.array([1.0, np.inf, 1.0, 1.0]))),
    ("volume", dict(volume=-np.ones(4))),
    ("volume", dict(volume=np.array([1.0, np.nan, 1.0, 1.0]))),
    ("intact", dict(intact=np.ones(4))),
    ("intact", dict(intact=np.ones(3, dtype=bool))),
])
def test_bad_input_names_the_argument(argument, change):
    args = dict(position=np.zeros((4, 3)), velocity=np.zeros((4, 3)), mass=np.ones(4), volume=np.ones(4),
                intact=np.ones(4, dtype=bool), link_length_cm=0.1)
    args.update(change)
    with pytest.raises(InputError, match=argument):
        find_fragments(**args)


def test_no_intact_particle_no_fragment():
    f = fragments(lattice(3, 3, 3), intact=np.zeros(27, dtype=bool))
    assert len(f) == 0 and f.total_mass() == 0.0 and f.ptr.tolist() == [0]
    assert cumulative_number(f)[1].size == 0 and fragment_rows(f)[1] == []


def test_cumulative_number_counts_fragments_at_least_that_heavy():
    """N(≥ m) non-decreasing as m falls, 1 at the largest, F at the smallest; equal masses share a count."""
    position = np.concatenate([lattice(4, 4, 4), lattice(3, 3, 3, origin=(1, 0, 0)), lattice(3, 3, 3, origin=(2, 0, 0)),
                               lattice(2, 1, 1, origin=(3, 0, 0)), [[4.0, 0, 0], [5.0, 0, 0]]])
    f = fragments(position)
    mass, count = cumulative_number(f)
    np.testing.assert_array_equal(mass, [64, 27, 27, 2, 1, 1])
    np.testing.assert_array_equal(count, [1, 3, 3, 4, 6, 6])
    assert np.all(np.diff(mass) <= 0) and np.all(np.diff(count) >= 0)


def test_rows_for_the_csv():
    """Header and one row per fragment (rank 1 the heaviest); n keeps the n heaviest."""
    position = np.concatenate([lattice(8, 2, 2), lattice(2, 2, 2, origin=(5, 0, 0))])
    velocity = np.tile([0.0, 0.3, 0.0], (len(position), 1))
    f = fragments(position, velocity)
    header, rows = fragment_rows(f)
    assert header == FRAGMENT_COLUMNS and all(len(r) == len(header) for r in rows) and len(rows) == 2
    row = dict(zip(header, rows[0]))
    assert row["rank"] == 1 and row["mass_g"] == 32.0 and row["count"] == 32
    assert row["vy_cm_per_us"] == pytest.approx(0.3)
    assert row["b_over_a"] < 0.5 and row["spin_rad_per_us"] == pytest.approx(0.0, abs=1e-14)
    assert fragment_rows(f, n=1)[1] == rows[:1]


@pytest.mark.parametrize("projectile", [None, 500.0])
def test_the_plot_is_written(tmp_path, projectile):
    rng = np.random.default_rng(5)
    n = 2000
    position = rng.uniform(0, 1, (n, 3))
    f = find_fragments(position, rng.normal(size=(n, 3)), np.ones(n), np.full(n, 1e-4), rng.random(n) < 0.8,
                       link_length_cm=0.07)
    path = plot_fragment_masses(tmp_path / "fragments.png", f, projectile_mass_g=projectile)
    assert path == tmp_path / "fragments.png" and path.stat().st_size > 1000
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    empty = plot_fragment_masses(tmp_path / "none.png", f.largest(0))
    assert empty.stat().st_size > 1000
    with pytest.raises(InputError, match="projectile_mass_g"):
        plot_fragment_masses(tmp_path / "bad.png", f, projectile_mass_g=0.0)


def test_the_plots_top_axis_labels_stand_apart_and_the_list_covers_no_data():
    """Fragments over less than two decades of mass (a lean shot's): the top axis's labels (m as % of the
    projectile) do not run into one another, and the list of the largest lies outside both panels."""
    from impactdyn.shield import fragment_mass_figure

    rng = np.random.default_rng(3)
    n = 300
    position = np.stack([np.arange(n, dtype=float), np.zeros(n), np.zeros(n)], axis=1)  # each its own fragment
    mass = 10.0 ** rng.uniform(-4.4, -2.75, n)   # the 7-km/s example's 4e-5 to 2e-3 g
    f = find_fragments(position, rng.normal(size=(n, 3)), mass, mass / 2.7, np.ones(n, bool), link_length_cm=0.1)
    assert len(f) == n and 1.0 < np.log10(f.mass.max() / f.mass.min()) < 2.0
    # the projectile as 140 times the largest, as in the example: one decade mark on the top axis
    fig = fragment_mass_figure(f, projectile_mass_g=140.0 * f.mass.max(), from_projectile_g=0.5 * f.mass)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    number, mass, listing = fig.axes[:3]
    for panel in (number, mass):
        [top] = panel.child_axes
        shown = [t for t in top.get_xticklabels() + top.get_xticklabels(minor=True)
                 if t.get_text() and panel.bbox.x0 <= t.get_window_extent(renderer).x0 <= panel.bbox.x1]
        boxes = sorted((t.get_window_extent(renderer) for t in shown), key=lambda b: b.x0)
        assert len(boxes) >= 2
        assert all(a.x1 < b.x0 for a, b in zip(boxes, boxes[1:])), [t.get_text() for t in shown]
        assert all("%" not in t.get_text() for t in shown)   # the unit is the axis label's
    [text] = listing.texts
    box = text.get_window_extent(renderer)
    assert not box.overlaps(number.bbox) and not box.overlaps(mass.bbox)
    assert text.get_text().startswith("the largest fragments:")
    import matplotlib.pyplot as plt
    plt.close(fig)


def test_the_record_is_read_only():
    f = fragments(lattice(2, 2, 2))
    assert isinstance(f, Fragments)
    with pytest.raises(ValueError):
        f.mass[0] = 1.0


def test_cumulative_mass_and_the_projectiles_part_of_each_fragment():
    """M(≥ m): the mass in fragments at least m heavy (equal masses share a sum), all or a part of each;
    the part of each fragment that was projectile material, its mirror images sharing their particle's."""
    position = np.concatenate([lattice(4, 4, 4), lattice(3, 3, 3, origin=(6, 0, 0)), lattice(3, 3, 3, origin=(10, 0, 0)),
                               [[14.0, 0, 0]]])
    f = fragments(position)
    mass, total = cumulative_mass(f)
    np.testing.assert_array_equal(mass, [64, 27, 27, 1])
    np.testing.assert_array_equal(total, [64, 118, 118, 119])
    projectile = position[:, 0] < 8                    # the 4-cube and the first 3-cube
    from_projectile = origin_masses(f, np.ones(len(position)), projectile)
    np.testing.assert_array_equal(from_projectile, [64, 27, 0, 0])
    np.testing.assert_array_equal(cumulative_mass(f, from_projectile)[1], [64, 91, 91, 91])
    # a half model's images (members N ... 2N - 1) count as their particles
    mirrored = Fragments(**{name: getattr(f, name) for name in ("mass", "position", "velocity", "spin",
                                                                 "diameter_cm", "axes_cm", "count", "ptr",
                                                                 "from_failed")},
                         members=f.members + len(position) * (np.arange(len(f.members)) % 2))
    np.testing.assert_array_equal(origin_masses(mirrored, np.ones(len(position)), projectile), from_projectile)
    header, rows = fragment_rows(f, from_projectile_g=from_projectile)
    assert [r[header.index("projectile_share")] for r in rows] == [1.0, 1.0, 0.0, 0.0]
    assert fragment_rows(f)[1][0][header.index("projectile_share")] == ""
