"""`impactdyn whipple limit`: bisection of the simulated verdict in diameter, per velocity (issue 11).

The search logic is checked with a stand-in for the pipeline whose verdict changes at a
known diameter d*(V); the pipeline itself is exercised by the end-to-end tests.
"""

import csv
import json

import pytest

from impactdyn._config import load_toml, set_dotted
from impactdyn._errors import InputError
from impactdyn.whipple import _limit


def _fake_shots(monkeypatch, critical):
    """Replace the shot runner: 'perforation' iff d > critical(V); records the shots taken."""
    taken = []

    def run_shot(shot):
        p = shot.case.projectile
        taken.append((p.velocity_km_s, p.diameter_cm))
        shot.folder.mkdir(parents=True)
        return {"wall": {"verdict": "perforation" if p.diameter_cm > critical(p.velocity_km_s) else "no perforation"}}

    monkeypatch.setattr(_limit, "run_shot", run_shot)
    return taken


def test_bisection_brackets_the_change_of_verdict(tmp_path, make_case, monkeypatch):
    critical = lambda v: 0.30 + 0.03 * v  # noqa: E731
    taken = _fake_shots(monkeypatch, critical)
    raw = load_toml(make_case(tmp_path))
    rows = _limit.run_limit(raw, [4.0, 7.0, 10.0], tmp_path / "limit", tolerance_cm=0.01, scheduler="serial")
    for r in rows:
        assert r["status"] == "converged"
        assert r["largest_safe_cm"] <= critical(r["velocity_km_s"]) < r["smallest_failed_cm"]
        assert r["smallest_failed_cm"] - r["largest_safe_cm"] <= 0.01
        assert abs(r["limit_diameter_cm"] - critical(r["velocity_km_s"])) <= 0.005
    # every limit carries what the validation shots say; 10 km/s lies above their speeds
    assert all(r["caution"].startswith("on the validation shots") for r in rows)
    assert ["km/s is outside" in r["caution"] for r in rows] == [False, False, True]
    # each velocity's shots: 2 to bracket, then about log2(width / tolerance) halvings
    assert len(taken) == sum(r["n_shots"] for r in rows) <= 3 * 12
    out = tmp_path / "limit"
    assert len(list(csv.DictReader((out / "shots.csv").open()))) == len(taken)
    assert json.loads((out / "limit.json").read_text())["rows"] == json.loads(json.dumps(rows))
    assert (out / "limit.png").stat().st_size > 10_000


def test_a_bracket_bisected_down_to_the_tolerance_is_converged(tmp_path, make_case, monkeypatch):
    """0.62–0.78 cm halved three times is 0.02 cm wide, the tolerance, only to round-off (0.72 − 0.70 =
    0.02000000000000002): the search stops there (5 shots), not a round later."""
    taken = _fake_shots(monkeypatch, lambda v: 0.705)
    raw = load_toml(make_case(tmp_path))
    rows = _limit.run_limit(raw, [7.0], tmp_path / "limit", tolerance_cm=0.02, brackets={7.0: (0.62, 0.78)},
                            scheduler="serial")
    assert rows[0]["status"] == "converged" and len(taken) == 5
    assert (rows[0]["largest_safe_cm"], rows[0]["smallest_failed_cm"]) == pytest.approx((0.70, 0.72))


def test_the_limit_plot_draws_the_shots_the_limit_and_the_nearby_test_shots(tmp_path, make_case, monkeypatch):
    import impactdyn.ble
    from impactdyn.ble import ShotDatabase

    drawn = {}
    monkeypatch.setattr(impactdyn.ble, "plot_ballistic_limit", lambda curves, path, **kw: drawn.update(kw))
    taken = _fake_shots(monkeypatch, lambda v: 0.45)
    rows = _limit.run_limit(load_toml(make_case(tmp_path)), [6.0, 7.0], tmp_path / "limit", tolerance_cm=0.02,
                            scheduler="serial")
    assert isinstance(drawn["shots"], ShotDatabase)
    v, d, failed = drawn["simulated"]
    assert sorted(zip(v, d)) == sorted(taken) and list(failed) == [di > 0.45 for di in d]
    v_lim, d_lim, half, label = drawn["limit"]
    assert list(v_lim) == [6.0, 7.0] and list(d_lim) == [r["limit_diameter_cm"] for r in rows]
    assert list(half) == [r["half_width_cm"] for r in rows] and "0.02 cm" in label


