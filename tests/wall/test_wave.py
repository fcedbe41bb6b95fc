"""An elastic pulse crosses the wall at c_L = √((K + 4G/3)/ρ) and reflects from the free rear face as tension.

A column of 200 elements through a 2 cm thickness in one-dimensional strain (``uniaxial``
supports), loaded on its front face by a constant force for 1 µs (impulse records every
0.01 µs: the deposition path of the solver).  The speed is measured between two stations,
0.5 and 1.5 cm deep, from the times the particle velocity first reaches half its plateau.
"""

import numpy as np
import pytest

from impactdyn import wall
from impactdyn.wall._state import P
from impactdyn.wallgrid import WallDeposition, WallGrid

from .conftest import elastic_model, elastic_moduli

THICKNESS, N = 2.0, 200
GRID = WallGrid.uniform((0.0, 0.05), (0.0, THICKNESS), (0.0, 0.05), (2, N + 1, 2))
FORCE = 1.0e-5          # g·cm/µs² on the 0.05 × 0.05 cm face: 4 kbar, below the HEL of 6061-T6 (about 6 kbar)
DURATION = 1.0


def run_column(model):
    dt_rec = 0.01
    times = np.arange(0.0, DURATION, dt_rec)
    dep = WallDeposition(element=np.zeros(times.size, dtype=np.int64), time=times,
                         impulse=np.tile([0.0, FORCE * dt_rec, 0.0], (times.size, 1)))
    options = wall.WallOptions(supports="uniaxial", material_model=model.name)
    mesh = wall.build_mesh(GRID, model.density, supports="uniaxial")
    s = wall.WallSolver(mesh, model, options, load=wall.nodal_load(mesh, dep, options.spread), t_start=0.0)
    stations = {y: 4 * int(round(y / THICKNESS * N)) for y in (0.5, 1.5)}
    probe = int(round(1.65 / THICKNESS * N))           # element 0.35 cm from the rear face
    t, v, syy = [], {y: [] for y in stations}, []
    while s.time < 5.0:
        s.advance(np.inf, max_steps=1)
        t.append(s.time - 0.5 * s.clock[1])               # v is the half-step velocity
        for y, n in stations.items():
            v[y].append(s.v[n, 1])
        syy.append(s.S[probe, 1] - s.es[probe, P])
    return np.array(t), {y: np.array(a) for y, a in v.items()}, np.array(syy), s


def arrival(t, v, plateau):
    k = np.flatnonzero(v >= 0.5 * plateau)[0]
    return t[k - 1] + (0.5 * plateau - v[k - 1]) / (v[k] - v[k - 1]) * (t[k] - t[k - 1])


def test_pulse_speed_and_reflection(model_name):
    model = elastic_model(model_name)
    rho, K, G = elastic_moduli(model)
    c_l = np.sqrt((K + 4.0 * G / 3.0) / rho)
    t, v, syy, s = run_column(model)
    area = 0.05 * 0.05
    v_plateau = FORCE / area / (rho * c_l)                # particle velocity of the incident pulse
    t1 = arrival(t, v[0.5], v_plateau)
    t2 = arrival(t, v[1.5], v_plateau)
    c = 1.0 / (t2 - t1)
    assert c == pytest.approx(c_l, rel=0.02)
    # the incident pulse is compressive, the reflected one tensile, of about the same strength
    stress = FORCE / area
    incident = syy[(t > 2.7) & (t < 3.5)]
    reflected = syy[(t > 3.9) & (t < 4.6)]
    assert incident.mean() == pytest.approx(-stress, rel=0.1)
    assert reflected.mean() == pytest.approx(stress, rel=0.1)
    assert reflected.min() > 0.0
