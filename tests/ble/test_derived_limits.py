"""The test-derived limit: the logistic fit recovers a known limit, refuses what it must, and the
docs table is what the database gives."""

import math
import runpy
from pathlib import Path

import numpy as np
import pytest
from scipy import special, stats

from impactdyn.ble import (
    CONFIGURATION_OBLIQUITY_DEG,
    CONFIGURATION_TOLERANCE,
    MIN_SHOTS,
    configurations,
    derived_limits,
    fit_limit,
    one_record_per_firing,
    read_database,
)

ROOT = Path(__file__).resolve().parents[2]
D50, SLOPE = 0.5, 8.0  # cm; b in logit P = b (ln d − ln d50): 12 % to 88 % over ±28 % in d


def _shots(seed: int, n: int = 40):
    rng = np.random.default_rng(seed)
    d = np.exp(rng.uniform(math.log(0.3), math.log(0.8), n))
    return d, rng.random(n) < special.expit(SLOPE * (np.log(d) - math.log(D50)))


def test_fit_recovers_a_known_limit_with_plausible_coverage():
    # 95 % intervals on 20 independent samples: P(17 or more cover | coverage 0.95) = 0.98
    covered = 0
    for seed in range(20):
        f = fit_limit(*_shots(seed))
        assert f.refused is None and f.low_cm is not None and f.high_cm is not None
        assert f.low_cm < f.d50_cm < f.high_cm
        covered += f.low_cm <= D50 <= f.high_cm
    assert covered >= 17


def test_fit_solves_the_score_equations_and_the_interval_ends_sit_on_the_chi2_quantile():
    d, y = _shots(3)
    f = fit_limit(d, y)
    x = np.log(d)
    p = special.expit(f.slope * (x - math.log(f.d50_cm)))
    # ∂ℓ/∂a = Σ (y − p) = 0 and ∂ℓ/∂b = Σ x (y − p) = 0 at the MLE
    assert abs(np.sum(y - p)) < 1e-6 and abs(np.sum(x * (y - p))) < 1e-6

    def deviance(m):  # 2 [ℓ̂ − max_b ℓ(m, b)], maximised by brute force over a fine grid of b
        best = max(np.sum(y * b * (x - m) - np.logaddexp(0, b * (x - m))) for b in np.linspace(0.1, 60, 6000))
        top = np.sum(y * np.log(p) + (1 - y) * np.log1p(-p))
        return 2 * (top - best)

    for end in (f.low_cm, f.high_cm):
        assert deviance(math.log(end)) == pytest.approx(stats.chi2.ppf(0.95, 1), abs=0.01)
    wider = fit_limit(d, y, confidence=0.99)
    assert wider.low_cm < f.low_cm and wider.high_cm > f.high_cm and wider.d50_cm == pytest.approx(f.d50_cm)


def test_separable_shots_give_the_bracket():
    d = np.array([0.30, 0.35, 0.40, 0.45, 0.55, 0.60, 0.70])
    perforated = d > 0.5
    f = fit_limit(d, perforated)
    assert f.refused.startswith("separable") and f.d50_cm is None and f.low_cm is None
    assert (f.largest_held_cm, f.smallest_perforated_cm) == (0.45, 0.55)
    # both outcomes at one diameter and none on the wrong side: still no MLE (quasi-separation)
    tie = fit_limit([0.3, 0.4, 0.5, 0.5, 0.6, 0.7], [False, False, False, True, True, True])
    assert tie.refused.startswith("separable") and tie.largest_held_cm == tie.smallest_perforated_cm == 0.5


def test_refusals():
    few = fit_limit([0.3, 0.5, 0.4, 0.6, 0.45], [False, True, True, False, True])
    assert few.refused.startswith("too few shots") and str(MIN_SHOTS) in few.refused
    one_sided = fit_limit([0.3, 0.4, 0.5, 0.6, 0.7, 0.8], [True] * 5 + [False])
    assert one_sided.refused.startswith("too few shots")
    backwards = fit_limit([0.3, 0.35, 0.4, 0.6, 0.65, 0.7], [True, True, True, False, False, False])
    assert backwards.refused.startswith("separated the wrong way")
    falling = fit_limit([0.3, 0.35, 0.4, 0.45, 0.5, 0.6, 0.7], [True, True, False, True, False, True, False])
    assert falling.refused.startswith("slope not positive") and falling.d50_cm is None
    with pytest.raises(ValueError, match="one length"):
        fit_limit([0.3, 0.4], [True])
    with pytest.raises(ValueError, match="> 0"):
        fit_limit([0.3, 0.0, 0.4, 0.5, 0.6, 0.7], [False, False, True, False, True, True])


def test_configurations_hold_their_tolerances():
    db = read_database()
    label, found = configurations(db)
    assert label.min() == 0 and len(found) == label.max() + 1
    for c, ref in enumerate(found):
        here = label == c
        assert set(db.projectile_material[here]) == {ref.projectile_material}
        assert set(db.wall_material[here]) == {ref.wall_material}
        for attr in ("bumper_thickness_cm", "wall_thickness_cm", "spacing_cm"):
            assert np.all(np.abs(getattr(db, attr)[here] / getattr(ref, attr) - 1) <= CONFIGURATION_TOLERANCE)
        assert np.all(np.abs(db.obliquity_deg[here] - ref.obliquity_deg) <= CONFIGURATION_OBLIQUITY_DEG)


def test_one_record_per_firing():
    db = read_database()
    keep = one_record_per_firing(db)
    # 17 twin groups: one record each of 16; the conflicting pair (shot 2225) is left out
    assert len(db) - keep.sum() == 17 + 1
    assert not keep[np.isin(db.line, [301, 452])].any()
    assert len(np.unique(db.twin_group[keep])) == keep.sum()


def test_derived_limits_on_the_database_and_the_docs_table():
    rows = derived_limits(read_database())
    assert all(r.fit.shots >= MIN_SHOTS for r in rows)
    fitted = [r for r in rows if r.fit.refused is None]
    assert len(fitted) >= 1
    for r in fitted:
        assert r.fit.high_cm is None or r.fit.d50_cm < r.fit.high_cm
        assert r.fit.low_cm is None or r.fit.low_cm < r.fit.d50_cm
        assert 0 < r.fit.perforated < r.fit.shots
    script = runpy.run_path(str(ROOT / "validation" / "test_derived_limits.py"))
    assert (ROOT / "docs" / "test_derived_limits.md").read_text(encoding="utf-8") == script["markdown"](), \
        "docs/test_derived_limits.md is out of date: python validation/test_derived_limits.py"
