"""Scoring the Whipple equations on the test database; the numbers docs/ble.md records; the plots."""

import json
import re
import sys
from pathlib import Path

import numpy as np
import pytest

from impactdyn.ble import (
    DEFAULT_EQUATION,
    EQUATIONS,
    OBLIQUITY_BANDS,
    Scores,
    WhippleShield,
    ballistic_limit_curve,
    nearby_shots,
    perforates,
    plot_ballistic_limit,
    plot_validation,
    read_database,
    validate,
)
from impactdyn.ble._validate import obliquity_band

ROOT = Path(__file__).resolve().parents[2]
PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def results():
    return {name: validate(name) for name in EQUATIONS}


def test_scores_count_what_they_say():
    perforated = np.array([True, True, True, False, False])
    called = np.array([True, False, False, True, False])
    s = Scores.of(perforated, called)
    assert (s.shots, s.perforated, s.correct, s.false_safe, s.false_alarm) == (5, 3, 2, 2, 1)
    assert (s.accuracy, s.false_safe_rate, s.false_alarm_rate) == (2 / 5, 2 / 3, 1 / 2)
    empty = Scores.of(np.array([], dtype=bool), np.array([], dtype=bool))
    assert empty.accuracy is None and empty.false_safe_rate is None and empty.false_alarm_rate is None
    assert json.loads(json.dumps(s.as_dict()))["false_safe_rate"] == pytest.approx(2 / 3)


def test_obliquity_bands():
    theta = np.array([0.0, 1e-9, 44.9, 45.0, 65.0, 65.01, 89.0])
    assert list(obliquity_band(theta)) == [OBLIQUITY_BANDS[i] for i in (0, 1, 1, 2, 2, 3, 3)]


@pytest.mark.parametrize("name", list(EQUATIONS))
def test_groups_add_up_and_calls_match_perforates(results, name):
    r = results[name]
    db = r.database
    for groups in (r.by_regime, r.by_obliquity):
        for field in ("shots", "perforated", "correct", "false_safe", "false_alarm"):
            assert sum(getattr(s, field) for s in groups.values()) == getattr(r.overall, field)
    assert r.overall.shots == len(db) and r.overall.perforated == db.perforated.sum()
    assert r.overall.correct + r.overall.false_safe + r.overall.false_alarm == r.overall.shots
    # every 25th shot through the public scalar API, with its own shield
    for i in range(0, len(db), 25):
        shield = WhippleShield(db.bumper_thickness_cm[i], db.wall_thickness_cm[i], db.spacing_cm[i],
                               db.wall_yield_ksi[i], db.bumper_density_g_cm3[i])
        assert perforates(shield, db.diameter_cm[i], db.velocity_km_s[i], db.obliquity_deg[i],
                          db.projectile_density_g_cm3[i], name) == r.called[i]
    d = json.loads(json.dumps(r.as_dict()))
    assert d["equation"] == name and d["overall"]["shots"] == len(db)
    assert set(d["by_regime"]) == {"ballistic", "shatter", "hypervelocity"}
    assert list(d["by_obliquity"]) == list(OBLIQUITY_BANDS)


def test_acceptance_2011_form(results):
    new, old = results["jsc2011"].overall, results["jsc1993"].overall
    assert new.accuracy >= 0.76
    assert new.false_safe < old.false_safe
    assert DEFAULT_EQUATION == "jsc2011"


def test_validate_on_a_subset_database(results):
    db = read_database()
    sub = db.subset(db.velocity_km_s > 7.0)
    r = validate("jsc1993", sub)
    assert r.overall.shots == len(sub)
    assert np.array_equal(r.called, results["jsc1993"].called[db.velocity_km_s > 7.0])


# ------------------------------------------------------------------ docs/ble.md records these numbers


def _percent(x):
    return f"{100 * x:.1f} %"


def _row(name, group, s):
    return (f"| {name} | {group} | {s.shots} | {_percent(s.accuracy)} | {_percent(s.false_safe_rate)} "
            f"({s.false_safe}/{s.perforated}) | {_percent(s.false_alarm_rate)} "
            f"({s.false_alarm}/{s.shots - s.perforated}) |")


def test_the_docs_record_the_measured_rates(results):
    # docs/ble.md includes the scores' table that the docs build generates (docs/_ext/impactdyn_vv.py)
    sys.path.insert(0, str(ROOT / "docs" / "_ext"))
    import impactdyn_vv

    section = (ROOT / "docs" / "ble.md").read_text() + impactdyn_vv.ble_scores_table()
    for name, r in results.items():
        rows = [("all shots", r.overall)] + [(f"regime: {k}", s) for k, s in r.by_regime.items()]
        if r.no_fixed_point:
            rows.append(("with a fixed point", r.with_fixed_point))
        for group, s in rows:
            assert _row(name, group, s) in section
    new = results["jsc2011"]
    right = new.overall.correct - new.with_fixed_point.correct
    assert f"The {new.no_fixed_point} shots on which `jsc2011` has no fixed point" in section
    assert f"{right} of the {new.no_fixed_point}\nare called right" in section
    assert f"`{DEFAULT_EQUATION}` (default)" in section
    shatter = int((np.isnan(new.limit.critical_diameter_cm) & (new.limit.regime == "shatter")).sum())
    assert re.search(rf"\({shatter} in the shatter regime", section)


