"""Planar Al 6061-T6 on Al 6061-T6 impact at 2 km/s: the SPH shock state against the Hugoniot (issue 4)."""

import numpy as np
import pytest

from impactdyn import shield
from impactdyn.materials import AL_6061_T6 as AL
from impactdyn.units import km_s_to_cm_us

DX = 0.01  # cm: 40 particles through the flyer, 60 through the target
T1, T2 = 0.25, 0.65  # µs: the target shock is at 1.7 and 4.3 mm, the flyer shock has not reached its back


def layer_profile(initial_y, state):
    """Mean y, pressure and y-velocity of each particle layer (same initial y), in layer order."""
    layers, index = np.unique(np.round(initial_y / DX, 6), return_inverse=True)
    count = np.bincount(index)
    return [np.bincount(index, w) / count for w in (state.position[:, 1], state.pressure, state.velocity[:, 1])]


def shock_front(y, p, p_half):
    """Position where the pressure falls through p_half ahead of the plateau (linear interpolation)."""
    k = np.nonzero((p > p_half) & (y > 0))[0].max()
    return y[k] + (y[k + 1] - y[k]) * (p[k] - p_half) / (p[k] - p[k + 1])


@pytest.fixture(scope="module")
def planar_run():
    problem = shield.planar_impact(AL, AL, velocity_km_s=2.0, flyer_length_cm=0.4, target_length_cm=0.6,
                                   spacing_cm=DX, width_particles=3)
    return problem, shield.run(problem, T2, snapshot_times_us=(T1, T2))


def test_plateau_pressure_and_shock_speed_match_hugoniot(planar_run):
    problem, result = planar_run
    # Hugoniot of the EOS parameters: symmetric impact, up = V/2, Us = c0 + s up, p = ρ0 Us up
    up = km_s_to_cm_us(2.0) / 2
    us = AL.c0 + AL.s * up
    p_h = AL.rho0 * us * up
    assert p_h == pytest.approx(0.179, abs=0.001) and us == pytest.approx(0.664)  # 17.9 GPa, 6.64 km/s

    fronts = []
    for state in result.snapshots:
        y, p, vy = layer_profile(problem.particles.position[:, 1], state)
        t = state.time
        behind = (y > up * t + 0.25 * (us - up) * t) & (y < up * t + 0.75 * (us - up) * t)  # mid-plateau layers
        assert behind.sum() >= 5
        plateau = np.median(p[behind])
        assert plateau == pytest.approx(p_h, rel=0.05)
        assert np.median(vy[behind]) == pytest.approx(up, rel=0.02)
        fronts.append(shock_front(y, p, plateau / 2))
    shock_speed = (fronts[1] - fronts[0]) / (T2 - T1)
    assert shock_speed == pytest.approx(us, rel=0.05)


def test_planar_run_conserves_momentum_and_energy(planar_run):
    _, result = planar_run
    h = result.history
    assert np.all(h.mass == h.mass[0])
    np.testing.assert_allclose(h.momentum[:, 1], h.momentum[0, 1], rtol=1e-12)
    assert np.abs(h.total_energy / h.total_energy[0] - 1).max() < 1e-3
    assert h.internal[-1] > 0.3 * h.total_energy[0]  # a strong shock has converted kinetic energy
