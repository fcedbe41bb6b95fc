"""Compact fragments on the wall: a solid fragment's flight to the wall and its load (the debris's second
population), conserving its momentum exactly on a half model."""

import numpy as np
import pytest

from impactdyn._errors import InputError
from impactdyn.debris import compact_deposition, element_impulse
from impactdyn.wallgrid import WallGrid

WALL_Y = 2.0


def _wall(h=0.02):
    x = np.arange(0.0, 1.0 + h / 2, h)
    z = np.arange(-1.0, 1.0 + h / 2, h)
    return WallGrid(x=x, y=np.array([WALL_Y, WALL_Y + 0.1]), z=z)


def _one(position, velocity, diameter=0.12, mass=None):
    mass = 2.7 * np.pi * diameter ** 3 / 6 if mass is None else mass
    return (np.array([mass]), np.array([diameter]), np.array([position], float), np.array([velocity], float))


def test_a_fragment_beside_the_plane_lays_down_all_its_momentum_where_and_when_it_arrives():
    wall = _wall()
    mass, d, r, v = _one([0.4, 1.0, -0.1], [0.05, 0.5, 0.1])
    records, share = compact_deposition(wall, WALL_Y, mass, d, r, v)
    assert share.tolist() == [1.0]
    assert records.impulse.sum(axis=0) == pytest.approx(mass[0] * v[0], rel=1e-12)
    t0 = (WALL_Y - r[0, 1] - d[0] / 2) / v[0, 1]
    assert records.time.min() == pytest.approx(t0, abs=wall.x[1] / v[0, 1])
    assert records.time.max() <= t0 + d[0] / v[0, 1] + wall.x[1] / v[0, 1]
    # the footprint's centre, weighted by impulse, is where the centre of mass strikes
    total = element_impulse(records, wall)[..., 1]
    xc = 0.5 * (wall.x[:-1] + wall.x[1:])
    zc = 0.5 * (wall.z[:-1] + wall.z[1:])
    hit = (np.sum(total * xc[:, None]) / total.sum(), np.sum(total * zc[None, :]) / total.sum())
    assert hit == pytest.approx((r[0, 0] + v[0, 0] * t0, r[0, 2] + v[0, 2] * t0), abs=0.2 * wall.x[1])


def test_a_half_model_folds_what_lies_beyond_the_plane_and_gives_an_image_nothing():
    wall = _wall()
    mass, d, r, v = _one([0.03, 1.0, 0.0], [0.0, 0.5, 0.0])            # the disc reaches x = −0.03
    records, share = compact_deposition(wall, WALL_Y, mass, d, r, v)
    assert share.tolist() == [1.0] and records.impulse[:, 1].sum() == pytest.approx(mass[0] * 0.5, rel=1e-12)
    records, share = compact_deposition(wall, WALL_Y, mass, d, np.array([[-0.4, 1.0, 0.0]]), v)
    assert share.tolist() == [0.0] and records.element.size == 0
    # on the plane (found whole with its image): the x ≥ 0 half
    records, share = compact_deposition(wall, WALL_Y, mass, d, np.array([[0.0, 1.0, 0.2]]), v)
    assert share.tolist() == [0.5] and records.impulse[:, 1].sum() == pytest.approx(0.25 * mass[0], rel=1e-12)


def test_a_fragment_partly_off_the_wall_loses_that_part():
    wall = _wall()
    mass, d, r, v = _one([1.0, 1.0, 0.0], [0.0, 0.5, 0.0])             # centred on the wall's edge
    records, _ = compact_deposition(wall, WALL_Y, mass, d, r, v)
    assert records.impulse[:, 1].sum() == pytest.approx(0.5 * mass[0] * 0.5, rel=0.01)   # half of it, sampled


def test_a_fragment_that_does_not_fly_to_the_wall_is_refused():
    mass, d, r, v = _one([0.4, 1.0, 0.0], [0.1, 0.0, 0.0])
    with pytest.raises(InputError, match="v_y > 0"):
        compact_deposition(_wall(), WALL_Y, mass, d, r, v)
