"""The error contract of every command (issue 10): exit codes, one message, no traceback, nothing written.

The commands are read from the typer app itself, so a new command or subcommand is
covered at once — and fails here until it has a bad-input invocation in
:data:`BAD_INPUT` and an output path in :data:`OUTPUT` (or is listed in :data:`NO_OUTPUT`).

* bad input (a missing file, an unknown key, a bad value, a size beyond memory) →
  exit 2, one message on stderr naming the file, key or option, no traceback, nothing
  written (the ``-o`` folder does not exist afterwards and the folder holding the
  inputs is as it was);
* an output path below a regular file (permissions do not stop root) → exit 2, a
  message naming the path, no folder;
* an SPH breakdown in ``whipple run`` → exit 1, "simulation failed", no run folder;
* a beam contact the solver cannot follow (a dashpot of 99999999999 s/m in ``beam run``) → exit 1, one
  message naming the contact key, no run folder.

Every case is tiny or fails before any simulation, so the whole file runs in seconds.
"""

from __future__ import annotations

import tomllib
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
import tomli_w

from impactdyn._config import set_dotted
from impactdyn.cli import app, main

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
HUGE = 99999999999  # the dc3din grid record


def cli_commands() -> list[str]:
    """Every leaf command of the app, as "group command" (walked from typer's click tree)."""
    from typer.main import get_command

    def walk(cmd, path):
        subs = getattr(cmd, "commands", None)
        if subs:
            for name in sorted(subs):
                yield from walk(subs[name], path + (name,))
        else:
            yield " ".join(path)

    return sorted(walk(get_command(app), ()))


COMMANDS = cli_commands()


# --- inputs: the shipped examples, made small ---------------------------------------------------------------

def _toml(path: Path, data: dict) -> Path:
    path.write_text(tomli_w.dumps(data))
    return path


def beam_case(d: Path, **changes) -> Path:
    data = tomllib.loads((EXAMPLES / "beam" / "impactb_sample.toml").read_text())
    for key, value in ({"time.end_s": 0.02} | changes).items():
        data = set_dotted(data, key, value)
    return _toml(d / "beam.toml", data)


def debris_case(d: Path, **changes) -> Path:
    data = tomllib.loads((EXAMPLES / "debris" / "shell_cloud.toml").read_text())
    small = {"grid.shell.cell_size_cm": 0.4, "grid.shell.subsamples": 1, "wall.nodes": [5, 2, 9],
             "output.vtk": False, "output.plots": False}
    for key, value in (small | changes).items():
        data = set_dotted(data, key, value)
    return _toml(d / "debris.toml", data)


def whipple_case(d: Path, **changes) -> Path:
    """Table 2 shot 7a, coarsened to ~150 SPH particles (as tests/whipple/conftest.py)."""
    data = tomllib.loads((EXAMPLES / "whipple" / "table2_7a.toml").read_text())
    coarse = {"shield.spacing_cm": 0.1, "shield.handoff_us": 1.0, "binning.cell_size_cm": 0.1,
              "wall.spacing_cm": 3.0, "wall.x_cm": [0.0, 3.0], "wall.z_cm": [-2.0, 4.0], "wall.nodes": [16, 3, 31],
              "projectile.diameter_cm": 0.45}
    for key, value in (coarse | changes).items():
        data = set_dotted(data, key, value)
    return _toml(d / "whipple.toml", data)


def _rule(d: Path, extra: str) -> Path:
    """Validation set 1's rule, unfixed, with ``extra`` lines at its top."""
    from impactdyn.whipple._selection import RULES_DIR

    text = (RULES_DIR / "set-1.toml").read_text()
    p = d / "rule.toml"
    p.write_text(extra + text[:text.index("[fixed]")])
    return p


def dc3din(d: Path, run_type: str = "2 1", **lines: str) -> Path:
    """The Appendix C dc3din with its run type and whole lines replaced (``l20=...``: 1-based line 20)."""
    text = (EXAMPLES / "debris" / "legacy" / "dc3din").read_text().splitlines()
    text[3] = "".join(f"{v:>10}" for v in run_type.split())
    for key, value in lines.items():
        text[int(key[1:]) - 1] = value
    p = d / "dc3din"
    p.write_text("\n".join(text) + "\n")
    return p


