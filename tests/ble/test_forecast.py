"""The verdicts scored as forecasts: Brier score, log-loss with its clip, bootstrap intervals, the baselines."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from impactdyn.ble import brier_score, database_logistic, forecast_scores, log_loss, plot_reliability, reliability
from impactdyn.whipple import score_validation


def test_the_scores_of_known_forecasts():
    assert brier_score([1.0, 0.0], [True, False]) == 0.0
    assert brier_score([0.5, 0.5, 0.5], [True, False, True]) == 0.25
    assert log_loss([0.5, 0.5], [True, False], [8, 8]) == pytest.approx(math.log(2.0))
    # a sure and wrong verdict of one draw costs ln 2 (P clipped to 1/2), of 8 draws ln 16
    assert log_loss([0.0], [True], [1]) == pytest.approx(math.log(2.0))
    assert log_loss([0.0], [True], [8]) == pytest.approx(math.log(16.0))
    assert log_loss([1.0], [True], [8]) == pytest.approx(-math.log(1.0 - 1.0 / 16.0))


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 8), st.booleans()), min_size=2, max_size=12))
def test_forecast_intervals_hold_the_score_and_repeat(shots):
    k, y = zip(*shots)
    p = np.array(k) / 8.0
    one = forecast_scores(p, [8] * len(p), y, {})
    again = forecast_scores(p, [8] * len(p), y, {})
    assert one == again                                     # a fixed seed: a rescoring gives the same intervals
    s = one["simulated"]
    assert 0.0 <= s["brier"] <= 1.0 and s["log_loss"] >= 0.0
    assert 0.0 <= s["brier_95"][0] <= s["brier_95"][1] <= 1.0 and 0.0 <= s["log_loss_95"][0] <= s["log_loss_95"][1]
    if len(set(p - np.array(y, float))) == 1:                # every shot's error the same: no spread to resample
        assert s["brier_95"] == pytest.approx([s["brier"]] * 2)


def test_the_database_logistic_rises_with_the_diameter_and_leaves_out_the_scored_shots():
    full = database_logistic()
    r = np.array([0.6, 0.9, 1.0, 1.2, 1.6])
    p = full(r)
    assert np.all(np.diff(p) > 0) and 0.0 < p[0] < 0.5 < p[-1] < 1.0
    from impactdyn.ble import read_database
    left_out = database_logistic(exclude_lines=read_database().line[:300])
    assert not np.allclose(left_out(r), p)


def test_validation_scores_carry_the_forecasts_only_with_the_draws():
    rows = [{"line": 10, "d_over_limit": 1.2, "test_perforated": True, "simulated_perforated": True,
             "jsc_perforated": True, "n_draws": 4, "p_perforation": 0.75},
            {"line": 11, "d_over_limit": 0.8, "test_perforated": False, "simulated_perforated": False,
             "jsc_perforated": True, "n_draws": 4, "p_perforation": 0.25},
            {"line": 12, "d_over_limit": 1.05, "test_perforated": True, "simulated_perforated": False,
             "jsc_perforated": True, "n_draws": 4, "p_perforation": 0.5}]
    forecast = score_validation(rows)["forecast"]
    assert set(forecast) == {"simulated", "jsc", "database_logistic"}
    assert forecast["simulated"]["brier"] == pytest.approx((0.25 ** 2 + 0.25 ** 2 + 0.5 ** 2) / 3)
    assert forecast["jsc"]["brier"] == pytest.approx(1.0 / 3.0)
    older = [{k: v for k, v in r.items() if k not in ("n_draws", "p_perforation")} for r in rows]
    assert score_validation(older)["forecast"] is None


def test_the_reliability_bins_of_known_forecasts():
    """Shots at P = 0.125 (two, one perforated), 0.5 (one held) and 1.0 (three perforated): three bins, each
    with its shots, mean P and observed frequency; P = 1 falls in the last, closed bin."""
    p = [0.125, 0.125, 0.5, 1.0, 1.0, 1.0]
    y = [True, False, False, True, True, True]
    bins = reliability(p, y)
    assert [b["bin"] for b in bins] == [[0.0, 0.2], [0.4, 0.6], [0.8, 1.0]]
    assert [b["shots"] for b in bins] == [2, 1, 3]
    assert [b["mean_p"] for b in bins] == [0.125, 0.5, 1.0]
    assert [b["observed"] for b in bins] == [0.5, 0.0, 1.0]
    assert all(lo <= b["observed"] <= hi for b in bins for lo, hi in [b["observed_95"]])
    assert bins[2]["observed_95"][1] == pytest.approx(1.0) and bins[2]["observed_95"][0] < 1.0


def test_the_reliability_diagram_is_drawn_from_the_scores(tmp_path):
    scores = forecast_scores([0.125, 0.5, 1.0], [8, 8, 8], [False, True, True], {"jsc": np.array([0.0, 1.0, 1.0])})
    assert sum(b["shots"] for b in scores["jsc"]["reliability"]) == 3
    path = plot_reliability(scores, tmp_path / "reliability.png")
    assert path.stat().st_size > 10_000
