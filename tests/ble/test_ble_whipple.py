"""NASA JSC Whipple-shield and Cour-Palais single-wall ballistic limit equations."""

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from impactdyn import InputError
from impactdyn.ble import (
    BallisticLimitCurve,
    FailureMode,
    Regime,
    SingleWall,
    WhippleShield,
    ballistic_limit_curve,
    critical_diameter,
    normal_velocity,
    penetration_depth,
    perforates,
    rear_wall,
    regime,
    regime_boundaries,
    single_wall_ballistic_limit_curve,
    single_wall_critical_diameter,
    single_wall_perforates,
)


def table2(spacing_cm=10.0, bumper_density=2.7):
    """The report's Table 2 shield: Al bumper 0.127 cm, wall 0.3175 cm, σ = 40 ksi."""
    return WhippleShield(bumper_thickness_cm=0.127, wall_thickness_cm=0.3175, spacing_cm=spacing_cm,
                         wall_yield_ksi=40.0, bumper_density_g_cm3=bumper_density)


# ---------------------------------------------------------------- issue 4 acceptance


@pytest.mark.parametrize("bumper_density", [2.7, 2.713])
def test_issue_acceptance_values(bumper_density):
    s = table2(10.0, bumper_density)
    assert abs(critical_diameter(s, 7.0, 25.0, 2.7) - 0.521) <= 1e-3
    assert abs(critical_diameter(s, 10.0, 25.0, 2.7) - 0.482) <= 1e-3
    # 7 km/s at 25° is V cos θ = 6.34 km/s: the shatter regime, not the hypervelocity one
    assert regime(7.0, 25.0) is Regime.SHATTER
    assert regime(10.0, 25.0) is Regime.HYPERVELOCITY


def test_pinned_values_both_spacings():
    assert critical_diameter(table2(10.0), [7.0, 10.0], 25.0, 2.7) == pytest.approx(
        [0.5212670130438949, 0.4822954880071449], rel=1e-12)
    assert critical_diameter(table2(10.0, 2.713), [7.0, 10.0], 25.0, 2.7) == pytest.approx(
        [0.5210114474309626, 0.4820381576871554], rel=1e-12)
    # the report's geometry, 10.16 cm from bumper back to wall front: 3e-3 cm above the
    # issue's numbers, which are therefore for S = 10 cm
    d = critical_diameter(table2(10.16), [7.0, 10.0], 25.0, 2.7)
    assert d == pytest.approx([0.523808111131298, 0.4848541326403335], rel=1e-12)
    assert abs(d[0] - 0.521) > 2e-3


@pytest.mark.parametrize("spacing", [10.0, 10.16])
@pytest.mark.parametrize("bumper_density", [2.7, 2.713])
@pytest.mark.parametrize("velocity, diameter, perforated", [
    (7.0, 0.575, True), (7.0, 0.475, False), (10.0, 0.530, True), (10.0, 0.430, False)])
def test_table2_verdicts(spacing, bumper_density, velocity, diameter, perforated):
    assert perforates(table2(spacing, bumper_density), diameter, velocity, 25.0, 2.7) is perforated


def test_published_rounded_shatter_form_agrees():
    """The handbook prints (W2) with 1.248 = 0.6·3^{2/3} and 1.071 = 3.918·7^{-2/3}."""
    s = table2()
    theta = np.radians(25.0)
    v = np.linspace(3.4, 7.7, 30)
    vn = v * np.cos(theta)
    resist = s.wall_thickness_cm * (s.wall_yield_ksi / 40) ** 0.5 + s.bumper_thickness_cm
    published = ((resist / (1.248 * 2.7 ** 0.5 * np.cos(theta))) ** (18 / 19) * (1.75 - vn / 4)
                 + 1.071 * s.wall_thickness_cm ** (2 / 3) * 2.7 ** (-1 / 3) * 2.7 ** (-1 / 9)
                 * s.spacing_cm ** (1 / 3) * (s.wall_yield_ksi / 70) ** (1 / 3) * (vn / 4 - 0.75))
    assert critical_diameter(s, v, 25.0, 2.7) == pytest.approx(published, rel=5e-4)
    assert published[np.argmin(abs(v - 7.0))] != critical_diameter(s, 7.0, 25.0, 2.7)


# ------------------------------------------------------------- hand calculations, θ = 0


