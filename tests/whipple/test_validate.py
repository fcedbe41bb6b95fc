"""`impactdyn whipple validate`: a selection of test shots run and scored; killed mid-run, it resumes
without running a finished shot again."""

import csv
import json
import os
import signal

import html
from pathlib import Path

import pytest

from impactdyn.cli import main
from impactdyn.whipple._selection import RULES_DIR

EXAMPLES = Path(__file__).parents[2] / "examples" / "whipple"


def _three_shot_rule(tmp_path):
    """Set 1's rule cut to its two nearest perforated shots and its nearest held one."""
    text = (RULES_DIR / "set-1.toml").read_text()
    text = text[:text.index("[fixed]")].replace('name = "set-1"', 'name = "three"')
    path = tmp_path / "three.toml"
    path.write_text(text.replace("perforated = 6", "perforated = 2").replace("held = 6", "held = 1")
                    .replace("min_oblique = 3", "min_oblique = 0"))
    return path


def test_validate_runs_scores_and_resumes_after_a_kill(tmp_path, make_case, cli):
    rule = _three_shot_rule(tmp_path)
    out = tmp_path / "validation"
    args = ["whipple", "validate", "--select", str(rule), "--from-case", str(make_case(tmp_path)),
            "--workers", "2", "-o", str(out)]
    command = cli.start(args, tmp_path)
    command.wait_for(lambda: len(cli.finished(out, "runs")) >= 1, timeout=400, what="finished shot")
    os.killpg(command.proc.pid, signal.SIGKILL)  # no tidying at all: resume must cope with what is left
    command.proc.wait()
    kept = {p.name: (p / "summary.json").stat().st_mtime_ns for p in cli.finished(out, "runs")}
    assert 1 <= len(kept) < 3

    resumed = cli.run(args + ["--resume"], tmp_path)
    assert resumed.returncode == 0, resumed.stderr
    assert {p.name: (p / "summary.json").stat().st_mtime_ns for p in cli.finished(out, "runs") if p.name in kept} \
        == kept, "a finished shot was run again"
    rows = list(csv.DictReader((out / "validation.csv").open()))
    assert len(rows) == 3 and sum(r["test_perforated"] == "True" for r in rows) == 2
    for r in rows:
        assert (r["simulated_right"] == "True") == (r["simulated_perforated"] == r["test_perforated"])
        assert abs(float(r["d_over_limit"]) * float(r["jsc_limit_cm"]) - float(r["diameter_cm"])) < 1e-9
    scores = json.loads((out / "scores.json").read_text())
    assert scores["n_shots"] == 3 and scores["simulated"]["overall"]["shots"] == 3
    assert scores["simulated"]["overall"]["accuracy"]["count"] == sum(r["simulated_right"] == "True" for r in rows)
    assert scores["selection"]["rule"] == "three" and scores["selection"]["fixed"] is None
    page = (out / "validation.html").read_text()
    assert (out / "validation.png").is_file() and "Scores by distance" in page and "<td>&lt; 5 %</td>" in page
    assert cli.hidden(out) == []


@pytest.mark.parametrize("args, message", [
    (["--lines", "99999"], "no shot at line 99999"),
    (["--lines", "x1"], "x1"),
    (["--select", "set-9"], "set-9: no such rule file"),
    ([], "give --select RULE or --lines"),
    (["--select", "set-1", "--lines", "136"], "give --select RULE or --lines"),
])
def test_bad_selections_exit_2_and_write_nothing(tmp_path, capsys, args, message):
    out = tmp_path / "validation"
    assert main(["whipple", "validate", "-o", str(out), *args]) == 2
    assert message in capsys.readouterr().err
    assert not out.exists()


def test_a_changed_fixed_rule_is_refused(tmp_path, capsys):
    path = tmp_path / "set-1.toml"
    path.write_text((RULES_DIR / "set-1.toml").read_text().replace("held = 6", "held = 5"))
    assert main(["whipple", "validate", "--select", str(path), "-o", str(tmp_path / "v")]) == 2
    assert "changed after it was fixed" in capsys.readouterr().err and not (tmp_path / "v").exists()


def test_fix_rule_stamps_a_new_rule(tmp_path):
    rule = _three_shot_rule(tmp_path)
    assert main(["whipple", "fix-rule", str(rule)]) == 0
    assert "[fixed]" in rule.read_text()


