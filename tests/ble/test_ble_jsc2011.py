"""The 2011 form (Ryan & Christiansen 2011; BLAP, NASA/TM-2009-214789) against an independent evaluation.

``published_limit`` below transcribes the published formulas in plain Python (floats and
``math``, the expanded form of F2*, (t_b/d)_crit picked from S/d of each trial diameter)
and finds the fixed points by its own means: a scan of d − (R1)(d) over a log grid for
sign changes, bisection in d, and a residual check that tells a root from the jump of
(R3).  It reads the database with the ``csv`` module.  Nothing is shared with the library
but the file.
"""

import csv
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from impactdyn.ble import DATABASE_PATH, WhippleShield, ballistic_limit, critical_diameter, jsc_verdict, validate
from impactdyn.ble._jsc2011 import TB_D_CRIT_FAR, TB_D_CRIT_NEAR, f2_star, r_sd

# ------------------------------------------------------------------ independent transcription


def _cos(theta_deg):
    return math.cos(math.radians(min(theta_deg, 65.0)))  # obliquity capped at 65°


def published_w1(s, v):
    """(W1), ballistic."""
    return ((s["wall_thick"] * (s["wall_yield"] / 40) ** 0.5 + s["bumper_thick"])
            / (0.6 * _cos(s["angle"]) ** (5 / 3) * s["proj_density"] ** 0.5 * v ** (2 / 3))) ** (18 / 19)


def published_f2_star(s, d):
    """(R2)–(R4) as printed, for a projectile of diameter d."""
    c = _cos(s["angle"])
    v_hv = 7.0 / c
    sigma, rho_p, rho_b, spacing = s["wall_yield"], s["proj_density"], s["bumper_density"], s["standoff"]
    tw0 = 0.6 * d ** (19 / 18) * c ** (5 / 3) * rho_p ** 0.5 * v_hv ** (2 / 3) / (sigma / 40) ** 0.5
    mass = math.pi * rho_p * d ** 3 / 6
    tw_crit = (0.16 * d ** 0.5 * (rho_p * rho_b) ** (1 / 6) * mass ** (1 / 3) * v_hv * c / spacing ** 0.5
               * (70 / sigma) ** 0.5)
    r = tw0 / tw_crit
    crit = 0.20 if spacing / d >= 30 else 0.25
    q = (s["bumper_thick"] / d) / crit
    if q >= 1:
        return 1.0
    return r - 2 * q * (r - 1) + q ** 2 * (r - 1)


def published_r1(s, d, v):
    """(R1): the hypervelocity limit for a projectile of diameter d at speed v."""
    return (3.918 * published_f2_star(s, d) ** (-2 / 3) * s["wall_thick"] ** (2 / 3) * s["proj_density"] ** (-1 / 3)
            * s["bumper_density"] ** (-1 / 9) * (v * _cos(s["angle"])) ** (-2 / 3) * s["standoff"] ** (1 / 3)
            * (s["wall_yield"] / 70) ** (1 / 3))


def fixed_points(s, v, lo=1e-3, hi=30.0, n=400):
    """Every d in [lo, hi] with d = (R1)(d, v)."""
    def f(d):
        return d - published_r1(s, d, v)

    grid = [lo * (hi / lo) ** (k / n) for k in range(n + 1)]
    roots = []
    for a, b in zip(grid, grid[1:]):
        fa = f(a)
        if fa * f(b) > 0:
            continue
        for _ in range(100):
            m = 0.5 * (a + b)
            if (f(m) > 0) == (fa > 0):
                a = m
            else:
                b = m
        x = 0.5 * (a + b)
        if abs(f(x)) <= 1e-9 * x:  # a root, not the jump of (R3) at S/30
            roots.append(x)
    return roots