# ------------------------------------------------------------------ plots


def test_plot_validation_with_a_configuration(tmp_path, results):
    shield = WhippleShield(0.16, 0.318, 10.16, 40.0)
    curves = [ballistic_limit_curve(shield, None, 0.0, 2.7, name) for name in EQUATIONS]
    near = nearby_shots(shield, 0.0)
    assert len(near) > 0 and near.perforated.any() and not near.perforated.all()
    out = plot_validation(list(results.values()), tmp_path / "v.png", curves, near, "t_b 0.16 cm")
    assert out.read_bytes()[:8] == PNG
    only = plot_validation([results["jsc1993"]], tmp_path / "one.png")
    assert only.read_bytes()[:8] == PNG
    assert sorted(p.name for p in tmp_path.iterdir()) == ["one.png", "v.png"]


def test_plot_ballistic_limit_draws_nearby_shots_and_missing_fixed_points(tmp_path, results):
    r = results["jsc2011"]
    db = r.database
    i = int(np.flatnonzero(np.isnan(r.limit.critical_diameter_cm) & (r.limit.regime == "hypervelocity"))[0])
    shield = WhippleShield(db.bumper_thickness_cm[i], db.wall_thickness_cm[i], db.spacing_cm[i],
                           db.wall_yield_ksi[i], db.bumper_density_g_cm3[i])
    curve = ballistic_limit_curve(shield, None, db.obliquity_deg[i], db.projectile_density_g_cm3[i], "jsc2011")
    assert np.isnan(curve.critical_diameter_cm).any()  # a dashed threshold where the curve has no fixed point
    assert json.loads(json.dumps(curve.as_dict()))["critical_diameter_cm"].count(None) == \
        np.isnan(curve.critical_diameter_cm).sum()
    near = nearby_shots(shield, db.obliquity_deg[i])
    assert db.line[i] in near.line
    p = plot_ballistic_limit([curve], tmp_path / "c.png", shots=near)
    assert p.read_bytes()[:8] == PNG


def test_shots_drawn_over_one_another_are_stacked_by_outcome_and_diameter_not_moved():
    from impactdyn.ble._plot import shot_stacks

    v = np.array([7.0, 7.1, 7.25, 8.0, 7.05, 7.0])
    d = np.array([0.318, 0.318, 0.3185, 0.318, 0.40, 0.635])
    # 7.0, 7.1 and 7.25 at one diameter (0.318 and 0.3185 within 1 %) chain within 0.2 km/s; 8.0 is apart;
    # 7.05 and 7.0 are alone on their own diameters
    assert [list(s) for s in shot_stacks(v, d, 0.2)] == [[0, 1, 2]]
    assert [list(s) for s in shot_stacks(v, d, 1.0)] == [[0, 1, 2, 3]]
    assert shot_stacks(v[:0], d[:0], 0.2) == []


def test_a_pile_of_test_shots_on_one_diameter_is_counted_on_the_limit_plot():
    """27 shots at 0.318 cm on a thick wall (13 of them held between 7.1 and 7.7 km/s): each stack of one outcome
    is counted where it lies, the markers stay where the tests were; the legend says what ×n is."""
    from impactdyn._plotting import pyplot
    from impactdyn.ble._plot import STACK_SPEED_SHARE, _draw_curves, shot_stacks

    shield = WhippleShield(0.064, 1.27, 5.08, 40.0)
    near = nearby_shots(shield, 0.0)
    curve = ballistic_limit_curve(shield, None, 0.0, 2.7)
    fig, ax = pyplot().subplots()
    _draw_curves(ax, [curve], shots=near)
    gap = STACK_SPEED_SHARE * (curve.velocity_km_s[-1] - curve.velocity_km_s[0])
    counts = sorted(int(t.get_text()[1:]) for t in ax.texts if t.get_text().startswith("×"))
    expected = sorted(len(s) for outcome in (True, False) for s in shot_stacks(
        near.velocity_km_s[near.perforated == outcome], near.diameter_cm[near.perforated == outcome], gap))
    assert counts == expected and max(counts) >= 10
    drawn = np.concatenate([c.get_offsets() for c in ax.collections if len(c.get_offsets())])
    assert len(drawn) == len(near)      # every shot drawn, at its own speed and diameter
    assert sorted(map(tuple, drawn)) == sorted(zip(near.velocity_km_s, near.diameter_cm))
    assert any(t.get_text().startswith("×n: n test shots of one outcome") for t in ax.get_legend().get_texts())
    pyplot().close(fig)