def _rows(lines, perforated, d_over_limit):
    """Rows of validation.csv for shots on ``lines`` (no simulation run): the test's outcome, the simulation
    calling every shot perforated, the equation calling those above its limit."""
    return [{"line": line, "source": "TP", "shot_id": f"S{line}", "diameter_cm": 0.5, "velocity_km_s": 6.5,
             "obliquity_deg": 0.0, "normal_velocity_km_s": 6.5, "jsc_limit_cm": 0.5 / r, "d_over_limit": r,
             "test_perforated": p, "jsc_perforated": r > 1, "simulated_verdict": "perforation",
             "simulated_perforated": True, "simulated_right": p, "jsc_right": (r > 1) == p, "n_draws": None,
             "p_perforation": None, "caution": "", "run": f"runs/line{line}"}
            for line, p, r in zip(lines, perforated, d_over_limit)]


def test_the_page_says_the_selection_the_case_and_the_outcomes_in_words():
    """validation.html of a synthetic table: the lines given in words, the case's settings off the package's
    defaults with what stands behind its verdict, the bands as people write them, one vocabulary of outcomes."""
    from impactdyn.whipple import load_whipple_case
    from impactdyn.whipple._report import FRAGMENTS_VALIDATION, verdict_record
    from impactdyn.whipple._validate import score_validation, validation_page

    rows = _rows([45, 67, 80], [True, False, True], [1.02, 0.8, 1.5])
    scores = score_validation(rows) | {"selection": {"lines": [45, 67, 80]}}
    case = load_whipple_case(EXAMPLES / "table2_7a_fragments.toml")
    page = html.unescape(validation_page(rows, scores, "table2_7a_fragments.toml",
                                         {"shield.failed_fragments": "grady", "integrator.method": "slow"},
                                         verdict_record(case)))
    assert "Selection:</strong> lines 45, 67, 80 of the test database (3 shots)</p>" in page
    assert '<li><code>[shield] failed_fragments = "grady"</code></li><li><code>[integrator] method = "slow"' in page
    assert FRAGMENTS_VALIDATION in page and "{" not in page.split("<body>")[1]   # no raw JSON
    for band in ("< 5 %", "5–15 %", "15–30 %", "≥ 30 %", "all"):
        assert f"<td>{band}</td>" in page
    assert "5-15%" not in page and ">=30%" not in page
    # the outcomes and calls in the report's words, never P / NP
    assert "<td>perforation or detached spall</td><td>perforation</td><td>perforation</td>" in page  # line 45
    assert "<td>no perforation</td><td>no perforation</td><td>perforation</td>" in page             # line 67
    assert "<td>P</td>" not in page and "<td>NP</td>" not in page and "held" not in page


def test_a_shipped_rule_is_named_with_its_description_and_another_by_its_hash():
    from impactdyn.whipple import load_rule, rule_hash
    from impactdyn.whipple._validate import selection_statement

    rule = load_rule("set-1")
    shipped = selection_statement({"rule": "set-1", "sha256": rule_hash(rule), "fixed": rule.fixed.date})
    assert shipped == f"the shots of the shipped rule set-1 (fixed on {rule.fixed.date}): {rule.description}"
    # a rule file that takes a shipped rule's name is not that rule
    other = selection_statement({"rule": "set-1", "sha256": "ab" * 32, "fixed": None})
    assert other == "the shots of rule set-1 (not fixed: these scores cannot judge a change; sha256 abababababab…)"
    assert selection_statement({"lines": [136]}) == "lines 136 of the test database (1 shot)"


def test_a_case_at_the_package_defaults_says_so():
    from impactdyn.whipple._validate import score_validation, validation_page

    rows = _rows([45], [True], [1.2])
    page = validation_page(rows, score_validation(rows) | {"selection": {"lines": [45]}}, "case.toml", {}, "")
    assert "from the package's defaults: none: the shots' numerics are the package's defaults." in page


def test_the_case_options_are_the_settings_off_the_package_defaults_the_shots_own_left_out():
    from impactdyn._config import set_dotted
    from impactdyn.whipple import WhippleCase, database_shot, database_shot_case
    from impactdyn.whipple._validate import case_options

    shot = database_shot("B31")   # its stand-off rescales the wall grid and the window: the shot's, not options
    base = EXAMPLES / "table2_7a_fragments.toml"
    raw = database_shot_case(shot, base)
    assert case_options(shot, WhippleCase.model_validate(raw), base) == {
        "shield.failed_fragments": "grady", "shield.failure_model": "fragmentation", "integrator.method": "slow"}
    # --draws is an option every shot shares
    drawn = WhippleCase.model_validate(set_dotted(raw, "shield.fragment_draws", 5))
    assert case_options(shot, drawn, base)["shield.fragment_draws"] == 5
    assert case_options(shot, WhippleCase.model_validate(database_shot_case(shot)), None) == {
        "integrator.method": "slow"}