def published_limit(s):
    """(regime, d_c or None, number of fixed points at the hypervelocity speed used)."""
    c = _cos(s["angle"])
    v, v_lv, v_hv = s["velocity"], 2.6 / c, 7.0 / c
    if v * c <= 2.6:
        return "ballistic", published_w1(s, v), 1
    hyper = v * c >= 7.0
    roots = fixed_points(s, v if hyper else v_hv)
    if len(roots) != 1:
        return ("hypervelocity" if hyper else "shatter"), None, len(roots)
    if hyper:
        return "hypervelocity", roots[0], 1
    low = published_w1(s, v_lv)
    return "shatter", low + (roots[0] - low) * (v - v_lv) / (v_hv - v_lv), 1


def database_rows():
    with open(DATABASE_PATH, newline="", encoding="utf-8-sig") as fh:
        rows = list(csv.DictReader(fh))[1:]  # the units row follows the header
    keys = ("proj_density", "proj_diam", "angle", "velocity", "bumper_density", "bumper_thick", "standoff",
            "wall_yield", "wall_thick")
    return [{k: float(r[k]) for k in keys} for r in rows]


# ------------------------------------------------------------------ acceptance: every shot


@pytest.fixture(scope="module")
def reference():
    return [published_limit(s) for s in database_rows()]


@pytest.fixture(scope="module")
def library():
    return validate("jsc2011")


def test_agrees_with_the_independent_evaluation_on_every_shot(reference, library):
    limit = library.limit
    assert len(reference) == len(library.database) == limit.critical_diameter_cm.size
    assert [r[0] for r in reference] == [str(x) for x in limit.regime]
    exists = np.array([r[1] is not None for r in reference])
    mine = limit.critical_diameter_cm
    # the fixed point exists on the same shots, and agrees to 1e-6 there
    assert np.array_equal(exists, ~np.isnan(mine))
    ref = np.array([r[1] for r in reference if r[1] is not None])
    assert np.max(np.abs(mine[exists] / ref - 1)) <= 1e-6
    # both kinds of shot are there: the test exercises the missing fixed point too
    assert exists.sum() > 0.9 * exists.size and (~exists).any()
    assert all(r[2] == 0 for r in reference if r[1] is None)  # no root at all, never two, on these shots


def test_shots_without_a_fixed_point_say_so(reference, library):
    db, limit = library.database, library.limit
    none = np.isnan(limit.critical_diameter_cm)
    assert library.no_fixed_point == none.sum() == library.overall.shots - library.with_fixed_point.shots
    for i in np.flatnonzero(none):
        note = limit.note[i]
        reg = str(limit.regime[i])
        assert note.startswith(f"{reg} regime") and "no fixed point" in note
        assert f"S/30 = {db.spacing_cm[i] / 30:.4g} cm" in note
        if reg == "hypervelocity":
            assert limit.threshold_cm[i] == pytest.approx(db.spacing_cm[i] / 30, rel=1e-15)
    assert all(n is None for n in limit.note[~none])
    assert np.array_equal(limit.threshold_cm[~none], limit.critical_diameter_cm[~none])


def test_without_a_fixed_point_the_line_is_drawn_at_the_jump(library):
    """Every diameter up to S/30 is below its own (R1), every larger one above it."""
    db, limit = library.database, library.limit
    hyper = np.flatnonzero(np.isnan(limit.critical_diameter_cm) & (limit.regime == "hypervelocity"))
    assert hyper.size
    rows = database_rows()
    for i in hyper:
        jump = db.spacing_cm[i] / 30
        for d in (0.5 * jump, 0.999 * jump, jump):
            assert d < published_r1(rows[i], d, rows[i]["velocity"])
        for d in (1.001 * jump, 2 * jump):
            assert d > published_r1(rows[i], d, rows[i]["velocity"])


def test_public_scalar_api_matches_the_database_evaluation(library):
    db, limit = library.database, library.limit
    for i in range(0, len(db), 37):
        shield = WhippleShield(db.bumper_thickness_cm[i], db.wall_thickness_cm[i], db.spacing_cm[i],
                               db.wall_yield_ksi[i], db.bumper_density_g_cm3[i])
        args = (db.velocity_km_s[i], db.obliquity_deg[i], db.projectile_density_g_cm3[i])
        assert critical_diameter(shield, *args, equation="jsc2011") == pytest.approx(
            limit.critical_diameter_cm[i], rel=1e-13, nan_ok=True)
        v = jsc_verdict(shield, db.diameter_cm[i], *args, equation="jsc2011")
        assert (v["verdict"] == "perforation") == library.called[i]
        assert v["note"] == limit.note[i]
        assert (v["critical_diameter_cm"] is None) == bool(np.isnan(limit.critical_diameter_cm[i]))


