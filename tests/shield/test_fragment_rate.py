"""The stretching rate of failed material read across each fragment's own size
(:func:`impactdyn.shield.own_size_strain_rates`) and the Grady fragments it sizes."""

import math

import numpy as np
import pytest

from impactdyn import shield
from impactdyn.materials import AL_6061_T6

TOUGHNESS, RHO0, YOUNG = AL_6061_T6.fracture_toughness.K_Ic, AL_6061_T6.rho0, AL_6061_T6.young_modulus


def grady(rate):
    return shield.grady_fragment_size(TOUGHNESS, RHO0, YOUNG, rate)


def ball(spacing, radius=0.1):
    """The points of a cubic lattice of ``spacing`` within ``radius`` of the origin."""
    g = np.arange(-math.ceil(radius / spacing), math.ceil(radius / spacing) + 1) * spacing
    x = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1).reshape(-1, 3)
    return x[np.linalg.norm(x, axis=1) <= radius]


def test_a_uniformly_stretched_body_has_its_rate_everywhere():
    """v = a + G X with sym(G)'s largest principal value 0.6 µs⁻¹ (a spin part besides): every point's
    rate is 0.6 and its size Grady's at 0.6, to round-off, at any radius the fixed point settles on."""
    x = ball(0.01)
    strain = np.array([[0.6, 0.1, 0.0], [0.1, 0.2, 0.0], [0.0, 0.0, -0.3]])
    spin = np.array([[0.0, 0.5, 0.0], [-0.5, 0.0, 0.0], [0.0, 0.0, 0.0]])
    velocity = 0.7 + x @ (strain + spin).T
    rates, sizes, passes = shield.own_size_strain_rates(x, velocity, np.full(len(x), 0.01), grady)
    largest = np.linalg.eigvalsh(strain)[-1]
    np.testing.assert_allclose(rates, largest, rtol=1e-9)
    np.testing.assert_allclose(sizes, grady(largest), rtol=1e-9)
    assert passes <= 3


def test_the_rate_is_the_fragments_own_not_the_kernels():
    """A body stretching at 0.3 µs⁻¹ (fragments of 0.10 cm) whose particles jitter at the kernel's scale
    (a random velocity of 0.002 cm/µs each): the rate read across the fragment's own size is the body's
    within 10 % (the largest principal value of a noisy fit lies above the true one) and the same within
    5 % at two spacings, where one read over the kernel's 1.6 Δ grows as the spacing shrinks."""
    rng = np.random.default_rng(3)
    medians = {}
    for spacing in (0.01, 0.005):
        x = ball(spacing, 0.12)
        velocity = 0.3 * x + 0.002 * rng.standard_normal(x.shape)
        rates, sizes, _ = shield.own_size_strain_rates(x, velocity, np.full(len(x), spacing), grady)
        inner = np.linalg.norm(x, axis=1) < 0.05
        medians[spacing] = np.median(rates[inner])
        kernel, *_ = shield.own_size_strain_rates(x, velocity, np.full(len(x), spacing),
                                                  lambda r: np.zeros_like(r))     # held at the floor
        medians[("kernel", spacing)] = np.median(kernel[inner])
    assert grady(0.3) == pytest.approx(0.10, rel=0.05)
    for spacing in (0.01, 0.005):
        assert medians[spacing] == pytest.approx(0.3, rel=0.10)
    assert medians[0.005] == pytest.approx(medians[0.01], rel=0.05)
    excess = {spacing: medians[("kernel", spacing)] - 0.3 for spacing in (0.01, 0.005)}
    assert excess[0.005] > 1.5 * excess[0.01] > 1.5 * 0.05 * 0.3        # the jitter's gradient, ∝ 1/Δ


def test_a_compressed_region_breaks_into_no_fragment():
    x = ball(0.01, 0.05)
    rates, sizes, _ = shield.own_size_strain_rates(x, -0.2 * x, np.full(len(x), 0.01), grady)
    assert np.all(rates < 0) and np.all(np.isinf(sizes))


def _failed_block(spacing, rate_at_failure, velocity):
    """A cube of failed 6061-T6 particles with ``velocity(x)`` and the kernel's ``rate_at_failure``."""
    g = (np.arange(16) + 0.5) * spacing
    x = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1).reshape(-1, 3)
    n = len(x)
    return shield.Particles(
        position=x, velocity=velocity(x), mass=np.full(n, RHO0 * spacing ** 3), density=np.full(n, RHO0),
        pressure=np.zeros(n), specific_energy=np.zeros(n), deviatoric_stress=np.zeros((n, 6)),
        plastic_strain=np.zeros(n), failed=np.ones(n, bool), smoothing_length=np.full(n, 1.3 * spacing),
        sound_speed=np.full(n, 0.5), temperature=np.full(n, 300.0), material=np.zeros(n, int),
        materials=("al6061-t6",), damage=np.ones(n), failure_strain_rate=np.full(n, rate_at_failure))


def test_grady_fragments_are_sized_by_the_bodys_rate_when_the_initial_state_is_given():
    """Failed particles that recorded a kernel-scale rate 30 times the body's: without the initial state
    they break into spray (s < Δ); with it, into fragments of Grady's size at the body's own rate
    (3 Δ: about 4096/27 of them), their mass and momentum the particles'."""
    spacing, body_rate = 0.01, None
    size = 3 * spacing
    body_rate = (24 * TOUGHNESS ** 2 / (YOUNG * RHO0 * size ** 3)) ** 0.5
    initial = _failed_block(spacing, 0.0, lambda x: np.zeros_like(x))
    now = _failed_block(spacing, 30 * body_rate, lambda x: 0.5 + body_rate * x)
    assert len(shield.grady_fragments(now, link_length_cm=1.5 * spacing, mirror_x0=False)) == 0
    initial = _failed_block(spacing, 0.0, lambda x: np.full_like(x, 0.5))       # moving at t = 0: one body
    fragments = shield.grady_fragments(now, link_length_cm=1.5 * spacing, mirror_x0=False, initial=initial)
    expected = len(now) / 27
    assert abs(len(fragments) - expected) < 4 * math.sqrt(expected)
    assert fragments.total_mass() == pytest.approx(now.total_mass(), rel=1e-12)
    np.testing.assert_allclose(fragments.momentum(), now.total_momentum(), rtol=1e-12)
