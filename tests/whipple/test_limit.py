"""`impactdyn whipple limit`: bisection of the simulated verdict in diameter, per velocity (issue 11).

The search logic is checked with a stand-in for the pipeline whose verdict changes at a
known diameter d*(V); the pipeline itself is exercised by the end-to-end tests.
"""

import csv
import json

import pytest

from impactdyn._config import load_toml
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
    # each velocity's shots: 2 to bracket, then about log2(width / tolerance) halvings
    assert len(taken) == sum(r["n_shots"] for r in rows) <= 3 * 12
    out = tmp_path / "limit"
    assert len(list(csv.DictReader((out / "shots.csv").open()))) == len(taken)
    assert json.loads((out / "limit.json").read_text())["rows"] == json.loads(json.dumps(rows))
    assert (out / "limit.png").stat().st_size > 10_000


def test_a_limit_out_of_reach_is_reported_unbracketed(tmp_path, make_case, monkeypatch):
    _fake_shots(monkeypatch, lambda v: 50.0)  # never perforates at any diameter the search may try
    raw = load_toml(make_case(tmp_path))
    (row,) = _limit.run_limit(raw, [7.0], tmp_path / "limit", tolerance_cm=0.01, max_expansions=2,
                              scheduler="serial")
    assert row["status"] == "unbracketed" and row["limit_diameter_cm"] is None
    assert row["smallest_failed_cm"] is None and row["n_shots"] == 2 + 3


@pytest.mark.parametrize("kwargs, message", [
    (dict(tolerance_cm=0.0), "--tolerance 0.0: must be > 0"),
    (dict(bracket_ratio=1.0), "--bracket-ratio 1.0: must be > 1"),
])
def test_bad_search_settings(tmp_path, make_case, kwargs, message):
    from impactdyn import InputError

    raw = load_toml(make_case(tmp_path))
    with pytest.raises(InputError, match=message.replace("+", r"\+")):
        _limit.run_limit(raw, [7.0], tmp_path / "limit", scheduler="serial", **kwargs)
    assert not (tmp_path / "limit").exists()
