"""`impactdyn whipple validate`: a selection of test shots run and scored; killed mid-run, it resumes
without running a finished shot again."""

import csv
import json
import os
import signal

import pytest

from impactdyn.cli import main
from impactdyn.whipple._selection import RULES_DIR


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
    assert (out / "validation.png").is_file() and "Scores by distance" in page and "<td>&lt;5%</td>" in page
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
