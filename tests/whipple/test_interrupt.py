"""Ctrl-C stops the Whipple commands: exit 130 within seconds, no process of ours left, no staging
folder left; a limit search keeps its finished shots and table, and ``--resume`` finishes it."""

import csv
import json
import time
from pathlib import Path

#: Seconds the contract allows from the interrupt to the exit.
EXIT_WITHIN_S = 10.0


def test_whipple_limit_stops_on_ctrl_c_keeps_its_finished_shots_and_resumes(tmp_path, make_case, cli):
    case = make_case(tmp_path)
    # one shot in this process first: the kernels are compiled (and cached) once, not by both workers at
    # once, so the interrupt comes while shots run
    assert cli.run(["whipple", "run", str(case), "-o", str(tmp_path / "warm")], tmp_path).returncode == 0
    out = tmp_path / "limit"
    args = ["whipple", "limit", str(case), "--velocity", "6:7:2", "--bracket", "6:0.3:0.45",
            "--bracket", "7:0.3:0.45", "--tolerance", "0.5", "--workers", "2", "-o", str(out)]
    command = cli.start(args, tmp_path)
    # four shots in the first round on two workers: interrupt once one has finished and others run
    command.wait_for(lambda: len(cli.finished(out, "runs")) >= 1, timeout=300, what="finished shot")
    took, err = command.interrupt()

    assert command.returncode == 130, err
    assert took < EXIT_WITHIN_S, f"exit {took:.1f} s after Ctrl-C"
    assert "Traceback" not in err and "interrupted:" in err and "--resume" in err, err
    assert command.group_is_empty(), "a process of the command outlived it"
    assert cli.hidden(out) == [] and cli.hidden(tmp_path) == [], "a staging folder or temporary file was left"
    kept = cli.finished(out, "runs")
    assert sorted(p.name for p in (out / "runs").iterdir()) == [p.name for p in kept], "an unfinished shot was kept"
    shots = list(csv.DictReader((out / "shots.csv").open()))
    assert sorted(Path(r["run"]).name for r in shots) == [p.name for p in kept]
    assert json.loads((out / "family.json").read_text())["complete"] is False
    stamps = {p.name: (p / "summary.json").stat().st_mtime_ns for p in kept}

    resumed = cli.run(args + ["--resume"], tmp_path)
    assert resumed.returncode == 0, resumed.stderr
    rows = list(csv.DictReader((out / "limit.csv").open()))
    assert len(rows) == 2 and all(r["status"] != "searching" for r in rows)
    assert {p.name: (p / "summary.json").stat().st_mtime_ns for p in kept} == stamps, "a kept shot was run again"
    shots = list(csv.DictReader((out / "shots.csv").open()))
    assert len(shots) == sum(int(r["n_shots"]) for r in rows) == len(cli.finished(out, "runs")) >= 4
    assert json.loads((out / "family.json").read_text())["complete"] is True
    assert (out / "limit.png").is_file() and cli.hidden(tmp_path) == []


def test_an_interrupted_run_leaves_nothing(tmp_path, make_case, cli):
    """`whipple run` stages its folder: Ctrl-C removes the staging folder and leaves no run folder."""
    out = tmp_path / "run"
    command = cli.start(["whipple", "run", str(make_case(tmp_path)), "-o", str(out)], tmp_path)
    command.wait_for(lambda: any(p.name.startswith(".run.") for p in tmp_path.iterdir()), timeout=120,
                     what="staging folder")
    time.sleep(1.0)
    took, err = command.interrupt()
    assert command.returncode == 130 and "interrupted: nothing was written" in err, err
    assert took < EXIT_WITHIN_S
    assert not out.exists() and cli.hidden(tmp_path) == []
    assert command.group_is_empty()
