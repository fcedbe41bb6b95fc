"""Statistics of a verdict score against textbook values, and the JSC 2011 equation scored by band."""

import json
import math

import numpy as np
import pytest
from scipy import stats

from impactdyn.ble import (
    DISTANCE_BANDS,
    Proportion,
    mcnemar,
    mcnemar_exact,
    score_by_distance,
    validate,
    wilson_interval,
)

# Newcombe 1998, Stat. Med. 17:857, Table I, method 3 (Wilson score interval, no continuity correction)
NEWCOMBE_TABLE_I = [
    (81, 263, 0.2553, 0.3662),
    (15, 148, 0.0624, 0.1605),
    (0, 20, 0.0, 0.1611),
    (1, 29, 0.0061, 0.1718),
]


@pytest.mark.parametrize("k, n, low, high", NEWCOMBE_TABLE_I)
def test_wilson_interval_matches_newcombe_table_i(k, n, low, high):
    got = wilson_interval(k, n)
    assert got == pytest.approx((low, high), abs=5e-5)


def test_wilson_interval_edges():
    assert wilson_interval(0, 10)[0] == 0.0 and wilson_interval(10, 10)[1] == 1.0
    # k = n mirrors k = 0
    assert wilson_interval(10, 10) == pytest.approx(tuple(1 - x for x in wilson_interval(0, 10)[::-1]))
    assert all(math.isnan(x) for x in wilson_interval(0, 0))
    # 99 % is wider than 95 %, which is wider than 80 %
    widths = [np.diff(wilson_interval(7, 30, c))[0] for c in (0.80, 0.95, 0.99)]
    assert widths[0] < widths[1] < widths[2]
    for bad in ((3, 2), (-1, 2)):
        with pytest.raises(ValueError):
            wilson_interval(*bad)
    with pytest.raises(ValueError):
        wilson_interval(1, 2, 1.0)


def test_wilson_interval_is_the_score_test_inversion():
    # the ends are where the score statistic (k − n p) / sqrt(n p (1 − p)) equals ±z
    z = stats.norm.ppf(0.975)
    for k, n in ((3, 17), (12, 40), (39, 41)):
        for p in wilson_interval(k, n):
            assert abs(k - n * p) / math.sqrt(n * p * (1 - p)) == pytest.approx(z, rel=1e-9)


def test_exact_mcnemar_by_hand_and_against_scipy():
    # b = 1, c = 6: 2 P(X <= 1 | 7, 1/2) = 2 (1 + 7) / 128 = 0.125; mid-p subtracts P(X = 1) = 7/128
    t = t1 = mcnemar_exact(1, 6)
    assert t.p_exact == pytest.approx(0.125, abs=1e-15) and t.p_mid == pytest.approx(0.125 - 7 / 128, abs=1e-15)
    # Fagerland, Lydersen & Laake 2013, Table 1 (Bentur et al. 2009): discordant pairs 1 and 7
    t = mcnemar_exact(1, 7)
    assert t.p_exact == pytest.approx(18 / 256, abs=1e-15) and t.p_mid == pytest.approx(10 / 256, abs=1e-15)
    assert round(t.p_exact, 3) == 0.070 and round(t.p_mid, 3) == 0.039
    for b, c in ((0, 5), (3, 11), (9, 4), (20, 31)):
        assert mcnemar_exact(b, c).p_exact == pytest.approx(stats.binomtest(b, b + c, 0.5).pvalue, rel=1e-12)
    assert mcnemar_exact(4, 4).p_exact == 1.0 and mcnemar_exact(4, 4).p_mid == pytest.approx(1 - 70 / 256 / 2)
    assert (mcnemar_exact(0, 0).p_exact, mcnemar_exact(0, 0).p_mid) == (1.0, 1.0)
    assert (mcnemar_exact(6, 1).p_exact, mcnemar_exact(6, 1).p_mid) == (t1.p_exact, t1.p_mid)
    with pytest.raises(ValueError):
        mcnemar_exact(-1, 3)