def test_jsc_verdict_without_a_fixed_point(library):
    db, limit = library.database, library.limit
    i = int(np.flatnonzero(np.isnan(limit.critical_diameter_cm))[0])
    shield = WhippleShield(db.bumper_thickness_cm[i], db.wall_thickness_cm[i], db.spacing_cm[i],
                           db.wall_yield_ksi[i], db.bumper_density_g_cm3[i])
    args = (db.velocity_km_s[i], db.obliquity_deg[i], db.projectile_density_g_cm3[i])
    out = [jsc_verdict(shield, f * limit.threshold_cm[i], *args) for f in (0.99, 1.01)]
    assert [o["verdict"] for o in out] == ["no perforation", "perforation"]
    assert all(o["critical_diameter_cm"] is None and "no fixed point" in o["note"] for o in out)
    assert out[0]["threshold_cm"] == pytest.approx(limit.threshold_cm[i], rel=1e-13)


def test_two_fixed_points_take_the_smaller():
    """An absurd shield (bumper 1e9 g/cm³) has r_S/D < 1 at S/30: the limit jumps up and R has two roots."""
    shield = WhippleShield(0.01, 4.6, 30.0, 40.0, 1e9)
    s = {"wall_thick": 4.6, "bumper_thick": 0.01, "standoff": 30.0, "wall_yield": 40.0, "bumper_density": 1e9,
         "proj_density": 2.7, "angle": 0.0, "velocity": 7.5}
    roots = fixed_points(s, 7.5, 0.5, 2.0, 3000)  # the roots lie 1.5 % and 1.9 % either side of S/30 = 1 cm
    assert len(roots) == 2 and roots[0] < 1.0 < roots[1]
    limit = ballistic_limit(shield, 7.5, 0.0, 2.7, "jsc2011")
    assert float(limit.critical_diameter_cm) == pytest.approx(roots[0], rel=1e-9)
    assert float(limit.threshold_cm) == float(limit.critical_diameter_cm)
    assert limit.note[()].startswith("hypervelocity regime: two fixed points")
    assert r_sd(shield, 1.0, 1.0, 2.7) < 1


# ------------------------------------------------------------------ the fixed point and F2*


shields = st.builds(
    WhippleShield,
    bumper_thickness_cm=st.floats(0.005, 0.5),
    wall_thickness_cm=st.floats(0.05, 1.0),
    spacing_cm=st.floats(1.0, 40.0),
    wall_yield_ksi=st.floats(10.0, 80.0),
    bumper_density_g_cm3=st.floats(1.5, 8.0),
)


@settings(max_examples=60, deadline=None)
@given(shield=shields, theta=st.floats(0.0, 65.0), rho_p=st.floats(0.5, 8.0), vn=st.floats(7.0, 20.0))
def test_the_root_is_a_fixed_point(shield, theta, rho_p, vn):
    v = vn / math.cos(math.radians(theta))
    d = critical_diameter(shield, v, theta, rho_p, "jsc2011")
    s = {"wall_thick": shield.wall_thickness_cm, "bumper_thick": shield.bumper_thickness_cm,
         "standoff": shield.spacing_cm, "wall_yield": shield.wall_yield_ksi,
         "bumper_density": shield.bumper_density_g_cm3, "proj_density": rho_p, "angle": theta}
    if math.isnan(d):
        # below the jump at S/30 every diameter is under its own limit, above it over it; each side is
        # taken a relative 1e-9 off the jump: at d = S/30 itself the branch R1 takes depends on the
        # last bit of S/d (S = 2.53125 cm gives S/(S/30) = 29.999999999999996, the upper branch)
        below, above = shield.spacing_cm / 30 * (1 - 1e-9), shield.spacing_cm / 30 * (1 + 1e-9)
        assert published_r1(s, below, v) > below and published_r1(s, above, v) < above
    else:
        assert published_r1(s, d, v) == pytest.approx(d, rel=1e-12)


