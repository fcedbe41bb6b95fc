"""Ctrl-C and SIGTERM stop the commands that run work in a pool (the Whipple ones: tests/whipple):
exit 130 within seconds, no process of ours left, no staging folder, a family's finished runs and
table kept, and ``--resume`` runs only what is missing."""

import csv
import multiprocessing
import os
import signal
import time
from pathlib import Path

import pytest

from impactdyn._errors import InputError, Interrupted
from impactdyn._family import FamilyFolder
from impactdyn._parallel import run_tasks, tasks_started

EXAMPLES = Path(__file__).parents[1] / "examples"
#: Seconds the contract allows from the interrupt to the exit.
EXIT_WITHIN_S = 10.0


def _sweep_args(out: Path, pool: list[str]) -> list[str]:
    # each case simulates 12-14 s of the IMPACTB sample (a few seconds of work): 8 cases on two workers
    return ["beam", "sweep", str(EXAMPLES / "beam" / "impactb_sample.toml"), "--vary", "time.end_s=12:14:8",
            "--workers", "2", "-o", str(out), *pool]


@pytest.mark.parametrize("sig, pool", [(signal.SIGINT, []), (signal.SIGTERM, []), (signal.SIGINT, ["--dask", "local"])],
                         ids=["ctrl-c", "sigterm", "ctrl-c-dask"])
def test_beam_sweep_stops_keeps_its_finished_cases_and_resumes(tmp_path, sig, pool, cli):
    out = tmp_path / "sweep"
    command = cli.start(_sweep_args(out, pool), tmp_path)
    finished = lambda: [p / "summary.json" for p in cli.finished(out, "cases")]  # noqa: E731
    command.wait_for(lambda: len(finished()) >= 2, timeout=300, what="two finished cases")
    took, err = command.interrupt(sig)

    assert command.returncode == 130, err
    assert took < EXIT_WITHIN_S, f"exit {took:.1f} s after {signal.Signals(sig).name}"
    assert "Traceback" not in err and "interrupted:" in err and "--resume" in err, err
    assert command.group_is_empty(), "a process of the command outlived it"
    assert cli.hidden(tmp_path) == []
    kept = finished()
    assert 2 <= len(kept) < 8, "the interrupt came after the sweep had finished: make its cases longer"
    rows = list(csv.DictReader((out / "sweep.csv").open()))
    assert sorted(int(r["index"]) for r in rows) == sorted(int(p.parent.name) for p in kept)
    stamps = [p.stat().st_mtime_ns for p in kept]

    resumed = cli.run(_sweep_args(out, pool) + ["--resume"], tmp_path)
    assert resumed.returncode == 0, resumed.stderr
    assert [p.stat().st_mtime_ns for p in kept] == stamps, "a kept case was run again"
    assert [int(r["index"]) for r in csv.DictReader((out / "sweep.csv").open())] == list(range(8))
    assert (out / "sweep.png").is_file()


def test_leaving_the_loop_ends_the_pool_workers_at_once():
    """Leaving the loop early (as an interrupt or a failed task does) cancels the queue and ends the
    running tasks: three 60-s tasks do not hold the caller."""
    start = time.monotonic()
    finished = run_tasks(time.sleep, [0.0, 60.0, 60.0, 60.0], scheduler="processes", workers=2)
    assert next(finished) == (0, None)
    finished.close()
    assert time.monotonic() - start < 30.0
    assert multiprocessing.active_children() == []


def test_started_tasks_run_while_the_caller_works_and_stop_when_it_fails():
    """``tasks_started`` hands the tasks to the pool as the block opens: they run while the caller does its
    own work (two 2-s sleeps end 2 s after the caller's own 2 s, not 4 s), and an exception in the block
    ends the running ones at once and leaves no worker behind."""
    start = time.monotonic()
    with tasks_started(time.sleep, [2.0, 2.0], scheduler="processes", workers=2) as finished:
        time.sleep(2.0)
        assert sorted(i for i, _ in finished) == [0, 1]
    assert time.monotonic() - start < 3.9
    start = time.monotonic()
    with pytest.raises(RuntimeError, match="the caller's own work failed"):
        with tasks_started(time.sleep, [60.0, 60.0], scheduler="processes", workers=2):
            raise RuntimeError("the caller's own work failed")
    assert time.monotonic() - start < 30.0
    assert multiprocessing.active_children() == []


