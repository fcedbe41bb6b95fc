"""The validation record: its sets are the fixed rules' shots, what a user reads first quotes its figures,
a rerun set's folder rebuilds its entry, and the report puts the limit at its top."""

import csv
import json
import re
import shutil
from pathlib import Path

import pytest

from impactdyn._errors import InputError
from impactdyn.ble import read_database
from impactdyn.whipple import (database_shot, limit_statement, load_rule, load_whipple_case, record_validation,
                               rule_hash, score_validation, select_shots, validation_record)
from impactdyn.whipple._report import WALL_VALIDATION, _top
from impactdyn.whipple._validation_record import RECORD_PATH, quoted_figures

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples" / "whipple"


def _words(text: str) -> str:
    """Text with line breaks and runs of spaces made single spaces (the pages wrap their lines)."""
    return re.sub(r"\s+", " ", text)


@pytest.mark.parametrize("entry", validation_record().sets, ids=lambda s: s.name)
def test_each_recorded_set_is_its_fixed_rules_shots(entry):
    rule = load_rule(entry.name)
    assert rule.fixed is not None and entry.rule_sha256 == rule_hash(rule), "the rule changed since the set was run"
    db = read_database()
    shots = [database_shot(int(db.line[i]), db) for i in select_shots(rule, db)]
    assert entry.shots == len(shots) and entry.perforated == sum(s.perforated for s in shots)
    assert entry.diameter_cm == (min(s.diameter_cm for s in shots), max(s.diameter_cm for s in shots))
    assert entry.velocity_km_s == (min(s.velocity_km_s for s in shots), max(s.velocity_km_s for s in shots))
    for score in (entry.simulated, entry.jsc):
        assert 0 <= score.false_safe <= entry.perforated and 0 <= score.false_alarm <= entry.shots - entry.perforated
        assert score.right == entry.shots - score.false_safe - score.false_alarm
    assert f"--select {entry.name} " in entry.command


def test_the_readme_first_screen_and_the_landing_page_quote_the_record():
    first_screen = _words("\n".join((ROOT / "README.md").read_text().splitlines()[:40]))
    landing = _words((ROOT / "docs" / "index.md").read_text())
    record = validation_record()
    for page, text in (("README.md (first 40 lines)", first_screen), ("docs/index.md", landing)):
        missing = [f for f in quoted_figures(record) if f not in text]
        assert missing == [], f"{page} does not quote the validation record's {missing}"
        assert record.set_names in text, f"{page} does not name {record.set_names}"


def test_the_readme_stays_short():
    assert len((ROOT / "README.md").read_text().splitlines()) <= 150


def test_the_limit_statement_and_the_caution_follow_the_record():
    record = validation_record()
    statement = limit_statement(record)
    assert all(f in statement for f in quoted_figures(record))
    assert "every tested perforation safe (18 of 18)" in statement  # the sets as recorded now
    assert WALL_VALIDATION.startswith("on the validation shots the wall stage called every tested perforation safe "
                                      f"({record.simulated.false_safe} of {record.perforated})")


def _validate_folder(folder: Path, rule="set-9", complete=True) -> Path:
    """A finished `whipple validate` folder of three shots: two perforated (one called so), one held."""
    rows = [{"line": 1, "diameter_cm": 0.30, "velocity_km_s": 6.5, "d_over_limit": 1.2, "test_perforated": True,
             "simulated_perforated": True, "jsc_perforated": True},
            {"line": 2, "diameter_cm": 0.50, "velocity_km_s": 4.0, "d_over_limit": 1.1, "test_perforated": True,
             "simulated_perforated": False, "jsc_perforated": True},
            {"line": 3, "diameter_cm": 0.40, "velocity_km_s": 7.1, "d_over_limit": 0.9, "test_perforated": False,
             "simulated_perforated": False, "jsc_perforated": True}]
    folder.mkdir()
    (folder / "family.json").write_text(json.dumps({"command": "whipple validate", "complete": complete}))
    scores = score_validation(rows) | {"selection": {"rule": rule, "sha256": "ab12", "fixed": "2026-01-01"}}
    (folder / "scores.json").write_text(json.dumps(scores))
    with (folder / "validation.csv").open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    return folder


