"""The Rosenbrock steps' controller is the elementary one of Hairer, Nørsett & Wanner (I, §II.4)."""

import pytest

from impactdyn.beam._step_control import StepControl, next_step

CONTROL = StepControl(rtol=1e-8, atol=1e-11, max_steps=1000)


@pytest.mark.parametrize("err", [0.02, 0.3, 1.0, 2.0, 40.0])
def test_next_step_aims_at_the_safety_factor_error(err):
    """Between its limits the controller picks the step whose error, O(h^(q+1)) with q = 3 the
    order of the embedded estimate, would be safety^(q+1) of the tolerance."""
    h_new = next_step(CONTROL, 1e-4, err)
    assert err * (h_new / 1e-4) ** 4 == pytest.approx(CONTROL.safety**4, rel=1e-12)


@pytest.mark.parametrize("err,factor", [(0.0, 5.0), (1e-6, 5.0), (1e3, 0.2), (1e10, 0.2)])
def test_next_step_grows_and_shrinks_at_most_five_fold(err, factor):
    """A step without error grows five-fold (not infinitely); a non-finite error, which the
    step loop counts as 1e10, or a large one cuts the step five-fold."""
    assert next_step(CONTROL, 1e-4, err) == pytest.approx(factor * 1e-4, rel=1e-15)