def _pid_after(seconds: float) -> int:
    time.sleep(seconds)
    return os.getpid()


def test_a_caller_that_helps_runs_the_tasks_no_worker_has_taken_last_first():
    """With ``caller_helps`` the caller, reading the results, runs the tasks still queued itself: of five
    1-s tasks on two workers (which hold at most three), the last runs in the caller, and every task's result
    comes once."""
    with tasks_started(_pid_after, [1.0] * 5, scheduler="processes", workers=2, caller_helps=True) as finished:
        pids = dict(finished)
    assert sorted(pids) == [0, 1, 2, 3, 4]
    assert pids[4] == os.getpid() and pids[0] != os.getpid()
    assert multiprocessing.active_children() == []


def test_resume_refuses_other_settings_and_names_them(tmp_path):
    settings = {"case": {"projectile": {"diameter_cm": 0.5}}, "velocities_km_s": [7.0]}
    with FamilyFolder(tmp_path / "f", "whipple limit", settings, table="limit.csv"):
        pass
    other = {"case": {"projectile": {"diameter_cm": 0.6}}, "velocities_km_s": [7.0]}
    with pytest.raises(InputError, match=r"other settings \(case\.projectile\.diameter_cm\)"):
        FamilyFolder(tmp_path / "f", "whipple limit", other, table="limit.csv", resume=True)
    with pytest.raises(InputError, match="a folder of `whipple limit`, not of `beam sweep`"):
        FamilyFolder(tmp_path / "f", "beam sweep", settings, table="sweep.csv", resume=True)
    with pytest.raises(InputError, match="--force and --resume"):
        FamilyFolder(tmp_path / "f", "whipple limit", settings, table="limit.csv", resume=True, force=True)
    with pytest.raises(InputError, match="run folder exists; pass --force"):
        FamilyFolder(tmp_path / "f", "whipple limit", settings, table="limit.csv")


def test_an_interrupt_in_a_family_removes_staging_and_says_what_was_kept(tmp_path, cli):
    with pytest.raises(Interrupted, match=r"2 finished shots and limit\.csv kept in .*--resume"):
        with FamilyFolder(tmp_path / "f", "whipple limit", {}, table="limit.csv", member="shot") as family:
            (family.path / "runs" / ".V7_d0.5.abc123").mkdir(parents=True)
            (family.path / "runs" / "V7_d0.4").mkdir()
            (family.path / ".limit.1234.tmp.csv").write_text("half")
            family.finished = 2
            raise KeyboardInterrupt
    assert cli.hidden(tmp_path) == []
    with FamilyFolder(tmp_path / "f", "whipple limit", {}, table="limit.csv", resume=True) as family:
        assert (family.path / "runs" / "V7_d0.4").is_dir()


def test_a_member_that_finished_during_the_stop_is_recorded(tmp_path):
    """A worker renames its finished run into place, then the stop comes before its result reaches the
    main process: the member is read back from its folder, so the table holds every finished member."""
    import json

    from impactdyn._family import run_members

    summaries = [tmp_path / f"m{k}" / "summary.json" for k in range(3)]

    def run(k: int) -> dict:
        summaries[k].parent.mkdir()
        summaries[k].write_text(json.dumps({"member": k}))
        if k == 1:  # finished on disk, result never delivered
            raise KeyboardInterrupt
        return {"member": k}

    recorded = {}
    with pytest.raises(KeyboardInterrupt):
        run_members(run, summaries, lambda pending: pending, recorded.__setitem__, scheduler="serial")
    assert recorded == {0: {"member": 0}, 1: {"member": 1}}
    # resumed: both are read back, only the third runs
    ran = []
    run_members(lambda k: ran.append(k) or run(k), summaries, lambda pending: pending, recorded.__setitem__,
                scheduler="serial")
    assert ran == [2] and recorded == {k: {"member": k} for k in range(3)}


