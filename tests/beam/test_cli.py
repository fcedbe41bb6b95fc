"""Command line: runs, run folders, and clear errors on bad input."""

import json
import shutil

import pytest

from impactdyn.cli import main

from pathlib import Path

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "beam"


def _case(tmp_path, text_edit=None, name="case.toml"):
    src = (EXAMPLES / "impactb_sample.toml").read_text()
    src = src.replace("end_s = 1.0", "end_s = 0.05")
    if text_edit:
        src = text_edit(src)
    p = tmp_path / name
    p.write_text(src)
    return p


def test_run_writes_folder(tmp_path, capsys):
    out = tmp_path / "run"
    assert main(["beam", "run", str(_case(tmp_path)), "-o", str(out)]) == 0
    for f in ("summary.json", "timeseries.csv", "impacts.csv", "config.resolved.toml", "plots/energy.png"):
        assert (out / f).is_file(), f
    s = json.loads((out / "summary.json").read_text())
    assert {"impacts", "n_impacts", "final_state", "energy", "wall_time_s"} <= s.keys()
    header = (out / "timeseries.csv").read_text().splitlines()[0].split(",")
    assert header[:7] == ["time_s", "deflection_m", "theta_dot_rad_s", "theta_rad", "stop_displacement_m",
                          "strain", "energy_J"]
    # the resolved config is itself a valid case that reproduces the run
    out2 = tmp_path / "again"
    assert main(["beam", "run", str(out / "config.resolved.toml"), "-o", str(out2)]) == 0
    assert (out2 / "timeseries.csv").read_text() == (out / "timeseries.csv").read_text()
    # an existing folder is not overwritten without --force
    assert main(["beam", "run", str(_case(tmp_path)), "-o", str(out)]) == 2
    assert "--force" in capsys.readouterr().err
    assert main(["beam", "run", str(_case(tmp_path)), "-o", str(out), "--force"]) == 0


BAD = {
    "missing key": (lambda s: s.replace("EI_N_m2 = 5.50\n", ""), "beam.EI_N_m2: missing key"),
    "negative EI": (lambda s: s.replace("EI_N_m2 = 5.50", "EI_N_m2 = -5.50"), "beam.EI_N_m2"),
    "stop beyond tip": (lambda s: s.replace("x_m = 0.515", "x_m = 0.6"), "stop.x_m"),
    "unknown key": (lambda s: s.replace("[stop]", "[stop]\nz_m = 1.0"), "stop.z_m: unknown key"),
    "nan": (lambda s: s.replace("EI_N_m2 = 5.50", "EI_N_m2 = nan"), "beam.EI_N_m2"),
    "wrong type": (lambda s: s.replace("n_modes = 3", 'n_modes = "three"'), "model.n_modes"),
    "bad toml": (lambda s: s + "\n[[[", "invalid TOML"),
}


@pytest.mark.parametrize("kind", sorted(BAD))
def test_bad_input_is_a_clear_error(tmp_path, capsys, kind):
    edit, expected = BAD[kind]
    out = tmp_path / "run"
    assert main(["beam", "run", str(_case(tmp_path, edit)), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert expected in err and "case.toml" in err and "Traceback" not in err
    assert not out.exists()
    assert not any(p.name.startswith(".run") for p in tmp_path.iterdir())


def test_unreadable_file(tmp_path, capsys):
    assert main(["beam", "run", str(tmp_path / "nope.toml"), "-o", str(tmp_path / "run")]) == 2
    assert "no such file" in capsys.readouterr().err
    assert not (tmp_path / "run").exists()


def test_modes_json(capsys):
    assert main(["beam", "modes", "4", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert len(data["beta"]) == 4 and abs(data["beta"][0] - 1.875104068712) < 1e-10
    assert main(["beam", "modes", "51"]) == 2


def test_sweep(tmp_path):
    out = tmp_path / "sweep"
    case = _case(tmp_path, lambda s: s.replace("end_s = 0.05", "end_s = 0.02"))
    assert main(["beam", "sweep", str(case), "--vary", "initial.theta_dot_rad_s=-8:-4:3",
                 "-o", str(out), "--workers", "2"]) == 0
    rows = (out / "sweep.csv").read_text().splitlines()
    assert len(rows) == 4 and (out / "sweep.png").is_file()
    assert main(["beam", "sweep", str(case), "--vary", "beam.nope=1:2:2", "-o", str(tmp_path / "s2")]) == 2
    assert not (tmp_path / "s2").exists()