JSC = ["--bumper-cm", "0.127", "--wall-cm", "0.3175", "--spacing-cm", "10.16", "--yield-ksi", "40",
       "--velocity-km-s", "7"]
SINGLE = ["--thickness-cm", "0.3", "--velocity-km-s", "7"]

# --- bad input: command -> {name: builder(dir, out) -> (argv, text the message must hold)} ------------------

Builder = Callable[[Path, Path], tuple[list[str], str]]


def _missing(*head: str, tail=()) -> Builder:
    return lambda d, out: ([*head, str(d / "nowhere.toml"), *tail, "-o", str(out)], "nowhere.toml: no such file")


BAD_INPUT: dict[str, dict[str, Builder]] = {
    "beam modes": {
        "bad value": lambda d, out: (["beam", "modes", "0"], "N = 0"),
        "bad option value": lambda d, out: (["beam", "modes", "3", "--length", "-1"], "--length"),
        "usage": lambda d, out: (["beam", "modes", "3", "--bogus"], "--bogus"),
    },
    "beam run": {
        "missing file": _missing("beam", "run"),
        "unknown key": lambda d, out: (["beam", "run", str(beam_case(d, **{"stop.z_m": 1.0})), "-o", str(out)],
                                       "stop.z_m: unknown key"),
        "end_s = 1e308": lambda d, out: (["beam", "run", str(beam_case(d, **{"time.end_s": 1e308})), "-o",
                                          str(out)], "time.end_s"),
        "output_step_s = 1e-300": lambda d, out: (["beam", "run", str(beam_case(d, **{"time.output_step_s": 1e-300})),
                                                   "-o", str(out)], "time.output_step_s = 1e-300"),
    },
    "beam sweep": {
        "missing file": _missing("beam", "sweep", tail=("--vary", "torque.amplitude_N_m=-0.3:-0.1:2")),
        "unknown key": lambda d, out: (["beam", "sweep", str(beam_case(d)), "--vary", "torque.bogus=0:1:2", "-o",
                                        str(out)], "torque.bogus: unknown key"),
        "N beyond memory": lambda d, out: (["beam", "sweep", str(beam_case(d)), "--vary",
                                            f"torque.amplitude_N_m=-0.3:-0.1:{HUGE}", "-o", str(out)],
                                           "--vary torque.amplitude_N_m="),
    },
    "debris run": {
        "missing file": _missing("debris", "run"),
        "unknown key": lambda d, out: (["debris", "run", str(debris_case(d, **{"wall.bogus": 1})), "-o", str(out)],
                                       "wall.bogus: unknown key"),
        "wall nodes beyond memory": lambda d, out: (["debris", "run", str(debris_case(d, **{"wall.nodes": [HUGE, 5, 101]})),
                                                     "-o", str(out)], f"wall.nodes = [{HUGE}, 5, 101]"),
        "shell grid beyond memory": lambda d, out: (["debris", "run",
                                                     str(debris_case(d, **{"grid.shell.cell_size_cm": 1e-6})),
                                                     "-o", str(out)], "grid.shell: cell_size_cm = 1e-06"),
    },
    "debris legacy": {
        "missing file": lambda d, out: (["debris", "legacy", str(d / "dc3din"), "-o", str(out)],
                                        "dc3din: no such file"),
        "bad record": lambda d, out: (["debris", "legacy", str(dc3din(d, "7 1")), "-o", str(out)],
                                      "dc3din:4: itype 7"),
        "wall record beyond memory": lambda d, out: (
            ["debris", "legacy", str(dc3din(d, "2 2", l20=f" {HUGE}         5       101        51         5       101")),
             "-o", str(out)], "dc3din:20: idmax jdmax kdmax"),
        "cell block beyond memory": lambda d, out: (
            ["debris", "legacy", str(dc3din(d, "2 1", l6=f"         2 {HUGE}")), str(d / "avsout"), "-o", str(out)],
            "dc3din:6-10: records i1 i2, j1 j2, k1 k2"),
    },
    "ble whipple": {
        "bad value": lambda d, out: (["ble", "whipple", *JSC[:-1], "-7"], "velocity"),
        "usage": lambda d, out: (["ble", "whipple", *JSC[2:]], "--bumper-cm"),
    },
    "ble validate": {
        "missing file": lambda d, out: (["ble", "validate", "--database", str(d / "nowhere.csv")], "nowhere.csv"),
        "bad value": lambda d, out: (["ble", "validate", "--equation", "bogus"], "bogus"),
    },
    "ble single-wall": {
        "bad value": lambda d, out: (["ble", "single-wall", "--thickness-cm", "-0.3", "--velocity-km-s", "7"],
                                     "thickness"),
        "bad mode": lambda d, out: (["ble", "single-wall", *SINGLE, "--mode", "bogus"], "bogus"),
    },
    "whipple run": {
        "missing file": _missing("whipple", "run"),
        "unknown key": lambda d, out: (["whipple", "run", str(whipple_case(d, **{"shield.bogus": 1})), "-o", str(out)],
                                       "shield.bogus: unknown key"),
        "bad momentum transfer": lambda d, out: (
            ["whipple", "run", str(whipple_case(d, **{"wall.momentum_transfer": "bounce"})), "-o", str(out)],
            "wall.momentum_transfer"),
        "SPH particles beyond memory": lambda d, out: (
            ["whipple", "run", str(whipple_case(d, **{"shield.spacing_cm": 1e-5})), "-o", str(out)],
            "shield.spacing_cm = 1e-05"),
        "wall nodes beyond memory": lambda d, out: (
            ["whipple", "run", str(whipple_case(d, **{"wall.nodes": [HUGE, 5, 101]})), "-o", str(out)],
            f"wall: nodes = [{HUGE}, 5, 101]"),
    },
    "whipple campaign": {
        "missing file": _missing("whipple", "campaign", tail=("--velocity", "6:7:2", "--diameter", "0.4:0.5:2")),
        "unknown key": lambda d, out: (["whipple", "campaign", str(whipple_case(d, **{"wall.bogus": 1})),
                                        "--velocity", "6:7:2", "--diameter", "0.4:0.5:2", "-o", str(out)],
                                       "wall.bogus: unknown key"),
        "N beyond memory": lambda d, out: (["whipple", "campaign", str(whipple_case(d)), "--velocity", f"6:7:{HUGE}",
                                            "--diameter", "0.4:0.5:2", "-o", str(out)], "--velocity '6:7:"),
    },
    "whipple shot": {
        "unknown line": lambda d, out: (["whipple", "shot", "--database", "line:99999", "-o", str(out)], "line 99999"),
        "missing base": lambda d, out: (["whipple", "shot", "--database", "B31", "--from-case", str(d / "nowhere.toml"),
                                         "-o", str(out)], "nowhere.toml: no such file"),
    },
    "whipple validate": {
        "unknown line": lambda d, out: (["whipple", "validate", "--lines", "99999", "-o", str(out)], "line 99999"),
        "unknown rule": lambda d, out: (["whipple", "validate", "--select", "set-9", "-o", str(out)], "set-9"),
        "missing base": lambda d, out: (["whipple", "validate", "--lines", "375", "--from-case",
                                         str(d / "nowhere.toml"), "-o", str(out)], "nowhere.toml: no such file"),
    },
    "whipple fix-rule": {
        "missing file": lambda d, out: (["whipple", "fix-rule", str(d / "nowhere.toml")], "nowhere.toml"),
        "unknown key": lambda d, out: (["whipple", "fix-rule", str(_rule(d, "bogus = 1\n"))], "bogus"),
    },
    "whipple limit": {
        "missing file": _missing("whipple", "limit", tail=("--velocity", "6:7:2")),
        "unknown key": lambda d, out: (["whipple", "limit", str(whipple_case(d, **{"wall.bogus": 1})),
                                        "--velocity", "6:7:2", "-o", str(out)], "wall.bogus: unknown key"),
        "bad value": lambda d, out: (["whipple", "limit", str(whipple_case(d)), "--velocity", "6:7:2",
                                      "--tolerance", "-1", "-o", str(out)], "--tolerance"),
        "bad bracket": lambda d, out: (["whipple", "limit", str(whipple_case(d)), "--velocity", "6:7:2",
                                        "--bracket", "7:0.9", "-o", str(out)], "--bracket '7:0.9'"),
    },
    "materials list": {
        "missing case": lambda d, out: (["materials", "list", "--case", str(d / "nowhere.toml")],
                                        "nowhere.toml: no such file"),
        "material used but not defined": lambda d, out: (
            ["materials", "list", "--case", str(whipple_case(d, **{"projectile.material": "ti64"}))],
            "projectile.material: unknown material 'ti64'"),
    },
    "materials show": {
        "unknown name": lambda d, out: (["materials", "show", "unobtainium"], "unknown material 'unobtainium'"),
        "bad material table": lambda d, out: (
            ["materials", "show", "x", "--case", str(whipple_case(d, **{"materials.x.eos.c0_km_s": -1.0}))],
            "materials.x.eos"),
    },
}