def test_normal_incidence_by_hand():
    s = table2()  # t_b 0.127, t_w 0.3175, S 10, σ 40, ρ_b = ρ_p = 2.7
    # (W1), V = 2: (0.3175·1 + 0.127) / (0.6 · 2.7^0.5 · 2^(2/3)) = 0.4445 / 1.5650197 = 0.28402199
    #              0.28402199^(18/19) = 0.30347500
    assert critical_diameter(s, 2.0) == pytest.approx(0.303475, abs=1e-6)
    # (W3), V = 10: 3.918 · 0.3175^(2/3) · 2.7^(-4/9) · 10^(-2/3) · 10^(1/3) · (40/70)^(1/3)
    #             = 3.918 · 0.46540297 · 0.64310631 · 0.46415888 · 0.82982653 = 0.45167946
    assert critical_diameter(s, 10.0) == pytest.approx(0.451679, abs=1e-6)
    # regime ends: (W1) at 3 km/s = 0.23491318, (W3) at 7 km/s = 0.57292571
    assert critical_diameter(s, 3.0) == pytest.approx(0.234913, abs=1e-6)
    assert critical_diameter(s, 7.0) == pytest.approx(0.572926, abs=1e-6)
    # (W2), V = 5 is half way: (0.23491318 + 0.57292571)/2 = 0.40391945
    assert critical_diameter(s, 5.0) == pytest.approx(0.403919, abs=1e-6)


def test_regime_thresholds_and_boundaries():
    assert regime(3.0) is Regime.BALLISTIC
    assert regime(3.0 + 1e-9) is Regime.SHATTER
    assert regime(7.0 - 1e-9) is Regime.SHATTER
    assert regime(7.0) is Regime.HYPERVELOCITY
    lo, hi = regime_boundaries(60.0)
    assert (lo, hi) == pytest.approx((6.0, 14.0))
    assert list(regime([5.9, 6.1, 13.9, 14.1], 60.0)) == [
        Regime.BALLISTIC, Regime.SHATTER, Regime.SHATTER, Regime.HYPERVELOCITY]
    assert normal_velocity(10.0, 60.0) == pytest.approx(5.0)
    assert str(Regime.SHATTER) == "shatter"


# ------------------------------------------------------------------ properties

shields = st.builds(
    WhippleShield,
    bumper_thickness_cm=st.floats(0.02, 0.5),
    wall_thickness_cm=st.floats(0.05, 1.0),
    spacing_cm=st.floats(2.0, 40.0),
    wall_yield_ksi=st.floats(10.0, 80.0),
    bumper_density_g_cm3=st.floats(1.5, 8.0),
)
angles = st.floats(0.0, 75.0)
densities = st.floats(0.5, 8.0)


@settings(max_examples=60, deadline=None)
@given(shield=shields, theta=angles, rho=densities)
def test_continuous_at_regime_boundaries(shield, theta, rho):
    for vb in regime_boundaries(theta):
        below, at, above = critical_diameter(shield, vb * np.array([1 - 1e-12, 1.0, 1 + 1e-12]), theta, rho)
        assert below == pytest.approx(at, rel=1e-9)
        assert above == pytest.approx(at, rel=1e-9)


@settings(max_examples=60, deadline=None)
@given(shield=shields, theta=angles, rho=densities)
def test_monotonic_in_velocity_within_regimes(shield, theta, rho):
    lo, hi = regime_boundaries(theta)
    ballistic = critical_diameter(shield, np.linspace(0.2 * lo, lo, 20), theta, rho)
    hyper = critical_diameter(shield, np.linspace(hi, 3 * hi, 20), theta, rho)
    assert np.all(np.diff(ballistic) < 0)
    assert np.all(np.diff(hyper) < 0)
    shatter = critical_diameter(shield, np.linspace(lo, hi, 20), theta, rho)
    # linear in V between the two regime ends
    assert np.diff(shatter, 2) == pytest.approx(np.zeros(18), abs=1e-12)


def _with(shield, **changes):
    return WhippleShield(**(shield.as_dict() | changes))


@settings(max_examples=60, deadline=None)
@given(shield=shields, theta=angles, rho=densities, factor=st.floats(1.05, 3.0))
def test_monotonic_in_shield_parameters(shield, theta, rho, factor):
    lo, hi = regime_boundaries(theta)
    v = np.array([0.5 * lo, 0.5 * (lo + hi), 1.5 * hi])  # one point in each regime
    d = critical_diameter(shield, v, theta, rho)
    # thicker wall, stronger wall, lighter projectile: larger d_c everywhere
    assert np.all(critical_diameter(_with(shield, wall_thickness_cm=shield.wall_thickness_cm * factor), v, theta, rho) > d)
    assert np.all(critical_diameter(_with(shield, wall_yield_ksi=shield.wall_yield_ksi * factor), v, theta, rho) > d)
    assert np.all(critical_diameter(shield, v, theta, rho * factor) < d)
    # spacing matters above the ballistic regime only; the bumper only up to the shatter regime
    wider = critical_diameter(_with(shield, spacing_cm=shield.spacing_cm * factor), v, theta, rho)
    assert wider[0] == pytest.approx(d[0], rel=1e-14) and np.all(wider[1:] > d[1:])
    thicker_bumper = critical_diameter(_with(shield, bumper_thickness_cm=shield.bumper_thickness_cm * factor),
                                       v, theta, rho)
    assert np.all(thicker_bumper[:2] > d[:2]) and thicker_bumper[2] == pytest.approx(d[2], rel=1e-14)