def test_a_rerun_sets_folder_rebuilds_its_entry_in_the_record(tmp_path):
    record_file = tmp_path / "record.json"
    shutil.copy(RECORD_PATH, record_file)
    before = validation_record(record_file)
    command = "impactdyn whipple validate --select set-9 -o runs/v"
    after = record_validation(_validate_folder(tmp_path / "v"), command, record_file)
    entry = after.sets[-1]
    assert (entry.name, entry.command, entry.shots, entry.perforated) == ("set-9", command, 3, 2)
    assert (entry.diameter_cm, entry.velocity_km_s) == ((0.30, 0.50), (4.0, 7.1))
    assert (entry.simulated.right, entry.simulated.false_safe, entry.simulated.false_alarm) == (2, 1, 0)
    assert (entry.jsc.right, entry.jsc.false_safe, entry.jsc.false_alarm) == (2, 0, 1)
    assert after.shots == before.shots + 3 and after.set_names == "sets 1, 2, 3 and 9"
    # not every perforation called safe any more: the words say how many
    assert "called 19 of 20 tested perforations safe" in limit_statement(after)
    # the same set rerun replaces its entry
    shutil.rmtree(tmp_path / "v")
    again = record_validation(_validate_folder(tmp_path / "v"), command + " --workers 2", record_file)
    assert [s.name for s in again.sets] == [s.name for s in after.sets]
    assert again.sets[-1].command.endswith("--workers 2")


@pytest.mark.parametrize("spoil, message", [
    (lambda f: (f / "scores.json").unlink(), r"scores\.json: missing"),
    (lambda f: (f / "validation.csv").unlink(), r"validation\.csv: missing"),
    (lambda f: (f / "scores.json").write_text("{"), r"scores\.json: line 1: not JSON"),
    (lambda f: (f / "family.json").write_text('{"command": "whipple validate", "complete": false}'),
     r"family\.json: not a finished `whipple validate` folder"),
    (lambda f: (f / "scores.json").write_text('{"selection": {"lines": [1, 2]}}'), r"chosen by --lines"),
    (lambda f: (f / "scores.json").write_text('{"selection": {"rule": "x"}}'), r"scores\.json: not the scores"),
], ids=["no-scores", "no-table", "bad-json", "unfinished", "lines", "not-scores"])
def test_a_folder_that_is_not_a_finished_set_changes_nothing(tmp_path, spoil, message):
    record_file = tmp_path / "record.json"
    shutil.copy(RECORD_PATH, record_file)
    folder = _validate_folder(tmp_path / "v")
    spoil(folder)
    with pytest.raises(InputError, match=message):
        record_validation(folder, "impactdyn whipple validate --select set-9", record_file)
    assert record_file.read_bytes() == RECORD_PATH.read_bytes()


def test_the_report_opens_with_a_banner_where_the_verdicts_differ_and_always_with_the_caution():
    caution = "on the validation shots the wall stage called every tested perforation safe"
    ble = {"equation": "jsc2011", "verdict": "perforation"}
    default = load_whipple_case(EXAMPLES / "table2_7a.toml")
    clash = _top({"verdict": "no perforation", "agrees_with_equation": False, "caution": caution}, ble, default)
    assert clash.startswith('<div class="banner"') and clash.index("banner") < clash.index(caution)
    assert "simulated wall: no perforation; jsc2011: perforation" in clash
    assert all(f in clash for f in quoted_figures())
    agree = _top({"verdict": "perforation", "agrees_with_equation": True, "caution": caution}, ble, default)
    assert "banner" not in agree and caution in agree
    # with the fragments the banner says what stands behind that case's verdict, not the default wall's record
    fragments = load_whipple_case(EXAMPLES / "table2_7a_fragments.toml")
    clash = _top({"verdict": "perforation", "agrees_with_equation": False, "caution": caution},
                 {"equation": "jsc2011", "verdict": "no perforation"}, fragments)
    assert "simulated wall: perforation; jsc2011: no perforation" in clash
    assert "no validation set has judged" in clash and "not evidence" not in clash
    assert not any(f in clash for f in quoted_figures())