def test_a_limit_out_of_reach_is_reported_unbracketed(tmp_path, make_case, monkeypatch):
    _fake_shots(monkeypatch, lambda v: 50.0)  # never perforates at any diameter the search may try
    raw = load_toml(make_case(tmp_path))
    (row,) = _limit.run_limit(raw, [7.0], tmp_path / "limit", tolerance_cm=0.01, max_expansions=2,
                              scheduler="serial")
    assert row["status"] == "unbracketed" and row["limit_diameter_cm"] is None
    assert row["smallest_failed_cm"] is None and row["n_shots"] == 2 + 3


def test_a_given_start_bracket_replaces_the_jsc_one(tmp_path, make_case, monkeypatch):
    critical = lambda v: 1.03  # noqa: E731  far above the JSC diameter, where a first search needs many shots
    taken = _fake_shots(monkeypatch, critical)
    raw = load_toml(make_case(tmp_path))
    rows = _limit.run_limit(raw, [4.0, 7.0], tmp_path / "limit", tolerance_cm=0.05, scheduler="serial",
                            brackets={7.0: (0.97, 1.06)})
    by_v = {r["velocity_km_s"]: r for r in rows}
    # both ends shot again, then one halving
    assert [d for v, d in taken if v == 7.0] == pytest.approx([0.97, 1.06, 1.015])
    assert by_v[7.0]["status"] == "converged" and by_v[7.0]["n_shots"] == 3
    assert by_v[4.0]["n_shots"] > 3 and by_v[4.0]["largest_safe_cm"] <= 1.03 < by_v[4.0]["smallest_failed_cm"]
    start = json.loads((tmp_path / "limit" / "limit.json").read_text())["start_brackets_cm"]
    assert start["7"] == [0.97, 1.06] and start["4"] != [0.97, 1.06]


@pytest.mark.parametrize("kwargs, message", [
    (dict(tolerance_cm=0.0), "--tolerance 0.0: must be > 0"),
    (dict(bracket_ratio=1.0), "--bracket-ratio 1.0: must be > 1"),
    (dict(brackets={5.0: (0.9, 1.1)}), "--bracket 5:0.9:1.1: 5 km/s is not one of the --velocity values"),
    (dict(brackets={7.0: (1.1, 0.9)}), "--bracket 7:1.1:0.9: needs 0 < LOW < HIGH"),
])
def test_bad_search_settings(tmp_path, make_case, kwargs, message):
    raw = load_toml(make_case(tmp_path))
    with pytest.raises(InputError, match=message.replace("+", r"\+")):
        _limit.run_limit(raw, [7.0], tmp_path / "limit", scheduler="serial", **kwargs)
    assert not (tmp_path / "limit").exists()


def test_a_lean_shot_folder_keeps_what_a_user_reads(tmp_path):
    from impactdyn.whipple._stages import prune_run

    keep = ["summary.json", "report.html", "case.toml", "plots/ballistic_limit.png", "wall/stage.json",
            "wall/wall.json", "wall/plots/wall_rear.png", "debris/areal_density.csv", "debris/summary.json"]
    drop = ["shield/particles.h5", "binning/handoff_grid.h5", "debris/debris.h5", "debris/particles_arrival.vtu",
            "wall/wall.pvd", "wall/wall_series/frame_0001.vtu", "decks/wall.k", "decks/wall_dyna3d.inp"]
    for name in keep + drop:
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(name)
    prune_run(tmp_path)
    assert sorted(p.relative_to(tmp_path).as_posix() for p in tmp_path.rglob("*") if p.is_file()) == sorted(keep)
    assert not (tmp_path / "wall" / "wall_series").exists() and not (tmp_path / "decks").exists()


def test_family_shots_keep_the_base_cases_resolution_and_timing(make_case, tmp_path):
    """A slower shot gets a proportionally longer hand-off and arrival window (the flight takes
    1/V as long), a smaller projectile a proportionally finer SPH spacing; faster and larger
    shots keep the base case's."""
    from impactdyn.whipple import load_whipple_case
    from impactdyn.whipple._shots import shot_variant

    base = load_whipple_case(make_case(tmp_path))
    v0, d0 = base.projectile.velocity_km_s, base.projectile.diameter_cm
    slow = shot_variant(base, v0 / 2, d0 / 2)
    assert slow["filter.t_cut_us"] == pytest.approx(2 * base.filter.t_cut_us)
    assert slow["shield.handoff_us"] == pytest.approx(2 * base.shield.handoff_us)
    assert slow["shield.spacing_cm"] == pytest.approx(base.shield.spacing_cm / 2)
    fast = shot_variant(base, 2 * v0, 2 * d0)
    assert fast["filter.t_cut_us"] == base.filter.t_cut_us and fast["shield.handoff_us"] == base.shield.handoff_us
    assert fast["shield.spacing_cm"] == base.shield.spacing_cm
    assert (fast["projectile.velocity_km_s"], fast["projectile.diameter_cm"]) == (2 * v0, 2 * d0)
    # a family's shot is not the test its base case may reproduce: its report must not claim the test's outcome
    from impactdyn._sweep import case_variants
    from impactdyn.whipple import WhippleCase, database_shot

    tested = set_dotted(load_toml(make_case(tmp_path)), "test_shot", database_shot("B31").record.model_dump())
    assert WhippleCase.model_validate(tested).test_shot is not None
    assert [c.test_shot for c in case_variants(WhippleCase, tested, [slow, fast])] == [None, None]


