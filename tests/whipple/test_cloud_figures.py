"""Debris-cloud figures from SPH particles: known clouds give known velocities and angles (issue 4)."""

import numpy as np
import pytest

from impactdyn.shield import Particles
from impactdyn.whipple import cloud_figures


def particles(position, velocity, mass=None):
    n = len(position)
    return Particles(position=position, velocity=velocity, mass=np.ones(n) if mass is None else mass,
                     density=np.full(n, 2.7), pressure=np.zeros(n), specific_energy=np.zeros(n),
                     deviatoric_stress=np.zeros((n, 6)), plastic_strain=np.zeros(n), failed=np.zeros(n, bool),
                     smoothing_length=np.full(n, 0.03), sound_speed=np.full(n, 0.5), temperature=np.full(n, 300.0),
                     material=np.zeros(n, int), materials=("al6061-t6",), time=4.0)


def test_a_translating_cloud_has_its_own_velocity_and_no_spread():
    rng = np.random.default_rng(3)
    x = rng.uniform([0, 0.2, -0.5], [0.5, 1.5, 0.5], (400, 3))
    v = np.tile([0.0, 0.6, 0.28], (400, 1))
    f = cloud_figures(particles(x, v), bumper_back_y=0.127)
    speed = 10 * np.hypot(0.6, 0.28)
    assert f["centre_of_mass_speed_km_s"] == pytest.approx(speed, rel=1e-12)
    assert f["leading_edge_velocity_km_s"] == pytest.approx(speed, rel=1e-12)
    assert f["axis_angle_from_normal_deg"] == pytest.approx(np.degrees(np.arctan2(0.28, 0.6)), rel=1e-12)
    assert f["cone_half_angle_deg"] == pytest.approx(0.0, abs=1e-5)
    assert f["axial_momentum_g_cm_us"] == pytest.approx(400 * 0.6)


def test_a_homologous_fan_has_the_fastest_particles_in_front_and_its_cone_angle():
    """Particles leave the origin in the y–z plane at angles uniform in ±α: x = v t."""
    alpha = np.radians(30.0)
    phi = np.linspace(-alpha, alpha, 2001)
    speeds = np.linspace(0.3, 0.7, 11)
    a, s = np.meshgrid(phi, speeds, indexing="ij")
    v = np.stack([np.full(a.size, 1e-9), (s * np.cos(a)).ravel(), (s * np.sin(a)).ravel()], axis=-1)
    f = cloud_figures(particles(4.0 * v, v), bumper_back_y=0.127)
    assert f["axis_angle_from_normal_deg"] == pytest.approx(0.0, abs=1e-9)
    # 95 % of the momentum (uniform in angle) lies within 0.95 α
    assert f["cone_half_angle_deg"] == pytest.approx(0.95 * 30.0, abs=0.05)
    # the foremost 1 % of the mass: the fastest shell, near the axis
    assert 6.9 < f["leading_edge_velocity_km_s"] <= 7.0


def test_material_in_front_of_the_bumper_or_moving_back_is_not_debris():
    x = np.array([[0.1, 0.5, 0.0], [0.1, 0.05, 0.0], [0.1, 0.6, 0.0]])
    v = np.array([[0.0, 0.5, 0.0], [0.0, 0.5, 0.0], [0.0, -0.2, 0.0]])
    f = cloud_figures(particles(x, v, np.array([1.0, 5.0, 7.0])), bumper_back_y=0.127)
    assert f["n_debris_particles"] == 1 and f["debris_mass_g"] == 1.0
    assert cloud_figures(particles(x[1:], v[1:]), bumper_back_y=0.127) == {"n_debris_particles": 0,
                                                                           "debris_mass_g": 0.0}