#: Commands that write no file (fix-rule writes into the rule file it is given, which must exist).
NO_OUTPUT = {"beam modes", "ble single-wall", "whipple fix-rule", "materials list", "materials show"}

#: command -> builder(dir, output path) of an invocation that writes to that path.
OUTPUT: dict[str, Callable[[Path, Path], list[str]]] = {
    "beam run": lambda d, out: ["beam", "run", str(beam_case(d)), "-o", str(out)],
    "beam sweep": lambda d, out: ["beam", "sweep", str(beam_case(d)), "--vary", "torque.amplitude_N_m=-0.3:-0.1:2",
                                  "--workers", "1", "-o", str(out)],
    "debris run": lambda d, out: ["debris", "run", str(debris_case(d)), "-o", str(out)],
    "debris legacy": lambda d, out: ["debris", "legacy", str(dc3din(d, "2 2")), "-o", str(out)],
    "ble whipple": lambda d, out: ["ble", "whipple", *JSC, "--plot", str(out.with_suffix(".png"))],
    "ble validate": lambda d, out: ["ble", "validate", "--plot", str(out.with_suffix(".png"))],
    "whipple run": lambda d, out: ["whipple", "run", str(whipple_case(d)), "-o", str(out)],
    "whipple campaign": lambda d, out: ["whipple", "campaign", str(whipple_case(d)), "--velocity", "6:7:2",
                                        "--diameter", "0.4:0.5:2", "-o", str(out)],
    "whipple limit": lambda d, out: ["whipple", "limit", str(whipple_case(d)), "--velocity", "6:7:2", "-o", str(out)],
    "whipple shot": lambda d, out: ["whipple", "shot", "--database", "B31", "--write-case", str(out)],
    "whipple validate": lambda d, out: ["whipple", "validate", "--lines", "375", "--from-case", str(whipple_case(d)),
                                        "-o", str(out)],
}


