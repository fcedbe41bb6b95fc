"""The slow-manifold integrator ``slow`` (issue 13): steps far longer than the particles' vibration period."""

import json
import tomllib
from pathlib import Path

import numpy as np
import pytest
import tomli_w
from scipy.integrate import solve_ivp

from impactdyn.cli import main
from impactdyn.debris import _particle as P
from impactdyn.debris import _tets as T
from impactdyn.debris import propagate

ELASTIC = P.ParticleMaterial(mu=0.276, lam=0.56, rho_ref=2.703)            # η = ∞, ζ = 0
PLASTIC = P.ParticleMaterial(mu=0.276, lam=0.56, rho_ref=2.703, eta=1.0)   # DC3D's ELDATA η
EXAMPLE = Path(__file__).parents[2] / "examples" / "debris" / "shell_cloud.toml"


def particle(mat, gradient, seed=5):
    """A cell tetrahedron flying at 0.7 cm/µs with a random velocity gradient of std ``gradient`` (1/µs)."""
    x = T.tet_vertices(np.zeros((1, 3)), np.array([0.03175, 0.025, 0.02]))[0, 1]
    m = mat.rho_ref * abs(T.signed_volume(x))
    L = gradient * np.random.default_rng(seed).standard_normal((3, 3))
    y0, J = T.initial_state(x, (x - x.mean(0)) @ L.T + np.array([0.0, 0.7, 0.0]), m)
    return y0, J, m


def omega_hat(J, m, mat):
    return np.sqrt(mat.reference_volume(m) * mat.stiffness_bound() / np.linalg.eigvalsh(J)[0])


def slow(y0, J, m, mat, t, **options):
    y, stats = propagate(y0[None], J[None], m, np.array([t]), mat, method="slow", **options)
    assert stats.code[0] == 0
    return y[0], int(stats.steps[0])


def angular_momentum(y):
    H, F, _, _, _ = P.unpack_state(y)
    A = H @ F.T - F @ H.T
    return np.array([A[2, 1], A[0, 2], A[1, 0]])


def test_translation_is_exact():
    y0, J, m = particle(PLASTIC, 0.0)
    y0[P.EP_SLICE] = 0.01 * np.array([1.0, 0.2, 0.0, 0.2, -0.5, 0.1, 0.0, 0.1, -0.5])  # a plastic strain it keeps
    y, _ = slow(y0, J, m, PLASTIC, 15.0)
    H, F, Ep, p, c = P.unpack_state(y)
    _, F0, Ep0, p0, c0 = P.unpack_state(y0)
    assert np.all(p == p0) and np.all(Ep == Ep0)
    np.testing.assert_allclose(c, c0 + 15.0 * p0 / m, rtol=1e-15, atol=0)
    # the stress-free stretch of Eₚ: E' = Eₚ and det F = 1, at rest
    C = F.T @ F
    np.testing.assert_allclose(0.5 * (C - np.trace(C) / 3 * np.eye(3)), Ep0, atol=1e-15)
    assert abs(np.linalg.det(F) - 1) < 1e-14 and np.all(H == 0)


def test_momenta_are_conserved():
    y0, J, m = particle(PLASTIC, 0.5)
    y, _ = slow(y0, J, m, PLASTIC, 15.0)
    assert np.all(y[P.P_SLICE] == y0[P.P_SLICE])
    np.testing.assert_allclose(angular_momentum(y), angular_momentum(y0), rtol=1e-12)


def test_energy_stays_bounded_over_10000_steps_of_omega_h_50():
    y0, J, m = particle(ELASTIC, 2.0)  # spinning at ~1/µs: ~0.2 rad a step, an energy error to see
    dt = 50.0 / omega_hat(J, m, ELASTIC)
    steps = np.unique(np.geomspace(1, 10_000, 60).astype(int))
    V0 = ELASTIC.reference_volume(m)
    translation = 0.5 * y0[P.P_SLICE] @ y0[P.P_SLICE] / m

    def internal(y):  # energy of the deformation and rotation: T + U less the translation's
        return P.total_energy(y, J, m, V0, ELASTIC) - translation

    E = []
    for k in steps:
        y, n = slow(y0, J, m, ELASTIC, k * dt, dt=dt)
        assert n == k
        E.append(internal(y))
    E = np.array(E)
    # the first step drops the vibration: what is left is the rigid rotation's ½ ω·ℓ,
    # ω = (tr M I − M)⁻¹ ℓ with M = J (F(0) = I)
    ell = angular_momentum(y0)
    rigid = 0.5 * ell @ np.linalg.solve(np.trace(J) * np.eye(3) - J, ell)
    assert rigid < 0.5 * internal(y0)
    # after it the energy error is bounded and does not drift: no larger in the last
    # thousands of steps than in the first hundred
    error = np.abs(E - rigid) / rigid
    assert error.max() < 1e-7, error.max()
    assert error[steps > 1000].max() < 2 * error[steps < 100].max(), error


def test_time_averaged_deformation_follows_dop853_with_plastic_flow():
    y0, J, m = particle(PLASTIC, 0.1)
    V0 = PLASTIC.reference_volume(m)
    window = 0.15  # µs: about five periods of the fastest vibration (2π/ω̂ = 0.03 µs), 0.03 rad of rotation
    sol = solve_ivp(lambda t, y: P.state_rates(y, J, m, V0, PLASTIC), (0.0, 15.0 + window), y0,
                    method="DOP853", rtol=1e-10, atol=1e-18, dense_output=True)
    assert sol.status == 0
    for t in (1.0, 5.0, 10.0, 15.0):
        F_mean = sol.sol(np.linspace(t - window / 2, t + window / 2, 2001))[P.F_SLICE].mean(axis=1)
        y, n = slow(y0, J, m, PLASTIC, t)
        assert n < 4 * t  # steps set by the slow rotation, not by the vibration (~33 periods per µs)
        error = np.linalg.norm(y[P.F_SLICE] - F_mean) / np.linalg.norm(F_mean)
        assert error < 1e-3, (t, error)


def case_file(tmp_path, **changes) -> Path:
    """The shipped debris example on a coarse grid (a few hundred particles), with ``changes``."""
    data = tomllib.loads(EXAMPLE.read_text())
    data["grid"]["shell"]["cell_size_cm"] = 0.25
    data["wall"]["nodes"] = [17, 3, 33]
    data["integrator"] = {**data.get("integrator", {}), **changes}
    path = tmp_path / "case.toml"
    path.write_text(tomli_w.dumps(data))
    return path


def test_debris_run_with_slow(tmp_path):
    out = tmp_path / "run"
    assert main(["debris", "run", str(case_file(tmp_path, method="slow")), "-o", str(out)]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["integrator"]["method"] == "slow" and s["n_arrived"] == s["n_particles"] > 100
    np.testing.assert_allclose(s["momentum_deposited"], s["momentum_in"], rtol=1e-12)


@pytest.mark.parametrize("changes, words", [
    ({"method": "slow_manifold"}, "integrator.method"),
    ({"method": "slow", "steps_per_period": 0.0}, "integrator.steps_per_period"),
    ({"method": "slow", "steps_per_period": -48.0}, "integrator.steps_per_period"),
])
def test_bad_integrator_settings_exit_2(tmp_path, capsys, changes, words):
    out = tmp_path / "out"
    assert main(["debris", "run", str(case_file(tmp_path, **changes)), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert words in err and "Traceback" not in err and not out.exists()
