"""The analytic Jacobian of the beam's right-hand side against finite differences."""

import numpy as np
import pytest

from impactdyn.beam import CONTACT_LAWS, BeamModel
from impactdyn.beam._model import IN_CONTACT, rhs_kernel
from impactdyn.beam._simulate import contact_law

from .conftest import contact_table

#: Values other than the defaults, where a law has some worth exercising (a dashpot, another exponent).
TUNED = {"hertz": {"damping_s_m": 0.006}, "lankarani_nikravesh": {"exponent": 1.3, "restitution": 0.7}}
LAWS = {law: contact_table(law, **TUNED.get(law, {})) for law in sorted(CONTACT_LAWS)}
COMPLIANT = [law for law in LAWS if not CONTACT_LAWS[law].impulsive]
#: Free flight (0) with one law, compliant contact (1) with every compliant law, resting (2) with every impulsive one.
LAW_MODES = [(COMPLIANT[0], 0)] + [(law, 1 if law in COMPLIANT else 2) for law in LAWS]
PENETRATION = 1e-5  # m, of the contact states


def finite_difference_jacobian(y, model, coupled, scale):
    """Fourth-order central differences of the compiled right-hand side, column by
    column, with steps of 1e-3 ``scale``."""
    jac = np.empty((y.size, y.size))
    for k in range(y.size):
        d = 1e-3 * scale[k]
        f = {}
        for s in (-2, -1, 1, 2):
            yp = y.copy()
            yp[k] += s * d
            f[s] = rhs_kernel(0.0, yp, model, coupled)
        jac[:, k] = (8.0 * (f[1] - f[-1]) - (f[2] - f[-2])) / (12.0 * d)
    return jac


def state_and_params(case, mode, amplitude=1e-3):
    """A generic state (hub radius, damping, torque all nonzero) in free flight, in
    compliant contact or resting on the stop; modal amplitudes ~``amplitude`` (m),
    their rates ~300 ``amplitude`` /s."""
    m = BeamModel.from_case(case)
    n = m.n
    rng = np.random.default_rng(7)
    y = np.zeros(m.n_state)
    y[1 : n + 1] = amplitude * rng.normal(size=n)
    y[n + 1] = -3.0
    y[n + 2 : 2 * n + 2] = 300.0 * amplitude * rng.normal(size=n)
    if mode == 0:
        y[0] = 0.3
    else:  # put the stop point into the stop
        y[0] = (-PENETRATION - m.phi_p @ y[1 : n + 1]) / (m.jacobian_row()[0])
    sc = m.params(torque=-0.18, v0=2.0)
    sc[IN_CONTACT] = mode
    return m, y, sc


@pytest.mark.parametrize("legacy_arms", [False, True], ids=["", "legacy_arms"])
@pytest.mark.parametrize("coupled,amplitude", [(False, 1e-3), (True, 1e-3), (True, 0.04)],
                         ids=["linear", "coupled", "coupled_large"])
@pytest.mark.parametrize("law,mode", LAW_MODES)
def test_analytic_jacobian_matches_finite_differences(make_case, law, mode, coupled, amplitude, legacy_arms):
    """Entry by entry to 1e-6 relative, linear and coupled, in every mode, also with the
    legacy moment arms (force direction ≠ gap row). The floor, 1e-9 of the row's largest
    entry, is the differences' own round-off: at rest, ∂θ̈/∂θ is a 1e-8 remainder of
    entries that cancel through λ. ``coupled_large``: modal amplitudes of 4 cm (tip
    deflections ~15 % of L, rates ~12 m/s), where the foreshortening and curvature terms
    are a tenth of the linear ones and every one of them shows in the entries."""
    case = make_case("impactb_sample.toml", contact=LAWS[law],
                     model={"n_modes": 3, "coupled": coupled}, legacy={"moment_arms_ignore_hub": legacy_arms},
                     beam={"hub_radius_m": 0.02}, damping={"modal_ratio": 0.01})
    m, y, sc = state_and_params(case, mode, amplitude)
    law_obj = contact_law(case)
    segment = m.segment(sc, law_obj.kernel_id, law_obj.params())
    if mode == 1:
        assert m.contact_force(y, sc, law_obj.kernel_id, law_obj.params()) > 0.0
    analytic = m.jacobian(y, sc, law_obj.kernel_id, law_obj.params())
    scale = np.maximum(np.abs(y), 1e-6)
    if mode == 1:  # steps in θ, q small against the penetration, where the force law curves
        gap_row = np.abs(m.jacobian_row())
        scale[: m.n + 1] = np.minimum(scale[: m.n + 1], PENETRATION / gap_row)
    numeric = finite_difference_jacobian(y, segment, m.coupled_terms(), scale)
    floor = 1e-9 * np.max(np.abs(numeric), axis=1, keepdims=True)
    err = np.abs(analytic - numeric)
    assert np.all(err <= 1e-6 * np.abs(numeric) + floor)
    # the running integrals do not feed back
    assert not np.any(analytic[:, 2 * m.n + 2 :])


@pytest.mark.parametrize("law", sorted(CONTACT_LAWS))
def test_every_registered_law_is_built_from_its_contact_table(make_case, law):
    """A registered law has a [contact] table that accepts it, and the case builds that law."""
    case = make_case("impactb_sample.toml", contact=LAWS[law])
    built = contact_law(case)
    assert isinstance(built, CONTACT_LAWS[law]) and built.name == law
    assert built.params().ndim == 1 and np.all(np.isfinite(built.params()))
