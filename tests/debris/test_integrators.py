"""Integrators of the particle state equations: accuracy, invariants, failures (docs/theory/debris.md)."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import eigh, expm

from impactdyn._errors import InputError
from impactdyn.debris import _particle as P
from impactdyn.debris import _tets as T
from impactdyn.debris._integrators import (
    AVERAGING, DEFAULT_STEPS_PER_PERIOD, INTEGRATORS, Failure, propagate, register_integrator)

ELASTIC = P.ParticleMaterial(mu=0.276, lam=0.56, rho_ref=2.703)                         # Al, η = ∞, ζ = 0
PLASTIC = P.ParticleMaterial(mu=0.276, lam=0.56, rho_ref=2.703, eta=0.05)               # ζ = 0
DISSIPATIVE = P.ParticleMaterial(mu=0.276, lam=0.56, rho_ref=2.703, eta=0.05, zeta=0.002)
METHODS = sorted(INTEGRATORS)
#: The integrators that follow the elastic vibration (the averaging ones have tests of their own,
#: tests/debris/test_slow_integrator.py).
FOLLOWING = sorted(set(INTEGRATORS) - AVERAGING)
SPLITTINGS = sorted(DEFAULT_STEPS_PER_PERIOD)
#: The step-size-controlled integrators (``eps``): those that follow the vibration and are no splitting.
ADAPTIVE = sorted(set(FOLLOWING) - set(SPLITTINGS))

# How each registered integrator is run against the DOP853 reference, and the stated
# tolerance on the relative end-state error (max over the H, F, Eₚ, c blocks) after 10
# periods 2π/ω̂. eps-controlled methods: 100·eps of global error. Splittings: the error
# of their order (test_splitting_global_error_has_its_order); with ζ > 0 both are second
# order, 4e-5 (verlet) and 2e-7 (splitting4) over 10 periods at 100 steps per period on
# this particle, so ≲ 1e-6 at 1000 and 100.
REFERENCE_RUNS = {
    "legacy": (dict(eps=1e-9), 1e-7),
    "rk45": (dict(eps=1e-9), 1e-7),
    "splitting4": (dict(steps_per_period=100), 1e-6),
    "verlet": (dict(steps_per_period=1000), 1e-6),
}


def cell_tet(spacing=(0.03175, 0.025, 0.02), which=1):
    """Vertices ``(4, 3)`` of one tetrahedron of a cell and its mass."""
    x = T.tet_vertices(np.zeros((1, 3)), np.array(spacing))[0, which]
    return x, ELASTIC.rho_ref * abs(T.signed_volume(x))


def omega_hat(J, m, mat):
    return np.sqrt(mat.reference_volume(m) * mat.stiffness_bound() / np.linalg.eigvalsh(J)[0])


def deforming_particle(mat, gradient=0.05, seed=11):
    """A cell tetrahedron with a random velocity gradient of size ``gradient``·ω̂."""
    x, m = cell_tet()
    rng = np.random.default_rng(seed)
    L = gradient * omega_hat(T.inertia_tensor(x, m), m, mat) * rng.standard_normal((3, 3))
    y0, J = T.initial_state(x, (x - x.mean(0)) @ L.T + np.array([0.0, 0.7, 0.0]), m)
    return y0, J, m


def reference_solution(y0, J, m, mat, t_end):
    V0 = mat.reference_volume(m)
    sol = solve_ivp(lambda t, y: P.state_rates(y, J, m, V0, mat), (0.0, t_end), y0,
                    method="DOP853", rtol=1e-12, atol=1e-16 + 1e-14 * np.abs(y0))
    assert sol.status == 0
    return sol.y[:, -1]


def relative_error(y, ref):
    return max(np.abs(y[s] - ref[s]).max() / np.abs(ref[s]).max()
               for s in (P.H_SLICE, P.F_SLICE, P.EP_SLICE, P.C_SLICE))


def linear_modes(J, V0, mat):
    """ω² and M-orthonormal mode shapes of the system linearised about F = I, Eₚ = 0.

    U ≈ V₀[μ |dev sym dF|² + ½K_b (tr dF)²] gives the stiffness K, T = ½ tr(Ḟ J Ḟᵀ)
    the mass M = I ⊗ J, both on dF flattened row-major.
    """
    basis = np.eye(9).reshape(9, 3, 3)

    def devsym(A):
        s = 0.5 * (A + A.T)
        return s - np.trace(s) / 3 * np.eye(3)

    K = V0 * np.array([[2 * mat.mu * np.sum(devsym(a) * devsym(b))
                        + mat.bulk_modulus * np.trace(a) * np.trace(b) for b in basis] for a in basis])
    M = np.kron(np.eye(3), J)
    w2, phi = eigh(K, M)
    return K, M, w2, phi


def sampled_frequency(q, dt):
    """ω of q_j = A sin(ω j dt + φ) from q_{j+1} + q_{j−1} = 2 cos(ω dt) q_j (least squares)."""
    cos_wdt = np.sum(q[1:-1] * (q[2:] + q[:-2])) / (2 * np.sum(q[1:-1] ** 2))
    return np.arccos(cos_wdt) / dt


def copies(y0, J, m, n):
    return np.repeat(y0[None], n, 0), np.repeat(J[None], n, 0), np.full(n, m)


# --- the registry ---------------------------------------------------------------


def test_registry():
    assert {"legacy", "rk45", "verlet"} <= set(INTEGRATORS)
    assert set(REFERENCE_RUNS) == set(FOLLOWING), "state a reference tolerance for every integrator"
    assert {run[0] for run in ORDER_RUNS.values()} == set(SPLITTINGS), "state the order of every splitting"
    with pytest.raises(ValueError, match="already registered"):
        register_integrator("verlet")(lambda batch, control: None)
    y0, J, m = deforming_particle(ELASTIC)
    with pytest.raises(ValueError, match="unknown integrator"):
        propagate(y0[None], J[None], np.array([m]), 1.0, ELASTIC, method="euler")


# --- accuracy ---------------------------------------------------------------------


@pytest.mark.parametrize("method", FOLLOWING)
def test_matches_tight_reference(method):
    y0, J, m = deforming_particle(DISSIPATIVE)
    period = 2 * np.pi / omega_hat(J, m, DISSIPATIVE)
    t_end = np.array([10.0, 7.0, 3.0]) * period
    refs = [reference_solution(y0, J, m, DISSIPATIVE, t) for t in t_end]
    kwargs, tol = REFERENCE_RUNS[method]
    y, stats = propagate(*copies(y0, J, m, 3), t_end, DISSIPATIVE, method=method, **kwargs)
    np.testing.assert_array_equal(stats.code, Failure.OK)
    np.testing.assert_array_equal(stats.t_reached, t_end)
    for k in range(3):
        assert relative_error(y[k], refs[k]) < tol, (method, k, relative_error(y[k], refs[k]))
        assert np.abs(refs[k][P.EP_SLICE]).max() > 1e-3        # plastic flow did happen
        Ep = y[k, P.EP_SLICE].reshape(3, 3)
        assert abs(np.trace(Ep)) <= 1e-12 * max(1.0, np.abs(Ep).max())


#: The global order each splitting integrator shows, with the steps per period that show it.
ORDER_RUNS = {
    "verlet": ("verlet", DISSIPATIVE, [100.0, 200, 400, 800], 2),
    "splitting4": ("splitting4", PLASTIC, [6.0, 12, 24, 48], 4),                # B is exact with plastic relaxation
    "splitting4-viscous": ("splitting4", DISSIPATIVE, [12.0, 24, 48, 96], 2),  # the viscous half steps are Strang's
}


@pytest.mark.parametrize("method, material, spp, order", list(ORDER_RUNS.values()), ids=list(ORDER_RUNS))
def test_splitting_global_error_has_its_order(method, material, spp, order):
    y0, J, m = deforming_particle(material)
    t_end = 5 * 2 * np.pi / omega_hat(J, m, material)
    ref = reference_solution(y0, J, m, material, t_end)
    errors = [relative_error(propagate(y0[None], J[None], np.array([m]), t_end, material, method=method,
                                       steps_per_period=s)[0][0], ref) for s in spp]
    slope = np.polyfit(np.log(1 / np.array(spp)), np.log(errors), 1)[0]
    assert abs(slope - order) < 0.1, (errors, slope)


@pytest.mark.parametrize("method", FOLLOWING)
def test_small_vibrations_have_the_linearised_frequencies(method):
    """Each mode of the linearised system, excited alone at 1e-5 strain, vibrates at its ω.

    Sampled every h = 1/10 of the fastest period. verlet is run with that step,
    where its frequency is the leapfrog's 2/h·arcsin(ωh/2) (0.15 % to 1.6 % above
    ω); splitting4 with h/16 (fourth order: its frequency error is below 1e-6); the adaptive methods at tight tolerance (eps is absolute on F ≈ I, so
    a tiny vibration needs a tiny eps). The estimate carries a bias linear in the
    amplitude (nonlinear harmonics; 3e-7 for the slowest mode at 1e-5, 3e-6 at 1e-4).
    """
    x, m = cell_tet()
    J = T.inertia_tensor(x, m)
    V0 = ELASTIC.reference_volume(m)
    K, M, w2, phi = linear_modes(J, V0, ELASTIC)

    # K is the Hessian of the coded U at F = I (second differences)
    h = 1e-4
    basis = np.eye(9).reshape(9, 3, 3)
    U = lambda dF: P.stored_energy(np.eye(3) + dF, np.zeros((3, 3)), V0, ELASTIC)
    hess = np.array([[(U(h * (a + b)) - U(h * (a - b)) - U(h * (b - a)) + U(-h * (a + b))) / (4 * h * h)
                      for b in basis] for a in basis])
    np.testing.assert_allclose(hess, K, rtol=0, atol=1e-6 * np.abs(K).max())
    np.testing.assert_allclose(w2[:3], 0.0, atol=1e-10 * w2[-1])      # the three rotations
    assert np.all(np.diff(w2[3:]) > 1e-3 * w2[-1])                     # distinct, so modes separate
    assert np.sqrt(w2[-1]) <= omega_hat(J, m, ELASTIC)                  # ω̂, the step control's bound

    dt = 2 * np.pi / np.sqrt(w2[-1]) / 10
    n_samples = 80
    t = dt * np.arange(1, n_samples + 1)
    for k in range(3, 9):
        omega = np.sqrt(w2[k])
        shape = phi[:, k].reshape(3, 3) / np.abs(phi[:, k]).max()
        y0 = P.pack_state(1e-5 * omega * shape @ J, np.eye(3), np.zeros((3, 3)), np.zeros(3), np.zeros(3))
        if method == "verlet":
            y, stats = propagate(*copies(y0, J, m, n_samples), t, ELASTIC, method=method, dt=dt)
            expected = 2 / dt * np.arcsin(omega * dt / 2)
        elif method == "splitting4":
            y, stats = propagate(*copies(y0, J, m, n_samples), t, ELASTIC, method=method, dt=dt / 16)
            expected = omega
        else:
            y, stats = propagate(*copies(y0, J, m, n_samples), t, ELASTIC, method=method, eps=1e-12)
            expected = omega
        np.testing.assert_array_equal(stats.code, Failure.OK)
        q = (y[:, P.F_SLICE] - np.eye(3).reshape(9)) @ M @ phi[:, k]      # modal coordinate
        assert abs(sampled_frequency(np.concatenate([[0.0], q]), dt) / expected - 1) < 1e-6, (k, method)


# --- invariants -----------------------------------------------------------------------


def energy_error(y0, J, m, t, **kwargs):
    """Relative total-energy error at times ``t`` of copies of one particle (η = ∞, ζ = 0)."""
    V0 = ELASTIC.reference_volume(m)
    y, stats = propagate(*copies(y0, J, m, len(t)), t, ELASTIC, **kwargs)
    np.testing.assert_array_equal(stats.code, Failure.OK)
    E = P.total_energy(y, np.repeat(J[None], len(t), 0), np.full(len(t), m), V0, ELASTIC)
    return E / P.total_energy(y0, J, m, V0, ELASTIC) - 1


@pytest.mark.parametrize("method", SPLITTINGS)
def test_splitting_energy_has_no_secular_drift(method):
    """Over 1000 periods of the slowest mode the energy error of a splitting stays bounded.

    Drift measure: the least-squares linear trend of the error over the run,
    relative to its largest value. Bounded oscillation gives a small trend; the
    same measure sees the linear drift of a non-symplectic method (rk45 at a loose
    tolerance, whose error at this cost is of the same size).
    """
    y0, J, m = deforming_particle(ELASTIC, gradient=0.02, seed=3)
    y0[P.P_SLICE] = 0.0                                                  # internal energy only
    w2 = linear_modes(J, ELASTIC.reference_volume(m), ELASTIC)[2]
    t = np.linspace(0, 1000, 101)[1:] * 2 * np.pi / np.sqrt(w2[3])

    def trend(e):
        return abs(np.polyfit(t, e, 1)[0] * t[-1]) / np.abs(e).max()

    e = energy_error(y0, J, m, t, method=method)                         # default steps per period
    assert np.abs(e).max() < 1e-2
    assert trend(e) < 0.25, trend(e)
    e_rk = energy_error(y0, J, m, t, method="rk45", eps=1e-5)
    assert trend(e_rk) > 0.75, trend(e_rk)


@pytest.mark.parametrize("method, spp, order", [("verlet", [8.0, 16, 32, 64], 2),
                                                ("splitting4", [4.0, 8, 16, 32], 4)])
def test_splitting_energy_error_has_its_order(method, spp, order):
    y0, J, m = deforming_particle(ELASTIC, gradient=0.02, seed=3)
    y0[P.P_SLICE] = 0.0
    t = np.linspace(0.5, 50, 64) * 2 * np.pi / omega_hat(J, m, ELASTIC)
    errors = [np.abs(energy_error(y0, J, m, t, method=method, steps_per_period=s)).max() for s in spp]
    slope = np.polyfit(np.log(1 / np.array(spp)), np.log(errors), 1)[0]
    assert abs(slope - order) < 0.15, (errors, slope)


@pytest.mark.parametrize("method", METHODS)
def test_angular_momentum_is_conserved(method):
    """skew(H Fᵀ) is constant for any η, ζ; every flow of the splittings keeps it to rounding."""
    y0, J, m = deforming_particle(DISSIPATIVE)
    t_end = 10 * 2 * np.pi / omega_hat(J, m, DISSIPATIVE)
    y, stats = propagate(y0[None], J[None], np.array([m]), t_end, DISSIPATIVE, method=method, eps=1e-9)
    assert stats.code[0] == Failure.OK
    spin = lambda s: (lambda A: A - A.T)(s[P.H_SLICE].reshape(3, 3) @ s[P.F_SLICE].reshape(3, 3).T)
    drift = np.abs(spin(y[0]) - spin(y0)).max() / np.abs(spin(y0)).max()
    assert drift < (1e-12 if method in SPLITTINGS else 1e-7), drift


@pytest.mark.parametrize("method", METHODS)
def test_translation_keeps_F_identity(method):
    x, m = cell_tet()
    v = np.broadcast_to(np.array([0.1, 0.7, -0.2]), x.shape)
    y0, J = T.initial_state(x, v, m)
    y, stats = propagate(y0[None], J[None], np.array([m]), 12.5, DISSIPATIVE, method=method)
    assert stats.code[0] == Failure.OK
    np.testing.assert_array_equal(y[0, P.F_SLICE], np.eye(3).reshape(9))
    np.testing.assert_array_equal(y[0, P.H_SLICE], 0.0)
    np.testing.assert_array_equal(y[0, P.EP_SLICE], 0.0)
    np.testing.assert_allclose(y[0, P.C_SLICE], x.mean(0) + 12.5 * v[0], rtol=1e-14)


@pytest.mark.parametrize("method", FOLLOWING)
def test_spin_is_a_rotation_up_to_centrifugal_strain(method):
    """A regular tetrahedron (J = αI) set spinning at Ω about z turns by Ωt and strains only as Ω².

    Rigid rotation is not an exact motion of the affine particle: in the frame
    turning with it the spin is a centrifugal load f = Ω²α P_xy applied at t = 0
    (P_xy projects on the spin plane). Linearised, mode k (M-orthonormal φ_k)
    responds with q_k(t) = (φ_k·f/ω_k²)(1 − cos ω_k t), so every strain
    component stays below 2 Σ_k |φ_k·f|/ω_k² |sym φ_k|; the stretched body spins
    slower by a relative O(Ω²/ω²), so halving Ω quarters the error of the rotation.
    """
    a = 0.03
    x = a / np.sqrt(8) * np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1.0]])
    m = ELASTIC.rho_ref * abs(T.signed_volume(x))
    J = T.inertia_tensor(x, m)
    np.testing.assert_allclose(J, J[0, 0] * np.eye(3), atol=1e-14 * J[0, 0])
    _, M, w2, phi = linear_modes(J, ELASTIC.reference_volume(m), ELASTIC)
    w_hat = omega_hat(J, m, ELASTIC)
    rotation_errors = []
    for ratio in (1e-3, 5e-4):
        Omega = ratio * w_hat
        W = Omega * np.array([[0.0, -1, 0], [1, 0, 0], [0, 0, 0]])
        load = (Omega**2 * J[0, 0] * np.diag([1.0, 1, 0])).reshape(9)
        static = phi[:, 3:].T @ load / w2[3:]
        sym_shapes = np.abs(0.5 * (phi[:, 3:] + phi.reshape(3, 3, 9).transpose(1, 0, 2).reshape(9, 9)[:, 3:]))
        strain_bound = 2 * (sym_shapes @ np.abs(static)).max()

        y0 = P.pack_state(W @ J, np.eye(3), np.zeros((3, 3)), np.zeros(3), np.zeros(3))
        t = 1.0 / Omega
        y, stats = propagate(y0[None], J[None], np.array([m]), t, ELASTIC, method=method, eps=1e-10)
        assert stats.code[0] == Failure.OK
        F = y[0, P.F_SLICE].reshape(3, 3)
        strain = np.abs(0.5 * (F.T @ F - np.eye(3))).max()
        assert 0 < strain < 1.01 * strain_bound, (strain, strain_bound)
        u, _, vt = np.linalg.svd(F)
        rotation_errors.append(np.abs(u @ vt - expm(W * t)).max())
    assert rotation_errors[0] < 10 * ratio**2 * 4
    assert 3.5 < rotation_errors[0] / rotation_errors[1] < 4.5, rotation_errors


# --- failures -----------------------------------------------------------------------


@pytest.mark.parametrize("method", METHODS)
def test_bad_particles_are_reported_and_do_not_poison_others(method):
    y0, J, m = deforming_particle(DISSIPATIVE)
    t_end = 3 * 2 * np.pi / omega_hat(J, m, DISSIPATIVE)
    ys, Js, ms = copies(y0, J, m, 4)
    ys[1, P.F_SLICE] = np.diag([-1.0, 1.0, 1.0]).reshape(9)               # inverted
    ys[2, 4] = np.nan                                                    # NaN in H
    ys[3, P.F_SLICE] = np.diag([1.0, 1.0, 0.0]).reshape(9)                # flat: det F = 0
    alone, _ = propagate(y0[None], J[None], np.array([m]), t_end, DISSIPATIVE, method=method)
    y, stats = propagate(ys, Js, ms, t_end, DISSIPATIVE, method=method)
    np.testing.assert_array_equal(stats.code, [Failure.OK, Failure.INVERTED, Failure.NAN, Failure.INVERTED])
    assert stats.n_failed == 3
    assert stats.failure_counts() == {"INVERTED": 2, "NAN": 1}
    np.testing.assert_array_equal(y[0], alone[0])
    np.testing.assert_array_equal(y[1:], ys[1:])                          # returned as given
    np.testing.assert_array_equal(stats.t_reached, [t_end, 0, 0, 0])


@pytest.mark.parametrize("method", ADAPTIVE)
def test_step_underflow_is_reported(method):
    y0, J, m = deforming_particle(DISSIPATIVE)
    y, stats = propagate(y0[None], J[None], np.array([m]), 1.0, DISSIPATIVE, method=method, eps=1e-30)
    assert stats.code[0] == Failure.STEP_UNDERFLOW
    assert stats.rejected[0] > 0 and stats.t_reached[0] < 1.0
    assert np.all(np.isfinite(y))


@pytest.mark.parametrize("method", METHODS)
def test_step_budget_is_reported(method):
    y0, J, m = deforming_particle(DISSIPATIVE)
    y, stats = propagate(y0[None], J[None], np.array([m]), 1.0, DISSIPATIVE, method=method, max_steps=10)
    assert stats.code[0] == Failure.STEP_BUDGET
    assert stats.steps[0] + stats.rejected[0] == 10
    assert 0 < stats.t_reached[0] < 1.0
    # the returned state is the state at t_reached: c moved ballistically to it
    c0, v = y0[P.C_SLICE], y0[P.P_SLICE] / m
    np.testing.assert_allclose(y[0, P.C_SLICE], c0 + stats.t_reached[0] * v, rtol=1e-12)


def test_input_validation():
    """Bad particles are InputErrors naming the array, the first particle that breaks its rule and its value."""
    y0, J, m = deforming_particle(ELASTIC)
    args = (y0[None], J[None], np.array([m]))
    with pytest.raises(InputError, match=r"^propagate: t_end: particle 0 of 1 has -1.0: an end time must be"):
        propagate(*args, -1.0, ELASTIC)
    with pytest.raises(InputError, match=r"^propagate: J: particle 1 of 2 has \[-.*must be positive definite"):
        propagate(np.stack([y0, y0]), np.stack([J, -J]), np.array([m, m]), 1.0, ELASTIC)
    with pytest.raises(InputError, match=r"^propagate: phi: particle 0 of 1 has 1.0: a void fraction must lie"):
        propagate(*args, 1.0, ELASTIC, phi=1.0)
    with pytest.raises(InputError, match=r"^propagate: m: particle 0 of 1 has nan"):
        propagate(y0[None], J[None], np.array([np.nan]), 1.0, ELASTIC)
    with pytest.raises(InputError, match=r"^propagate: states: shape \(1, 30\)"):
        propagate(y0[None, :30], J[None], np.array([m]), 1.0, ELASTIC)
    with pytest.raises(InputError, match=r"^propagate: dt = 0.0: must be > 0"):
        propagate(*args, 1.0, ELASTIC, dt=0.0)
    y, stats = propagate(*args, 0.0, ELASTIC)
    np.testing.assert_array_equal(y, args[0])
    assert stats.code[0] == Failure.OK and stats.steps[0] == 0
