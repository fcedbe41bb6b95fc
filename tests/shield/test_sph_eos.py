"""Material library, Mie–Grüneisen EOS and the deviatoric-stress kernels of the SPH shield stage."""

import numpy as np
import pytest

from impactdyn._errors import InputError
from impactdyn.materials import AL_6061_T6, MATERIALS, get_material
from impactdyn.constitutive import _eos, _strength
from impactdyn.units import cm_us_to_km_s, mbar_to_gpa

VOIGT = [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (2, 0)]


def eos(mat):
    return mat.rho0, mat.c0, mat.s, mat.gamma0


def to_matrix(s6):
    m = np.zeros((3, 3))
    for k, (a, b) in enumerate(VOIGT):
        m[a, b] = m[b, a] = s6[k]
    return m


def test_registry_and_steinberg_numbers():
    al = get_material("Al 6061-T6")
    assert al is get_material("al_6061_t6") is AL_6061_T6 is MATERIALS["al6061-t6"]
    assert (al.rho0, cm_us_to_km_s(al.c0), al.s, al.gamma0) == pytest.approx((2.703, 5.24, 1.40, 1.97))
    assert mbar_to_gpa(al.shear_modulus) == pytest.approx(27.6) and mbar_to_gpa(al.yield_stress) == pytest.approx(0.29)
    al7 = get_material("al7075-t6")
    assert (al7.rho0, cm_us_to_km_s(al7.c0), al7.s, al7.gamma0) == pytest.approx((2.803, 5.20, 1.36, 2.20))
    assert all(m.source for m in MATERIALS.values())
    with pytest.raises(InputError, match="choose one of al6061-t6, al2024-t4"):
        get_material("unobtainium")


def test_planar_hugoniot_values():
    """Symmetric Al 6061-T6 impact at 2 km/s: up = 1 km/s, Us = 6.64 km/s, p = 17.9 GPa."""
    us, p, rho = AL_6061_T6.hugoniot(0.1)
    assert cm_us_to_km_s(us) == pytest.approx(6.64)
    assert mbar_to_gpa(p) == pytest.approx(17.95, abs=0.01)
    assert rho == pytest.approx(2.703 * 6.64 / 5.64)


@pytest.mark.parametrize("name", sorted(MATERIALS))
def test_reference_state_and_hugoniot_consistency(name):
    mat = MATERIALS[name]
    assert _eos.pressure(mat.rho0, 0.0, *eos(mat)) == 0.0
    assert _eos.sound_speed(mat.rho0, 0.0, *eos(mat)) == pytest.approx(mat.c0, rel=1e-14)
    for up in (0.02, 0.1, 0.35, 0.6):
        us, p_h, rho_h = mat.hugoniot(up)
        e_h = 0.5 * up * up  # Rankine–Hugoniot energy: e − e₀ = ½ p (V₀ − V) = ½ up²
        assert _eos.pressure(rho_h, e_h, *eos(mat)) == pytest.approx(p_h, rel=1e-12)


def test_tension_branch_and_sound_speed():
    mat = AL_6061_T6
    k = mat.rho0 * mat.c0**2
    rho = 0.99 * mat.rho0
    assert _eos.pressure(rho, 0.01, *eos(mat)) == pytest.approx(k * (rho / mat.rho0 - 1) + mat.gamma0 * mat.rho0 * 0.01)
    # c² = (∂p/∂ρ)_s: differentiate along an isentrope de = p/ρ² dρ
    for rho, e in [(3.4, 0.02), (2.6, 0.001), (2.9, 0.0)]:
        p = _eos.pressure(rho, e, *eos(mat))
        d = 1e-6
        dp = (_eos.pressure(rho + d, e + p / rho**2 * d, *eos(mat))
              - _eos.pressure(rho - d, e - p / rho**2 * d, *eos(mat))) / (2 * d)
        assert _eos.sound_speed(rho, p, *eos(mat)) == pytest.approx(np.sqrt(dp), rel=1e-6)


def test_jaumann_rate_matches_matrix_form():
    rng = np.random.default_rng(1)
    S = rng.standard_normal(6)
    S[2] = -S[0] - S[1]
    L = rng.standard_normal((1, 3, 3))
    G = 0.276
    dS, rate = _strength.jaumann_rate(*S, L, 0, G)
    D, W = 0.5 * (L[0] + L[0].T), 0.5 * (L[0] - L[0].T)
    Dd = D - np.trace(D) / 3 * np.eye(3)
    want = 2 * G * Dd + W @ to_matrix(S) - to_matrix(S) @ W
    np.testing.assert_allclose(to_matrix(dS), want, rtol=1e-13, atol=1e-13)
    assert rate == pytest.approx(np.sqrt(2 / 3 * np.sum(Dd * Dd)))
    assert sum(dS[:3]) == pytest.approx(0.0, abs=1e-13)


def test_radial_return():
    G, Y = 0.276, 0.0029
    S = np.array([[0.004, -0.001, -0.003, 0.002, 0.0, -0.001]])
    seq = np.sqrt(1.5 * np.sum(to_matrix(S[0]) ** 2))
    deps = _strength.radial_return(S, 0, Y, G)
    assert deps == pytest.approx((seq - Y) / (3 * G))
    assert _strength.von_mises(S, 0) == pytest.approx(Y)
    assert _strength.radial_return(S, 0, Y, G) == 0.0