def test_an_interrupted_search_keeps_its_table_and_resumes_without_repeating_a_shot(tmp_path, make_case,
                                                                                     monkeypatch):
    from impactdyn._errors import Interrupted

    critical = lambda v: 0.30 + 0.03 * v  # noqa: E731
    raw = load_toml(make_case(tmp_path))
    whole = _fake_shots(monkeypatch, critical)
    expected = _limit.run_limit(raw, [4.0, 7.0], tmp_path / "whole", tolerance_cm=0.01, scheduler="serial")

    taken = []

    def run_shot(shot, stop_at=5):
        if len(taken) == stop_at:
            raise KeyboardInterrupt
        p = shot.case.projectile
        taken.append((p.velocity_km_s, p.diameter_cm))
        shot.folder.mkdir(parents=True)
        verdict = "perforation" if p.diameter_cm > critical(p.velocity_km_s) else "no perforation"
        (shot.folder / "summary.json").write_text(json.dumps({"wall": {"verdict": verdict}}))
        return {"wall": {"verdict": verdict}}

    monkeypatch.setattr(_limit, "run_shot", run_shot)
    out = tmp_path / "limit"
    with pytest.raises(Interrupted, match="5 finished shots and limit.csv kept"):
        _limit.run_limit(raw, [4.0, 7.0], out, tolerance_cm=0.01, scheduler="serial")
    assert len(list(csv.DictReader((out / "shots.csv").open()))) == 5
    assert {r["status"] for r in csv.DictReader((out / "limit.csv").open())} == {"searching"}

    monkeypatch.setattr(_limit, "run_shot", lambda shot: run_shot(shot, stop_at=-1))
    rows = _limit.run_limit(raw, [4.0, 7.0], out, tolerance_cm=0.01, scheduler="serial", resume=True)
    assert rows == expected
    assert sorted(taken) == sorted(whole) and len(set(taken)) == len(taken), "a kept shot was run again"
    with pytest.raises(InputError, match=r"other settings \(tolerance_cm\)"):
        _limit.run_limit(raw, [4.0, 7.0], out, tolerance_cm=0.02, scheduler="serial", resume=True)


def test_the_limit_fitted_to_the_tests_of_the_configuration_is_drawn_where_it_exists(tmp_path, make_case,
                                                                                    monkeypatch):
    import impactdyn.ble
    from impactdyn.ble import Configuration, DerivedLimit, LimitFit

    drawn = {}
    monkeypatch.setattr(impactdyn.ble, "plot_ballistic_limit", lambda curves, path, **kw: drawn.update(kw))
    _fake_shots(monkeypatch, lambda v: 0.45)
    raw = load_toml(make_case(tmp_path))
    _limit.run_limit(raw, [7.0], tmp_path / "real", tolerance_cm=0.05, scheduler="serial")
    assert drawn["tested"] is None, "the packaged database has no fitted limit for the Table 2 shield"

    case = _limit.validate(_limit.WhippleCase, raw)
    p, b, w = case.projectile, case.bumper, case.wall
    fit = LimitFit(shots=9, perforated=5, d50_cm=0.4, low_cm=None, high_cm=0.5, slope=5.0, largest_held_cm=0.45,
                   smallest_perforated_cm=0.38, refused=None, confidence=0.95)
    here = Configuration("AA6061-T6", "AA6061-T6", "AA6061-T6", 1.02 * b.thickness_cm, w.thickness_cm,
                         w.spacing_cm, p.obliquity_deg + 1.0)
    elsewhere = Configuration("AA6061-T6", "AA6061-T6", "AA6061-T6", 1.2 * b.thickness_cm, w.thickness_cm,
                              w.spacing_cm, p.obliquity_deg)
    monkeypatch.setattr(impactdyn.ble, "derived_limits", lambda db: [
        DerivedLimit(here, 6.0, 7.0, (1,), fit), DerivedLimit(elsewhere, 6.0, 7.0, (2,), fit)])
    _limit.run_limit(raw, [7.0], tmp_path / "fitted", tolerance_cm=0.05, scheduler="serial")
    v, low, d50, high, half_band = drawn["tested"]
    assert (v, low, d50, high, half_band) == ((6.5,), (0.0,), (0.4,), (0.5,), (0.5,))