def test_mcnemar_counts_the_discordant_shots():
    truth = np.array([1, 1, 1, 0, 0, 0, 1, 0], dtype=bool)
    first = np.array([1, 1, 0, 0, 1, 0, 1, 0], dtype=bool)   # wrong on shots 2, 4
    second = np.array([0, 1, 1, 0, 0, 1, 0, 1], dtype=bool)  # wrong on shots 0, 5, 6, 7
    t = mcnemar(truth, first, second)
    assert (t.b, t.c) == (4, 2)  # first only right: 0, 5, 6, 7; second only right: 2, 4


def test_score_by_distance_bands_and_counts():
    ratio = np.array([1.01, 0.97, 1.10, 0.88, 1.2, 0.75, 2.0, 0.3, np.nan])
    perforated = np.array([1, 0, 1, 0, 1, 0, 1, 0, 1], dtype=bool)
    called = ratio > 1.0
    called[0] = False  # a false safe within 5 %
    called[3] = True   # a false alarm at 12 %
    s = score_by_distance(ratio, perforated, called)
    assert [b.band for b in s.bands] == list(DISTANCE_BANDS)
    assert [b.shots for b in s.bands] == [2, 2, 2, 2] and s.unbanded == 1 and s.overall.shots == 9
    near, mid = s.bands[0], s.bands[1]
    assert near.accuracy == Proportion.of_counts(1, 2) and near.false_safe.count == 1 and near.false_safe.of == 1
    assert near.false_alarm == Proportion.of_counts(0, 1)
    assert mid.false_alarm.count == 1 and mid.false_safe.count == 0
    assert s.overall.accuracy.count == 6  # 1.01, 0.88 and the NaN shot (called held) are wrong
    # a band with no held shots has no false-alarm rate
    only = score_by_distance([1.5], [True], [True])
    assert only.bands[3].false_alarm == Proportion(0, 0, None, None, None) and only.bands[0].shots == 0
    text = json.dumps(s.as_dict())
    assert json.loads(text)["bands"][0]["false_safe"]["rate"] == 1.0
    with pytest.raises(ValueError, match="one shape"):
        score_by_distance([1.0, 2.0], [True], [True])


def test_band_edges_belong_to_the_band_above():
    s = score_by_distance([1.05, 0.85, 1.30], [True] * 3, [True] * 3)
    assert [b.shots for b in s.bands] == [0, 1, 1, 1]


def test_jsc2011_scored_by_distance_from_its_own_limit():
    """The default equation on the packaged database, nothing fitted: near the limit its verdicts
    are a coin toss, far from it they are right nine times in ten (93 %, 49.6 % within 5 %)."""
    v = validate()
    s = score_by_distance(v.database.diameter_cm / v.limit.threshold_cm, v.database.perforated, v.called)
    near, *_, far = s.bands
    assert (near.shots, near.accuracy.count) == (133, 66)
    assert (far.shots, far.accuracy.count) == (479, 447)
    assert near.accuracy.high < far.accuracy.low  # the bands' intervals do not overlap
    assert near.accuracy.low < 0.5 < near.accuracy.high  # within 5 % of the limit: no better than chance
    assert s.overall.accuracy.count == v.overall.correct and s.overall.false_safe.count == v.overall.false_safe
    assert sum(b.shots for b in s.bands) == len(v.database) and s.unbanded == 0
    accuracies = [b.accuracy.rate for b in s.bands]
    assert accuracies == sorted(accuracies)  # easier further from the limit


def test_jsc2011_against_jsc1993_on_the_same_shots():
    """The 2011 form calls 61 shots right that the 1993 equations call wrong, and the 1993 ones 27 the
    other way: the exact McNemar test says the difference is not chance (p = 3.7e-4)."""
    new, old = validate("jsc2011"), validate("jsc1993")
    t = mcnemar(new.database.perforated, new.called, old.called)
    assert (t.b, t.c) == (61, 27)
    assert t.b - t.c == new.overall.correct - old.overall.correct
    assert t.p_mid < t.p_exact < 1e-3