def _tree(root: Path) -> set[str]:
    return {str(p.relative_to(root)) for p in root.rglob("*")}


def _run(capsys, argv: list[str]) -> tuple[int, str, str]:
    code = main(argv)
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def _one_message(err: str) -> bool:
    """One error report: an ``error: …`` line, or the usage panel of a command-line mistake."""
    return (err.count("error: ") == 1 and err.lstrip().startswith("error: ")) or (
        "error:" not in err and err.count("Error") == 1)


# --- the tables cover the app ------------------------------------------------------------------------------

def test_the_command_list_is_walked_from_the_app():
    assert {"beam modes", "beam run", "debris legacy", "ble whipple", "whipple run"} <= set(COMMANDS)
    assert all(len(c.split()) == 2 for c in COMMANDS)


@pytest.mark.parametrize("command", COMMANDS)
def test_every_command_is_in_the_tables(command):
    assert BAD_INPUT.get(command), f"'{command}' has no bad-input invocation: add one to BAD_INPUT"
    assert (command in OUTPUT) != (command in NO_OUTPUT), \
        f"'{command}': give an invocation writing to an output path in OUTPUT, or list it in NO_OUTPUT"


def test_the_tables_name_no_command_the_app_lacks():
    assert set(BAD_INPUT) | set(OUTPUT) | NO_OUTPUT <= set(COMMANDS)


