"""Invariants, event timing and integrator order of the beam model."""

import numpy as np
import pytest

from impactdyn.beam import CONTACT_LAWS, BeamModel, simulate

from .conftest import contact_section, contact_table

FREE = {"torque": {"amplitude_N_m": 0.0}, "damping": {"joint_N_m_s": 0.0, "modal_ratio": 0.0}}


def test_first_contact_time_of_a_rigid_spinning_beam(make_case):
    """n = 0 modes, constant spin, no gravity: contact at θ₀/Ω exactly."""
    theta0, omega = 0.3, 2.0
    case = make_case("impactc_sample.toml", **FREE, model={"n_modes": 0, "gravity_m_s2": 0.0},
                     initial={"theta_rad": theta0, "theta_dot_rad_s": -omega},
                     time={"end_s": 0.2, "output_step_s": 0.01})
    r = simulate(case)
    assert abs(r.impacts[0].t_start - theta0 / omega) < 1e-9


def test_energy_conserved_through_elastic_impacts(make_case):
    """No damping, torque or gravity, e = 1: E = T + V is an invariant of the coupled model."""
    case = make_case("impactc_sample.toml", **FREE,
                     model={"n_modes": 3, "gravity_m_s2": 0.0, "coupled": True},
                     contact={"model": "momentum", "restitution_law": "constant", "restitution": 1.0,
                              "rest_velocity_m_s": 1e-9},
                     initial={"theta_rad": 0.02, "theta_dot_rad_s": -8.0},
                     time={"end_s": 0.05, "output_step_s": 1e-4},
                     solver={"rtol": 1e-11, "atol": 1e-14})
    r = simulate(case)
    assert len(r.impacts) >= 3
    e = r.energy
    assert np.max(np.abs(e - e[0])) / abs(e[0]) < 1e-6


def test_hertz_contact_returns_energy(make_case):
    """An undamped Hertz contact stores and returns the energy: E after = E before."""
    case = make_case("impactb_sample.toml", **FREE,
                     model={"n_modes": 3, "gravity_m_s2": 0.0, "coupled": True},
                     contact={"model": "hertz", "stiffness_N_m1_5": 3.2e9, "damping_s_m": 0.0},
                     initial={"theta_rad": 0.02, "theta_dot_rad_s": -8.0},
                     time={"end_s": 0.03, "output_step_s": 1e-4},
                     solver={"rtol": 1e-11, "atol": 1e-14})
    r = simulate(case)
    assert len(r.impacts) >= 1
    outside = np.ones(len(r.t), bool)
    for i in r.impacts:
        outside &= ~((r.t >= i.t_start) & (r.t <= i.t_end + 1e-3))
    e = r.energy[outside]
    assert np.max(np.abs(e - e[0])) / abs(e[0]) < 1e-6
    assert r.impacts[0].restitution == pytest.approx(1.0, abs=1e-3)


#: The compliant laws that take a target restitution (every such registered law).
DISSIPATIVE = sorted(law for law, cls in CONTACT_LAWS.items()
                     if not cls.impulsive and "restitution" in contact_section(law).model_fields)


@pytest.mark.parametrize("law", DISSIPATIVE)
def test_dissipative_laws_reach_their_restitution(make_case, law):
    """A rigid beam (n = 0) on a stiff contact: v_sep/v_app ≈ the law's target e."""
    case = make_case("impactb_sample.toml", **FREE, model={"n_modes": 0, "gravity_m_s2": 0.0},
                     contact=contact_table(law, stiffness_N_m_n=1e9, restitution=0.9),
                     initial={"theta_rad": 0.01, "theta_dot_rad_s": -4.0},
                     time={"end_s": 0.01, "output_step_s": 1e-4})
    e = simulate(case).impacts[0].restitution
    # both damping coefficients are derived for e near 1 (at e = 0.7 they give 0.77
    # and 0.80): the laws' known limitation, not a solver error
    assert e == pytest.approx(0.9, abs=0.02)


def test_energy_balance_closes_with_damping_and_torque(make_case, impactb_result):
    """E − E₀ = work of torque − losses + work of contact: exactly (to the integration
    tolerance) for the coupled model; for the linearised model up to its own
    non-conservation (it drops d/dt(θ̇ qᵀPq) from the hub equation), under 1 %."""
    coupled = simulate(make_case("impactb_sample.toml", model={"coupled": True})).energy_terms()
    scale = np.max(np.abs(coupled["work_torque"]))
    assert np.max(np.abs(coupled["residual"])) < 1e-8 * scale
    linear = impactb_result.energy_terms()
    assert np.max(np.abs(linear["residual"])) < 1e-2 * scale


def test_rosenbrock_is_fourth_order(make_case):
    """Fixed-step-like runs (tolerance-driven) on a smooth free flight: fit log-error
    against log(mean step) and check the slope is near the method's order 4."""
    base = dict(**FREE, model={"n_modes": 3, "gravity_m_s2": 9.81},
                initial={"theta_rad": 3.0, "theta_dot_rad_s": -1.0, "tip_deflection_m": 0.002},
                time={"end_s": 0.05, "output_step_s": 0.05})
    ref = simulate(make_case("impactc_sample.toml", **base, solver={"rtol": 1e-13, "atol": 1e-16})).y[-1]
    steps, errs = [], []
    for tol in (1e-5, 1e-6, 1e-7, 1e-8):
        r = simulate(make_case("impactc_sample.toml", **base, solver={"rtol": tol, "atol": tol * 1e-3}))
        steps.append(0.05 / r.stats["steps"])
        errs.append(np.max(np.abs(r.y[-1, :8] - ref[:8]) / (np.abs(ref[:8]) + 1e-6)))
    slope = np.polyfit(np.log(steps), np.log(errs), 1)[0]
    assert 3.0 < slope < 5.5


def test_momentum_impact_solves_the_balance(make_case):
    """J v⁺ = −e J v⁻ and M Δv ∥ Jᵀ after one impulsive impact."""
    case = make_case("impactc_sample.toml")
    m = BeamModel.from_case(case)
    rng = np.random.default_rng(1)
    y = np.zeros(m.n_state)
    y[: 2 * m.n + 2] = rng.normal(size=2 * m.n + 2)
    y_new, P = m.impact(y, 0.4)
    n = m.n
    J = m.jacobian_row()
    v, v_new = y[n + 1 : 2 * n + 2], y_new[n + 1 : 2 * n + 2]
    assert J @ v_new == pytest.approx(-0.4 * (J @ v), rel=1e-12)
    np.testing.assert_allclose(m.mass_matrix(y) @ (v_new - v), J * P, rtol=1e-12, atol=1e-14)