@settings(max_examples=60, deadline=None)
@given(shield=shields, rho=densities, theta=st.floats(0.0, 70.0), dtheta=st.floats(1.0, 15.0))
def test_obliquity_raises_dc_at_fixed_velocity_in_ballistic_and_hypervelocity(shield, rho, theta, dtheta):
    lo0, _ = regime_boundaries(0.0)
    _, hi1 = regime_boundaries(theta + dtheta)
    for v in (0.5 * lo0, 1.5 * hi1):  # same regime at both angles
        assert critical_diameter(shield, v, theta + dtheta, rho) > critical_diameter(shield, v, theta, rho)


@settings(max_examples=40, deadline=None)
@given(shield=shields,
       v=st.lists(st.floats(0.1, 30.0), min_size=1, max_size=12),
       theta=angles, rho=densities)
def test_vectorised_equals_scalar(shield, v, theta, rho):
    vec = critical_diameter(shield, v, theta, rho)
    assert isinstance(vec, np.ndarray) and vec.shape == (len(v),)
    for vi, di in zip(v, vec):
        scalar = critical_diameter(shield, vi, theta, rho)
        assert isinstance(scalar, float)
        assert scalar == pytest.approx(di, rel=1e-14)  # SIMD and scalar pow may differ by an ulp
    regimes = regime(v, theta)
    assert [regime(vi, theta) for vi in v] == list(regimes)


def test_broadcasting_over_all_arguments():
    s = table2()
    v = np.array([2.0, 5.0, 10.0])[:, None]
    th = np.array([0.0, 25.0, 45.0])[None, :]
    d = critical_diameter(s, v, th, 2.7)
    assert d.shape == (3, 3)
    for i in range(3):
        for j in range(3):
            assert d[i, j] == pytest.approx(critical_diameter(s, float(v[i, 0]), float(th[0, j]), 2.7), rel=1e-14)
    assert critical_diameter(s, 7.0, 0.0, [1.0, 2.7]) == pytest.approx(
        [critical_diameter(s, 7.0, 0.0, 1.0), critical_diameter(s, 7.0, 0.0, 2.7)])


def test_ballistic_limit_curve():
    s = table2(10.16)
    c = ballistic_limit_curve(s, obliquity_deg=25.0)
    assert isinstance(c, BallisticLimitCurve)
    assert c.velocity_km_s[0] == 1.0 and c.velocity_km_s[-1] == 15.0
    lo, hi = c.regime_boundaries()
    assert lo in c.velocity_km_s and hi in c.velocity_km_s  # kinks are on the grid
    assert np.all(np.diff(c.velocity_km_s) > 0)
    assert c.critical_diameter_cm == pytest.approx(critical_diameter(s, c.velocity_km_s, 25.0, 2.7), rel=1e-15)
    assert list(c.regime) == list(regime(c.velocity_km_s, 25.0))
    d = json.loads(json.dumps(c.as_dict()))
    assert d["regime"][0] == "ballistic" and d["regime"][-1] == "hypervelocity"
    assert d["regime_boundaries_km_s"] == pytest.approx([lo, hi])
    custom = ballistic_limit_curve(s, [9.0, 2.0, 2.0], 0.0)  # sorted, de-duplicated; no boundary inside
    assert list(custom.velocity_km_s) == [2.0, 3.0, 7.0, 9.0]


# ---------------------------------------------------------------------- bad input


@pytest.mark.parametrize("field, value", [
    ("bumper_thickness_cm", 0.0), ("wall_thickness_cm", -0.3), ("spacing_cm", float("nan")),
    ("wall_yield_ksi", float("inf")), ("bumper_density_g_cm3", 0.0), ("wall_density_g_cm3", -2.7),
    ("spacing_cm", True), ("wall_yield_ksi", "40"),
])
def test_bad_shield_names_the_field(field, value):
    kwargs = table2().as_dict() | {field: value}
    with pytest.raises(InputError, match=field):
        WhippleShield(**kwargs)