# --- bad input ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("command, kind", [(c, k) for c in COMMANDS for k in sorted(BAD_INPUT.get(c, {}))])
def test_bad_input_exits_2_with_one_message_and_writes_nothing(tmp_path, capsys, command, kind):
    inputs, out = tmp_path / "in", tmp_path / "out" / "run"
    inputs.mkdir()
    (tmp_path / "out").mkdir()
    argv, expected = BAD_INPUT[command][kind](inputs, out)
    before = _tree(tmp_path)
    code, stdout, err = _run(capsys, argv)
    assert code == 2, err
    assert expected in err, err
    assert _one_message(err), err
    assert "Traceback" not in stdout + err
    assert not out.exists()
    assert _tree(tmp_path) == before  # no staging folder, plot or stray file either


@pytest.mark.parametrize("command", COMMANDS)
def test_unknown_option_is_a_usage_error(capsys, command):
    code, stdout, err = _run(capsys, [*command.split(), "--bogus"])
    assert code == 2
    assert "--bogus" in err and "Traceback" not in stdout + err


# --- an output path that cannot be written -----------------------------------------------------------------

@pytest.mark.parametrize("command", sorted(OUTPUT))
def test_output_below_a_file_exits_2_naming_the_path(tmp_path, capsys, command):
    inputs = tmp_path / "in"
    inputs.mkdir()
    afile = tmp_path / "afile"
    afile.write_text("a regular file, not a folder\n")
    argv = OUTPUT[command](inputs, afile / "run")
    before = _tree(tmp_path)
    code, stdout, err = _run(capsys, argv)
    assert code == 2, err
    assert "afile" in err and _one_message(err), err
    assert "Traceback" not in stdout + err
    assert afile.is_file() and _tree(tmp_path) == before


# --- a solver failure --------------------------------------------------------------------------------------

def test_sph_breakdown_exits_1_and_leaves_no_run_folder(tmp_path, capsys, monkeypatch):
    """The SPH step is made to produce NaN (no shot is run): the solver's own check stops the run."""
    from impactdyn.shield import _integrate

    def broken_step(self, dt):
        self.state.v[0] = np.nan  # one particle's velocity goes non-finite, and with it the next time step
        self.dt = float("nan")
        self.steps += 1
        return self.totals()

    monkeypatch.setattr(_integrate._Solver, "step", broken_step)
    inputs, out = tmp_path / "in", tmp_path / "run"
    inputs.mkdir()
    case = whipple_case(inputs)
    code, stdout, err = _run(capsys, ["whipple", "run", str(case), "-o", str(out)])
    assert code == 1, err
    assert err.startswith("simulation failed: ") and "time step nan" in err, err
    assert "Traceback" not in stdout + err
    assert not out.exists()
    assert _tree(tmp_path) == {"in", "in/whipple.toml"}


def test_a_contact_the_beam_solver_cannot_follow_exits_1_naming_its_key(tmp_path, capsys):
    """The IMPACTB sample with its dashpot at 99999999999 s/m: at the first contact the dashpot holds the stop
    point and would let it go only below the round-off of the gap rate, and the steps fall below what the
    time resolves (it ended in a ZeroDivisionError and a traceback)."""
    inputs, out = tmp_path / "in", tmp_path / "run"
    inputs.mkdir()
    case = beam_case(inputs, **{"time.end_s": 1.0, "contact.damping_s_m": 99999999999})
    code, stdout, err = _run(capsys, ["beam", "run", str(case), "-o", str(out)])
    assert code == 1, err
    assert err.startswith("simulation failed: contact.damping_s_m = 1e+11: ") and err.count("\n") == 1, err
    assert "Traceback" not in stdout + err
    assert not out.exists()
    assert _tree(tmp_path) == {"in", "in/beam.toml"}