def _fake_draws(monkeypatch, probability):
    """Replace the shot runner: of its N draws, round(N P(d)) perforate (a deterministic stand-in for the
    partition's draws); records the shots taken."""
    taken = []

    def run_shot(shot):
        p, n = shot.case.projectile, shot.case.shield.fragment_draws
        k = round(n * probability(p.diameter_cm))
        taken.append((p.diameter_cm, k, n))
        shot.folder.mkdir(parents=True)
        return {"wall": {"verdict": "perforation" if 2 * k >= n else "no perforation"},
                "draws": {"perforated": k, "n_draws": n}}

    monkeypatch.setattr(_limit, "run_shot", run_shot)
    return taken


def _grady(tmp_path, make_case):
    from impactdyn._config import set_dotted

    raw = set_dotted(load_toml(make_case(tmp_path)), "shield.failure_model", "fragmentation")
    return set_dotted(raw, "shield.failed_fragments", "grady")


def test_with_draws_the_search_closes_on_half_and_the_logistic_gives_the_band(tmp_path, make_case, monkeypatch):
    """Draws from a known logistic in ln d (d50 = 0.5 cm, slope 12): the bisection on k/N ≥ 1/2 closes on
    d50, and the fit over every draw finds d50 and the band d50 exp(∓ln 9 / 12) = 0.4167–0.6000 cm."""
    import math

    d50, slope = 0.5, 12.0
    taken = _fake_draws(monkeypatch, lambda d: 1.0 / (1.0 + math.exp(-slope * math.log(d / d50))))
    rows = _limit.run_limit(_grady(tmp_path, make_case), [7.0], tmp_path / "limit", tolerance_cm=0.005,
                            brackets={7.0: (0.3, 0.8)}, draws=64, scheduler="serial")
    r = rows[0]
    assert r["status"] == "converged" and all(n == 64 for *_, n in taken)
    assert r["largest_safe_cm"] <= d50 + 0.005 and r["smallest_failed_cm"] >= d50 - 0.005
    assert r["draws_d50_cm"] == pytest.approx(d50, rel=0.02)
    assert r["draws_d50_low_cm"] < r["draws_d50_cm"] < r["draws_d50_high_cm"]
    spread = math.exp(math.log(9.0) / slope)
    assert r["p10_diameter_cm"] == pytest.approx(d50 / spread, rel=0.03)
    assert r["p90_diameter_cm"] == pytest.approx(d50 * spread, rel=0.03)
    shots = list(csv.DictReader((tmp_path / "limit" / "shots.csv").open()))
    assert [(float(s["diameter_cm"]), int(s["perforated_draws"]), int(s["n_draws"])) for s in shots] == taken


def test_draws_that_never_disagree_give_no_band_and_say_why(tmp_path, make_case, monkeypatch):
    _fake_draws(monkeypatch, lambda d: float(d > 0.5))
    rows = _limit.run_limit(_grady(tmp_path, make_case), [7.0], tmp_path / "limit", tolerance_cm=0.02,
                            brackets={7.0: (0.3, 0.8)}, draws=4, scheduler="serial")
    r = rows[0]
    assert r["status"] == "converged" and r["largest_safe_cm"] <= 0.5 < r["smallest_failed_cm"]
    assert r["p10_diameter_cm"] is None and r["draws_d50_cm"] is None
    assert "separable" in r["band_note"]


def test_one_draw_a_shot_gives_no_band(tmp_path, make_case, monkeypatch):
    _fake_shots(monkeypatch, lambda v: 0.5)
    rows = _limit.run_limit(load_toml(make_case(tmp_path)), [7.0], tmp_path / "limit", tolerance_cm=0.02,
                            brackets={7.0: (0.3, 0.8)}, scheduler="serial")
    assert rows[0]["band_note"] is None and rows[0]["p10_diameter_cm"] is None


@pytest.mark.parametrize("draws", [0, -3, 65])
def test_a_bad_number_of_draws_is_refused_naming_the_key(tmp_path, make_case, monkeypatch, draws):
    taken = _fake_draws(monkeypatch, lambda d: 0.5)
    with pytest.raises(InputError, match="fragment_draws"):
        _limit.run_limit(_grady(tmp_path, make_case), [7.0], tmp_path / "limit", draws=draws, scheduler="serial")
    assert taken == [] and not (tmp_path / "limit").exists()
