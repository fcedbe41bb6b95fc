"""Spall in a one-dimensional flyer-plate impact (Al on Al, flyer h, target 2h, lateral translations fixed).

The flyer (0 < y < h) moves at V into the target (h < y < 3h), bonded to it at y = h (the
interface carries no tension before the reflected wave comes back to it, after the time
looked at).  The compressive pulses meet the release from the flyer's free back and the
reflection from the target's free rear face in the plane y = 2h, h from the rear face, at
t ≈ 3h/c (about 1.1 µs for the plastic wave, at about the bulk sound speed; the run ends at
1.4 µs, before the tension gets back to the interface at about 1.5 µs): the tension there is
about the impact stress ρcV/2.  A fast impact (V = 600 m/s,
ρcV/2 ≈ 5 GPa) spalls the target in that plane; a slow one (V = 100 m/s, about 0.9 GPa)
stays below the spall strength (1.2 GPa, the library's 6061-T6) and does not fail.

Both models: "mat13" with the report's card and the failure pressure p_cut = −p_spall (no
plastic-strain failure), "johnson_cook" with each of its spall laws, the Tuler–Butcher damage
integral (the default; threshold σ₀ = p_spall, so the slow impact accumulates no damage) and the
cut-off p < −p_spall (no ductile damage, which would fail the material in triaxial tension below
the spall strength with the fit unbounded, :mod:`impactdyn.wall._johnson_cook`).
"""

import dataclasses

import numpy as np
import pytest

from impactdyn import wall
from impactdyn.materials import AL_6061_T6, AL_6061_T6_MAT13
from impactdyn.wall._state import SPALL_DAMAGE
from impactdyn.wallgrid import WallGrid

H = 0.2
N = 20                                       # elements per h
GRID = WallGrid.uniform((0.0, H / N), (0.0, 3 * H), (0.0, H / N), (2, 3 * N + 1, 2))


#: (model, spall law): the models and laws under test, and the failure cause each records.
CASES = {("mat13", None): "tensile_pressure", ("johnson_cook", "tuler_butcher"): "spall_damage",
         ("johnson_cook", "cutoff"): "tensile_pressure"}


def spall_model(name: str, law: str | None) -> wall.WallModel:
    if name == "mat13":
        card = dataclasses.replace(AL_6061_T6_MAT13, failure_strain=0.0, failure_pressure=-AL_6061_T6.spall_strength)
        return wall.Mat13Model(card, source="App. D card with p_cut = -p_spall")
    return wall.wall_model("johnson_cook", "al6061-t6", damage=None, spall_law=law)


def flyer_plate(model: wall.WallModel, speed: float):
    mesh = wall.build_mesh(GRID, model.density, supports="uniaxial")
    y = mesh.coordinates[:, 1]
    v = np.zeros((mesh.n_nodes, 3))
    v[y < H - 1e-9, 1] = speed
    v[np.abs(y - H) < 1e-9, 1] = 0.5 * speed
    options = wall.WallOptions(supports="uniaxial", material_model=model.name, end_time_us=1.4)
    s = wall.WallSolver(mesh, model, options, velocity=v)
    p0 = (mesh.node_mass * s.v[:, 1]).sum()
    result = s.run()
    return s, result, p0


def test_every_model_has_a_spall_case():
    assert {name for name, _ in CASES} == set(wall.MODELS), "state each wall model's spall case (CASES)"


@pytest.mark.parametrize("name, law", sorted(CASES, key=str))
def test_fast_impact_spalls_h_from_the_rear_face(name, law):
    s, result, p0 = flyer_plate(spall_model(name, law), 0.06)
    damaged = s.failed | s.eroded
    assert damaged.any()
    yc = s.mesh.coordinates[s.mesh.connectivity, 1].mean(axis=1)       # initial element centres
    mass = s.mesh.element_mass[damaged]
    plane = 2 * H
    assert np.average(yc[damaged], weights=mass) == pytest.approx(plane, abs=H / 10)
    assert np.abs(yc[damaged] - plane).max() <= H / 4
    assert result.verdict == wall.DETACHED_SPALL
    # all of it failed on the law's criterion, and the measure says so
    cause = CASES[name, law]
    assert result.measures["failed_mass_by_cause_g"][cause] == pytest.approx(
        s.mesh.element_mass[damaged].sum(), rel=1e-12)
    assert np.all(result.frames[-1].failure_cause[damaged] == 1 + wall.FAILURE_CAUSES.index(cause))
    # eroded or not, no momentum is lost
    assert (s.mesh.node_mass * s.v[:, 1]).sum() == pytest.approx(p0, rel=1e-12)
    assert abs(result.measures["energy"]["balance_error"]) < 1e-10


@pytest.mark.parametrize("name, law", sorted(CASES, key=str))
def test_slow_impact_does_not_spall(name, law):
    s, result, _ = flyer_plate(spall_model(name, law), 0.01)
    assert not (s.failed | s.eroded).any()
    if law == "tuler_butcher":   # the tension (≈ 0.9 GPa) never passed the threshold σ₀ = 1.2 GPa
        assert s.es[:, SPALL_DAMAGE].max() == 0.0
    assert result.verdict == wall.NO_PERFORATION