@settings(max_examples=60, deadline=None)
@given(shield=shields, theta=st.floats(0.0, 65.0), rho_p=st.floats(0.5, 8.0))
def test_residual_increases_within_each_branch(shield, theta, rho_p):
    """dR/d ln d > 1/27 inside each (t_b/d)_crit branch (module docstring): at most one root per branch."""
    c = math.cos(math.radians(theta))
    d = np.geomspace(1e-3, 30.0, 400)
    for crit in (TB_D_CRIT_FAR, TB_D_CRIT_NEAR):
        r = np.log(d) + (2 / 3) * np.log(f2_star(shield, d, crit, c, rho_p))
        assert np.all(np.diff(r) / np.diff(np.log(d)) > 1 / 27 - 1e-9)


@settings(max_examples=40, deadline=None)
@given(shield=shields, theta=st.floats(0.0, 65.0), rho_p=st.floats(0.5, 8.0), d=st.floats(0.01, 5.0))
def test_r_sd_closed_form(shield, theta, rho_p, d):
    """r_S/D = 1.839 cos θ ρ_b^{-1/6} S^{1/2} d^{-4/9}: ρ_p, σ and V drop out (module docstring)."""
    k = 0.6 / 0.16 * (40 / 70) ** 0.5 * (6 / math.pi) ** (1 / 3) * 7 ** (-1 / 3)
    assert k == pytest.approx(1.839, abs=5e-4)
    c = math.cos(math.radians(theta))
    assert r_sd(shield, d, c, rho_p) == pytest.approx(
        k * c * shield.bumper_density_g_cm3 ** (-1 / 6) * shield.spacing_cm ** 0.5 * d ** (-4 / 9), rel=1e-12)


@settings(max_examples=40, deadline=None)
@given(shield=shields, theta=st.floats(0.0, 65.0), rho_p=st.floats(0.5, 8.0), vn=st.floats(7.0, 20.0))
def test_thick_bumpers_are_not_derated(shield, theta, rho_p, vn):
    """F2* = 1 for t_b/d ≥ (t_b/d)_crit: there the 2011 hypervelocity limit is (W3) of 1993.

    Below it F2* lies between r_S/D and 1, so a thin bumper lowers the limit where r_S/D > 1 and
    raises it where r_S/D < 1 (close stand-off, steep obliquity: S = 1 cm at 63° has r_S/D ≈ 0.996).
    """
    v = vn / math.cos(math.radians(theta))
    d93 = critical_diameter(shield, v, theta, rho_p, "jsc1993")
    d11 = critical_diameter(shield, v, theta, rho_p, "jsc2011")
    crit = TB_D_CRIT_FAR if shield.spacing_cm / d93 >= 30 else TB_D_CRIT_NEAR
    if shield.bumper_thickness_cm >= crit * d93:
        assert d11 == pytest.approx(d93, rel=1e-12)
    elif not math.isnan(d11):
        assert (d11 < d93) == (r_sd(shield, d11, math.cos(math.radians(theta)), rho_p) > 1.0)


def test_f2_star_runs_from_r_sd_to_one():
    shield = WhippleShield(0.1, 0.3, 10.0, 40.0)
    at, beyond = f2_star(shield, np.array([0.4, 0.4 * (1 + 1e-6)]), 0.25, 1.0, 2.7)  # t_b/d = 0.25 and just below
    assert at == 1.0 and 1.0 < beyond < 1.0 + 1e-9
    thin = WhippleShield(1e-12, 0.3, 10.0, 40.0)
    assert f2_star(thin, 1.0, 0.25, 1.0, 2.7) == pytest.approx(r_sd(thin, 1.0, 1.0, 2.7), rel=1e-9)
