"""The two recorded sample runs of seed 001 (reference/beam_sample_runs.md)."""

import numpy as np
import pytest

from impactdyn.beam import simulate


def test_impactc_first_impact(impactc_result):
    first = impactc_result.impacts[0]
    assert 0.78105 <= first.t_start <= 0.78112
    assert first.v_approach == pytest.approx(3.996, abs=0.005)
    assert first.restitution == pytest.approx(0.3546, abs=0.001)
    assert first.v_separation == pytest.approx(1.417, abs=0.005)


def test_impactc_chattering_is_reported_and_ends(impactc_result):
    """Micro-impacts follow the strike; they end in resting contact, not in a hang."""
    r = impactc_result
    assert len(r.impacts) > 8
    assert any(i.kind == "plastic" for i in r.impacts)
    assert len(r.resting) >= 1 and r.resting[0, 1] > r.resting[0, 0]
    # the sequence decays: each later impact is slower than the first
    assert all(i.v_approach < r.impacts[0].v_approach for i in r.impacts[1:])
    assert np.isfinite(r.y).all() and r.t[-1] == pytest.approx(1.0)


def test_impactb_first_contact(impactb_result):
    first = impactb_result.impacts[0]
    assert abs(first.t_start - 0.78109025) < 1e-5
    assert first.v_approach == pytest.approx(3.9959, abs=0.005)
    assert first.restitution == pytest.approx(0.264, abs=0.01)
    # the force phase ends where the listing's TSTP does (0.78112358 s)
    assert abs(first.t_end - 0.78112358) < 2e-6


def test_impactb_force_history_matches_listing_samples(make_case):
    """Contact force at the listing's own 5-µs output instants against its printout.

    (The listing's peak 1410.9 N and duration 33.3 µs are 5-µs samples and a late
    start flag; the force history itself is what can be compared.)
    """
    listing = {0.781090: 1316.332172, 0.781095: 1410.879164, 0.781100: 939.403621, 0.781105: 502.990294}
    case = make_case("impactb_sample.toml", time={"end_s": 0.78112, "output_step_s": 5e-6})
    r = simulate(case)
    for t, f in listing.items():
        k = int(np.argmin(np.abs(r.t - t)))
        assert r.contact_force[k] == pytest.approx(f, rel=0.10), t
    assert max(r.contact_force) == pytest.approx(1411, rel=0.05)


def test_impactb_contact_kinematics_match_listing_printout(make_case):
    """Stop-point gap and velocity through the first contact against the listing's own printout.

    Each "TIME= t FORCE= … WP= … WPP= …" line of the IMPACTB sample run prints WP and
    WPP computed before its DDRIVE call, i.e. at the previous output time t − 5 µs,
    and FORCE after it (listing, main loop). WP is printed to 1e-6 m. The printout's
    first line puts the gap at +17 µm at 0.781080 s, closing at 3.9957 m/s: the
    listing's own contact began at 0.781084 s, 6 µs before its TSTR flag.
    """
    printed = {  # TIME: (WP, WPP) of the line, belonging to TIME − 5 µs
        0.781085: (0.000017, -3.995724), 0.781090: (-0.000003, -3.977030), 0.781095: (-0.000022, -3.137011),
        0.781100: (-0.000034, -1.654186), 0.781105: (-0.000039, -0.395933), 0.781110: (-0.000038, 0.382752),
        0.781115: (-0.000035, 0.791656), 0.781120: (-0.000031, 0.980241)}
    case = make_case("impactb_sample.toml", time={"end_s": 0.78113, "output_step_s": 5e-6})
    r = simulate(case)
    gap, rate = r.model.gap(r.y), r.model.gap_rate(r.y)
    for t, (wp, wpp) in printed.items():
        k = int(np.argmin(np.abs(r.t - (t - 5e-6))))
        assert abs(gap[k] - wp) < 0.6e-6, (t, gap[k], wp)
        assert abs(rate[k] - wpp) < 0.01, (t, rate[k], wpp)
    first = r.impacts[0]
    assert abs(first.t_start - (0.781080 + 0.000017 / 3.995724)) < 2e-7


def test_impactb_state_at_one_second(impactb_result):
    s = impactb_result.summary()["final_state"]
    assert s["theta_dot"] == pytest.approx(-5.200794, rel=0.05)
    assert abs(s["theta"] - 0.181022) < 0.01


@pytest.mark.parametrize("method", ["LSODA", "Radau"])
def test_scipy_solvers_agree_on_first_impact(make_case, method):
    """The compiled Rosenbrock path and SciPy's solvers locate the same impact."""
    base = make_case("impactb_sample.toml", time={"end_s": 0.7812, "output_step_s": 1e-3})
    other = make_case("impactb_sample.toml", time={"end_s": 0.7812, "output_step_s": 1e-3},
                      solver={"method": method, "rtol": 1e-8, "atol": 1e-11})
    a, b = simulate(base).impacts[0], simulate(other).impacts[0]
    assert abs(a.t_start - b.t_start) < 1e-8
    assert a.v_approach == pytest.approx(b.v_approach, rel=1e-6)
    assert a.restitution == pytest.approx(b.restitution, rel=1e-5)