def test_johnson_cook_flow_stress():
    params = _eos.pack_materials([AL_6061_T6])
    jc = AL_6061_T6.johnson_cook
    assert _strength.flow_stress(params, 0, False, 0.5, 1.0, 900.0) == AL_6061_T6.yield_stress
    assert _strength.flow_stress(params, 0, True, 0.0, 0.0, 294.0) == pytest.approx(jc.A)
    y = _strength.flow_stress(params, 0, True, 0.1, 1e-2, 500.0)  # 1e4 /s
    tstar = (500.0 - 294.0) / (925.0 - 294.0)
    assert y == pytest.approx((jc.A + jc.B * 0.1**jc.n) * (1 + jc.C * np.log(1e4)) * (1 - tstar**jc.m))
    assert _strength.flow_stress(params, 0, True, 0.1, 1e-2, 2000.0) == 0.0
    # the unyielded state skips pow(): continuous into εₚ > 0, and a negative εₚ counts as 0
    assert _strength.flow_stress(params, 0, True, 1e-300, 0.0, 294.0) == pytest.approx(jc.A, rel=1e-12)
    assert _strength.flow_stress(params, 0, True, -1e-3, 0.0, 294.0) == _strength.flow_stress(params, 0, True, 0.0, 0.0, 294.0)


def test_artificial_stress_is_the_tensile_part():
    rng = np.random.default_rng(5)
    eps, rho = 0.3, 2.7
    for _ in range(20):
        S = rng.standard_normal((1, 6)) * 0.01
        S[0, 2] = -S[0, 0] - S[0, 1]
        p = rng.uniform(-0.01, 0.01)
        R = np.zeros((1, 6))
        tensile = _strength.artificial_stress(S, p, rho, eps, 0, R, np.zeros((1, 3, 3)), np.zeros((1, 3, 3)))
        lam, vec = np.linalg.eigh(to_matrix(S[0]) - p * np.eye(3))
        want = -eps / rho**2 * (vec * np.maximum(lam, 0)) @ vec.T
        np.testing.assert_allclose(to_matrix(R[0]), want, atol=1e-15)
        assert tensile == (lam.max() > 0)


def test_temperature_estimate():
    """T_room at the reference state, continuous at μ = 0, and plausible shock temperatures of aluminium."""
    params = _eos.pack_materials([AL_6061_T6])
    assert _eos.temperature(AL_6061_T6.rho0, 0.0, params, 0) == _eos.T_ROOM
    assert _eos.temperature(AL_6061_T6.rho0 * (1 + 1e-9), 0.0, params, 0) == pytest.approx(_eos.T_ROOM, rel=1e-6)
    # the cold energy is the isentrope: e_s ≈ ½ c0² μ² for small μ
    mu = _eos.MU_COLD / (_eos.N_COLD - 1)
    assert params[0, _eos.N_PARAMS + 1] == pytest.approx(0.5 * AL_6061_T6.c0**2 * mu**2, rel=0.01)
    # Hugoniot states at 18, 43 and 96 GPa: a few hundred to a few thousand kelvin, increasing
    temps = [_eos.temperature(AL_6061_T6.hugoniot(up)[2], 0.5 * up * up, params, 0) for up in (0.1, 0.2, 0.35)]
    assert 400 < temps[0] < 600 and temps[0] < temps[1] < temps[2] < 5000
    # expanded (failed) material: T_room + e/c_v
    assert _eos.temperature(1.0, 0.01, params, 0) == pytest.approx(_eos.T_ROOM + 0.01 / AL_6061_T6.specific_heat)


def test_material_validation():
    import dataclasses
    with pytest.raises(InputError, match="c0"):
        dataclasses.replace(AL_6061_T6, c0=-1.0)
    with pytest.raises(InputError, match="spall_strength"):
        dataclasses.replace(AL_6061_T6, spall_strength=0.0)
    jc = AL_6061_T6.johnson_cook
    for field, bad in (("n", 0.0), ("m", -1.0), ("B", -0.1), ("reference_strain_rate", 0.0), ("t_melt", 200.0)):
        with pytest.raises(InputError, match=f"JohnsonCook.{field}"):
            dataclasses.replace(jc, **{field: bad})
    assert _eos.pack_materials([dataclasses.replace(AL_6061_T6, spall_strength=None)])[0, _eos.P_SPALL] == np.inf


@pytest.mark.parametrize("name", [m.name for m in MATERIALS.values() if m.johnson_cook is not None])
@pytest.mark.parametrize("m_exponent", [None, 0.8])
def test_flow_stress_floor_is_a_lower_bound(name, m_exponent):
    """temperature_bound ≥ temperature and flow_stress_floor(T_bound) ≤ flow_stress over random states
    (compressed, expanded, heated, hardened, fast and slow), for m as given and for an m < 1."""
    params = _eos.pack_materials([get_material(name)])
    if m_exponent is not None:
        params[0, _eos.JC_M] = m_exponent
    rng = np.random.default_rng(11)
    rho0 = params[0, _eos.RHO0]
    for _ in range(2000):
        rho = rho0 * rng.uniform(0.7, 1.8)
        e = rng.choice([0.0, rng.uniform(0.0, 3e-3), rng.uniform(-1e-4, 1e-2)])
        eps_p = rng.choice([0.0, rng.uniform(0.0, 2.0)])
        rate = rng.choice([0.0, 10.0 ** rng.uniform(-9, 1)])
        T = _eos.temperature(rho, e, params, 0)
        T_up = _eos.temperature_bound(rho, e, params, 0)
        assert T_up >= T
        assert _strength.flow_stress_floor(params, 0, T_up) <= _strength.flow_stress(params, 0, True, eps_p, rate, T)
    # tight where the material is cold and at rest: the floor is A itself
    assert _strength.flow_stress_floor(params, 0, _eos.temperature_bound(rho0, 0.0, params, 0)) == params[0, _eos.JC_A]
