"""A wall failure law registered from outside the package (this module) is a value of ``spall_law``
and runs: the one-module recipe of docs/extending.md.

The law here is the cut-off written as a plug-in that brings its own constant (the spall strength in its
slot of the parameter vector, ``prm[J_LAW]``, where the built-in cut-off reads the packed material
table): on the flyer plate of :mod:`test_spall` it fails the same elements at the same steps, to the bit.
"""

import numpy as np
import pytest
from numba import njit

from impactdyn import wall
from impactdyn._errors import InputError

from .test_spall import flyer_plate


@njit(inline="always")
def accumulate(e, p_old, p_new, dt, es, table, prm):
    """No state."""


@njit(inline="always")
def fails(e, p_new, es, table, prm):
    return p_new < -prm[wall.J_LAW]


THRESHOLD = wall.FailureLaw(
    name="test_threshold", description="p < -p_spall, the constant in the law's own parameter slot",
    cause="tensile_pressure", accumulate=accumulate, fails=fails,
    library_constants=lambda material: material.spall_strength,
    kernel_constants=lambda spall_strength: (spall_strength,),
    describe=lambda spall_strength: spall_strength, describe_key="test_threshold_Mbar", needs="a spall strength")


@pytest.fixture
def threshold_law():
    wall.FAILURE_LAWS.register(THRESHOLD.name, THRESHOLD)
    yield THRESHOLD
    wall.FAILURE_LAWS.unregister(THRESHOLD.name)


def test_a_registered_law_is_accepted_by_the_options_and_runs(threshold_law):
    options = wall.WallOptions(spall_law="test_threshold")
    assert options.spall_law == "test_threshold"
    model = wall.wall_model("johnson_cook", "al6061-t6", damage=None, spall_law="test_threshold")
    assert model.failure_law is threshold_law and not threshold_law.in_package
    assert model.kernel_params()[wall.J_LAW] == model.material.spall_strength
    described = model.describe()
    assert described["spall_law"] == "test_threshold" and described["test_threshold_Mbar"] == 0.012
    assert described["tuler_butcher"] is None and model.failure_criteria() == ("tensile_pressure",)
    cutoff = wall.wall_model("johnson_cook", "al6061-t6", damage=None, spall_law="cutoff")
    s, result, _ = flyer_plate(model, 0.06)
    ref, ref_result, _ = flyer_plate(cutoff, 0.06)
    assert s.failed.any() and result.verdict == wall.DETACHED_SPALL
    # the same failures, element for element; the states to round-off: the two laws' kernels are compiled
    # separately, and numba's machine code for one source differs in the last bits between a fresh compile and
    # one loaded from its cache (measured on the 7a wall: 4e-16 per step, 2e-12 in the bulge after 1720 steps)
    assert np.array_equal(s.flags, ref.flags)
    for mine, theirs in ((s.S, ref.S), (s.es, ref.es)):    # to 1e-9 of the field's largest value
        np.testing.assert_allclose(mine, theirs, rtol=1e-9, atol=1e-9 * np.abs(theirs).max())
    assert result.measures["failed_mass_by_cause_g"] == ref_result.measures["failed_mass_by_cause_g"]


def test_a_law_the_material_has_no_constants_for(threshold_law):
    # required (the default): refused naming the key, the law and what it needs
    with pytest.raises(InputError, match="spall_law: 'test_threshold' needs a spall strength"):
        wall.wall_model("johnson_cook", "al6061-t6", spall_law="test_threshold", spall_constants=None)


def test_an_unregistered_law_is_refused_with_the_choices():
    with pytest.raises(InputError, match="spall_law: unknown wall failure law 'test_threshold'; "
                                         "choose one of tuler_butcher, cutoff"):
        wall.WallOptions(spall_law="test_threshold")
