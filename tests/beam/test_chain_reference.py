"""The rigid-link chain (``_chain``) as an independent nonlinear check of the modal model.

(a) The chain's clamped, non-rotating frequencies converge to the Euler–Bernoulli
cantilever's βᵢ²·√(EI/ρL⁴) at second order in 1/N.
(b) A large-deflection spin-up (tip deflection ≈ 10 % of L): the ``coupled`` modal
model follows the chain's hub angle 6–10× closer than the linearised one (the light
hub is covered by ``test_coupled_chain.py``). The tolerances come from the
convergence study in docs/vv/analytic.md ("The coupled beam model against a rigid-link
chain", ``python verification/verify_beam_chain.py``).
"""

import numpy as np
import pytest

from impactdyn import SimulationError
from impactdyn.beam import RigidLinkChain, eigenvalues, simulate


def test_clamped_frequencies_converge_to_euler_bernoulli(make_case):
    """Relative errors of the first three frequencies fall 4× per halving of ℓ, and
    Richardson's extrapolation of N = 32, 64 lands within 2e-6 of βᵢ² (measured
    5e-8, 7e-7, 1.4e-6: the next term, O(N⁻⁴))."""
    case = make_case("impactc_sample.toml")
    bm = case.beam
    scale = np.sqrt(bm.EI_N_m2 / (bm.mass_per_length_kg_m * bm.length_m**4))
    beta_sq = eigenvalues(3) ** 2
    omega = {N: RigidLinkChain.from_case(case, N).clamped_frequencies()[:3] / scale for N in (8, 16, 32, 64)}
    err = {N: omega[N] / beta_sq - 1.0 for N in omega}
    assert np.all(err[8] < 0) and np.all(np.abs(err[64]) < 1e-3)
    for N in (16, 32):
        np.testing.assert_allclose(err[N] / err[2 * N], 4.0, rtol=0.05)
    richardson = (4.0 * omega[64] - omega[32]) / 3.0
    np.testing.assert_allclose(richardson, beta_sq, rtol=2e-6)


def test_chain_conserves_energy(make_case):
    """No torque or damping: T + V of the chain is an invariant (checks its Lagrange equations)."""
    case = make_case("impactc_sample.toml", torque={"amplitude_N_m": 0.0}, damping={"joint_N_m_s": 0.0},
                     beam={"hub_radius_m": 0.05, "inertia_ratio": 0.5})
    chain = RigidLinkChain.from_case(case, 6)
    t = np.linspace(0.0, 0.05, 11)
    y0 = chain.initial_state(0.5, 20.0)
    y0[3:7] += 0.2  # bend the beam: large motion of every link
    e = chain.energy(chain.integrate(y0, t, rtol=1e-10, atol=1e-12))
    assert np.max(np.abs(e - e[0])) < 1e-8 * abs(e[0])



def test_chain_integration_failure_is_a_simulation_error(make_case):
    """A torque the solver cannot carry (infinite) ends in the package's SimulationError, naming the time."""
    chain = RigidLinkChain.from_case(make_case("impactc_sample.toml"), 4)
    with pytest.raises(SimulationError, match="chain integration failed at t = 0 s"):
        chain.integrate(chain.initial_state(0.0, 0.0), np.linspace(0.0, 0.01, 3), torques=(np.inf,))


@pytest.fixture(scope="module")
def spin_up(make_case):
    """Heavy hub (IR = 1), no gravity, τ = ±3 N·m for 50 ms each: tip deflection 9.6 % of L.

    Returns (chain reference, linear result, coupled result); the reference is
    Richardson's extrapolation of N = 8 and 16 links (error ∝ 1/N²).
    """
    def case(coupled):
        return make_case("impactc_sample.toml", beam={"inertia_ratio": 1.0},
                         torque={"amplitude_N_m": 3.0, "pulse_duration_s": 0.05, "zero_fraction": 0.0},
                         model={"gravity_m_s2": 0.0, "n_modes": 4, "coupled": coupled},
                         initial={"theta_rad": 0.5}, time={"end_s": 0.2, "output_step_s": 2e-4},
                         output={"response_point_m": 0.53}, solver={"rtol": 1e-10, "atol": 1e-13})

    linear, coupled = simulate(case(False)), simulate(case(True))
    chains = {N: RigidLinkChain.from_case(case(False), N).simulate(case(False), linear.t) for N in (8, 16)}
    theta = (4.0 * chains[16].theta - chains[8].theta) / 3.0
    tip = (4.0 * chains[16].tip_deflection - chains[8].tip_deflection) / 3.0
    return theta, tip, linear, coupled


def test_spin_up_is_a_large_deflection(spin_up):
    theta, tip, linear, coupled = spin_up
    assert 0.09 < np.max(np.abs(tip)) / 0.53 < 0.10
    assert np.ptp(theta) > 0.5


def test_coupled_model_follows_the_chain_hub_angle(spin_up):
    """max |θ_modal − θ_chain|: linear 2.0e-4 rad, coupled 2–4e-5 rad (chain reference
    uncertain by ~3e-5 rad, modal truncation converged at 4 modes)."""
    theta, tip, linear, coupled = spin_up
    d_lin = np.max(np.abs(linear.theta - theta))
    d_cpl = np.max(np.abs(coupled.theta - theta))
    assert 1.6e-4 < d_lin < 2.6e-4
    assert d_cpl < 6e-5
    assert d_cpl < 0.3 * d_lin


def test_tip_deflection_matches_the_chain(spin_up):
    """max |w_tip,modal − w_tip,chain|: both models ≈ 0.3 % of the 51-mm peak deflection,
    the coupled one no worse."""
    theta, tip, linear, coupled = spin_up
    d_lin = np.max(np.abs(linear.model.deflection(linear.y) - tip))
    d_cpl = np.max(np.abs(coupled.model.deflection(coupled.y) - tip))
    assert d_lin < 2.5e-4 and d_cpl < 2.0e-4
    assert d_cpl < d_lin