def test_an_interrupt_while_a_member_is_recorded_waits_for_the_whole_record(tmp_path):
    """Ctrl-C lands between a finished member's row and its count (the table being rewritten):
    the record completes, the interrupt is raised after it, and the member is recorded once."""
    import json
    import os

    from impactdyn._family import run_members

    summaries = [tmp_path / f"m{k}" / "summary.json" for k in range(3)]
    rows, counted = [], []

    def run(k: int) -> dict:
        summaries[k].parent.mkdir()
        summaries[k].write_text(json.dumps({"member": k}))
        return {"member": k}

    def record(k: int, summary: dict) -> None:
        rows.append(k)
        if k == 0:
            os.kill(os.getpid(), signal.SIGINT)  # the user's Ctrl-C, mid-record
            time.sleep(0.05)
        counted.append(k)

    with pytest.raises(KeyboardInterrupt):
        run_members(run, summaries, lambda pending: pending, record, scheduler="serial")
    assert rows == counted == [0], "the record was cut, or the member recorded twice, or the stop lost"


def _kernel_returning_with_the_interrupt_set(*args, **kwargs):
    """What a compiled numba kernel raises when Ctrl-C's handler runs as it returns: Python finds a result
    and the interrupt both, and reports a SystemError caused by the KeyboardInterrupt."""
    try:
        raise KeyboardInterrupt
    except KeyboardInterrupt as interrupt:
        raise SystemError("CPUDispatcher(<function _permute_rows at 0x7f0000000000>) returned a result with an "
                          "exception set") from interrupt


def test_an_interrupt_surfacing_as_a_kernels_system_error_exits_130_in_one_line(tmp_path, capsys, monkeypatch):
    import impactdyn.whipple
    from impactdyn.cli import main

    monkeypatch.setattr(impactdyn.whipple, "run_whipple", _kernel_returning_with_the_interrupt_set)
    case = EXAMPLES / "whipple" / "table2_7a.toml"
    assert main(["whipple", "run", str(case), "-o", str(tmp_path / "run")]) == 130
    assert capsys.readouterr().err.strip().splitlines() == ["interrupted: nothing was written"]
    assert list(tmp_path.iterdir()) == []


def test_a_system_error_of_another_cause_is_not_taken_for_an_interrupt(tmp_path, monkeypatch):
    import impactdyn.whipple
    from impactdyn.cli import main

    def broken(*args, **kwargs):
        raise SystemError("a defect")

    monkeypatch.setattr(impactdyn.whipple, "run_whipple", broken)
    with pytest.raises(SystemError, match="a defect"):
        main(["whipple", "run", str(EXAMPLES / "whipple" / "table2_7a.toml"), "-o", str(tmp_path / "run")])


def _sigint_ignored(pid: int) -> bool:
    """Whether the process ``pid`` ignores SIGINT (its ``SigIgn`` mask in /proc)."""
    mask = next(line.split()[1] for line in Path(f"/proc/{pid}/status").read_text().splitlines()
                if line.startswith("SigIgn:"))
    return bool(int(mask, 16) & (1 << (signal.SIGINT - 1)))


def test_a_command_takes_ctrl_c_even_where_the_suite_runs_as_a_background_job(tmp_path, cli):
    """A suite started as a background job (``nohup pytest &``) has SIGINT ignored, and a child inherits that
    through exec: the commands it starts are started as a terminal starts them, with SIGINT at its default."""
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        command = cli.start(_sweep_args(tmp_path / "sweep", []), tmp_path)
    finally:
        signal.signal(signal.SIGINT, previous)
    assert not _sigint_ignored(command.proc.pid), "the command inherited SIGINT ignored: Ctrl-C would not stop it"