@pytest.mark.parametrize("kwargs, name", [
    ({"obliquity_deg": 90.0}, "obliquity_deg"),
    ({"obliquity_deg": 95.0}, "obliquity_deg"),
    ({"obliquity_deg": -1.0}, "obliquity_deg"),
    ({"obliquity_deg": float("nan")}, "obliquity_deg"),
    ({"velocity_km_s": 0.0}, "velocity_km_s"),
    ({"velocity_km_s": -7.0}, "velocity_km_s"),
    ({"velocity_km_s": [7.0, float("inf")]}, "velocity_km_s"),
    ({"velocity_km_s": "fast"}, "velocity_km_s"),
    ({"projectile_density": 0.0}, "projectile_density"),
])
def test_bad_impact_inputs(kwargs, name):
    args = {"velocity_km_s": 7.0, "obliquity_deg": 25.0, "projectile_density": 2.7} | kwargs
    with pytest.raises(InputError, match=name):
        critical_diameter(table2(), **args)


def test_bad_inputs_elsewhere():
    with pytest.raises(InputError, match=r"obliquity_deg = 95\.0: obliquity must be in \[0, 90\)"):
        regime(7.0, 95.0)
    with pytest.raises(InputError, match="diameter_cm"):
        perforates(table2(), 0.0, 7.0)
    with pytest.raises(InputError, match="one angle"):
        ballistic_limit_curve(table2(), obliquity_deg=[0.0, 10.0])
    with pytest.raises(InputError, match="velocities"):
        ballistic_limit_curve(table2(), velocities=[1.0, -2.0])
    with pytest.raises(TypeError, match="WhippleShield"):
        critical_diameter(SingleWall(0.3), 7.0)


# --------------------------------------------------------------- single wall (Cour-Palais)


def test_single_wall_by_hand():
    w = SingleWall(0.3175)  # Al 6061-T6: ρ 2.7, HB 95, C 5.1 km/s
    # 5.24 · 1.8 · 95^(-1/4) · 1 · (7/5.1)^(2/3) = 5.24 · 1.8 · 0.32030897 · 1.23505200 = 3.73128252
    # (0.3175 / 3.73128252)^(18/19) = 0.08509139^(18/19) = 0.09687404
    assert single_wall_critical_diameter(w, 7.0) == pytest.approx(0.0968740, abs=1e-7)
    # steel sphere (ρ_p/ρ_t = 2.89 ≥ 1.5, exponent 2/3): (0.08509139 / 2.8889^(2/3))^(18/19) = 0.04957007
    assert single_wall_critical_diameter(w, 7.0, 0.0, 7.8) == pytest.approx(0.0495701, abs=1e-7)
    # obliquity enters as V cos θ
    assert single_wall_critical_diameter(w, 14.0, 60.0) == pytest.approx(single_wall_critical_diameter(w, 7.0))


@settings(max_examples=40, deadline=None)
@given(t=st.floats(0.05, 2.0), v=st.floats(0.5, 20.0), theta=angles, rho=densities,
       mode=st.sampled_from(list(FailureMode)))
def test_single_wall_inverts_penetration_depth(t, v, theta, rho, mode):
    w = SingleWall(t)
    dc = single_wall_critical_diameter(w, v, theta, rho, mode)
    assert mode.k * penetration_depth(w, dc, v, theta, rho) == pytest.approx(t, rel=1e-12)
    assert single_wall_perforates(w, dc * 1.001, v, theta, rho, mode)
    assert not single_wall_perforates(w, dc * 0.999, v, theta, rho, mode)


def test_single_wall_modes_curve_and_rear_wall():
    w = rear_wall(table2(), brinell_hardness=95.0)
    assert w == SingleWall(0.3175, 2.7, 95.0, 5.1)
    d = [single_wall_critical_diameter(w, 7.0, 25.0, 2.7, m) for m in
         ("perforation", "detached_spall", "incipient_spall")]
    assert d[0] > d[1] > d[2]
    # the bumper buys a factor of five at 7 km/s
    assert critical_diameter(table2(), 7.0, 25.0, 2.7) > 5 * d[0]
    c = single_wall_ballistic_limit_curve(w, obliquity_deg=25.0)
    assert c.regime is None and c.regime_boundaries() is None and "regime" not in c.as_dict()
    assert np.all(np.diff(c.critical_diameter_cm) < 0)
    assert c.critical_diameter_cm == pytest.approx(single_wall_critical_diameter(w, c.velocity_km_s, 25.0))
    with pytest.raises(InputError, match="mode"):
        single_wall_critical_diameter(w, 7.0, mode="shattered")
    with pytest.raises(InputError, match="brinell_hardness"):
        SingleWall(0.3, brinell_hardness=0.0)
    with pytest.raises(InputError, match="obliquity_deg"):
        penetration_depth(w, 0.1, 7.0, 90.0)
    assert math.isclose(single_wall_critical_diameter(w, 7.0, 25.0), d[0])
