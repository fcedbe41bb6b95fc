"""The phase of a released state (impactdyn.constitutive._phase): the latent heats hold the temperature
on the melting range and at the boiling point, and a material without phase data never melts."""

import dataclasses

import numpy as np
import pytest

from impactdyn.constitutive import T_ROOM, pack_materials, pack_phases, phase_of_released, release_states
from impactdyn.materials import AL_6061_T6


def test_the_latent_heats_hold_the_temperature_while_the_phase_changes():
    params, phases = pack_materials([AL_6061_T6]), pack_phases([AL_6061_T6])
    ph, cv = AL_6061_T6.phase, AL_6061_T6.specific_heat
    e1 = cv * (ph.solidus - T_ROOM)
    e2 = cv * (ph.liquidus - T_ROOM) + ph.latent_fusion
    e3 = e2 + cv * (ph.boiling - ph.liquidus)
    e4 = e3 + ph.latent_vaporisation
    assert phase_of_released(0.5 * e1, params, phases, 0) == pytest.approx((T_ROOM + 0.5 * e1 / cv, 0.0, 0.0))
    assert phase_of_released(e1, params, phases, 0) == pytest.approx((ph.solidus, 0.0, 0.0))
    t, melted, vapour = phase_of_released(0.5 * (e1 + e2), params, phases, 0)
    assert (t, melted, vapour) == pytest.approx((0.5 * (ph.solidus + ph.liquidus), 0.5, 0.0))
    assert phase_of_released(e2, params, phases, 0) == pytest.approx((ph.liquidus, 1.0, 0.0))
    assert phase_of_released(0.5 * (e3 + e4), params, phases, 0) == pytest.approx((ph.boiling, 1.0, 0.5))
    assert phase_of_released(e4 + 10 * cv, params, phases, 0) == pytest.approx((ph.boiling + 10, 1.0, 1.0))


def test_a_state_already_at_or_below_zero_pressure_is_released_as_it_is():
    params, phases = pack_materials([AL_6061_T6]), pack_phases([AL_6061_T6])
    rho = np.array([0.5 * AL_6061_T6.rho0, AL_6061_T6.rho0])     # failed debris's bulk density; p = 0 at e = 0
    e = np.array([0.02, 0.0])
    e_r, _, melted, _ = release_states(rho, e, np.zeros(2, dtype=np.int64), params, phases)
    assert np.array_equal(e_r, e)
    assert melted[0] == 1.0 and melted[1] == 0.0


def test_a_material_without_phase_data_never_melts():
    plain = dataclasses.replace(AL_6061_T6, name="plain", phase=None)
    params, phases = pack_materials([plain]), pack_phases([plain])
    _, melted, vapour = phase_of_released(1.0, params, phases, 0)
    assert melted == 0.0 and vapour == 0.0
