"""``impactdyn ble``: critical diameter, regime, verdict, plot; bad input is exit 2."""

import json

import pytest

from impactdyn.ble import WhippleShield, critical_diameter
from impactdyn.cli import main

TABLE2 = ["--bumper-cm", "0.127", "--wall-cm", "0.3175", "--spacing-cm", "10.16", "--yield-ksi", "40",
          "--obliquity-deg", "25"]


def run_json(capsys, *args):
    assert main(["ble", "whipple", *TABLE2, "--json", *args]) == 0
    return json.loads(capsys.readouterr().out)


def test_table_output(capsys):
    assert main(["ble", "whipple", *TABLE2, "--velocity-km-s", "7", "--diameter-cm", "0.575"]) == 0
    out = capsys.readouterr().out
    assert "0.5238 cm" in out and "shatter" in out and "perforation" in out


@pytest.mark.parametrize("velocity, diameter, verdict", [
    ("7", "0.575", "perforation"), ("7", "0.475", "no perforation"),
    ("10", "0.530", "perforation"), ("10", "0.430", "no perforation")])
def test_table2_shots_json(capsys, velocity, diameter, verdict):
    out = run_json(capsys, "--velocity-km-s", velocity, "--diameter-cm", diameter)
    shield = WhippleShield(0.127, 0.3175, 10.16, 40.0)
    assert out["critical_diameter_cm"] == critical_diameter(shield, float(velocity), 25.0, 2.7)
    assert out["verdict"] == verdict
    assert out["regime"] == ("shatter" if velocity == "7" else "hypervelocity")
    assert out["shield"]["spacing_cm"] == 10.16
    assert out["rear_wall_only_critical_diameter_cm"] < out["critical_diameter_cm"] / 4


def test_issue_numbers_on_the_command_line(capsys):
    args = [a if a != "10.16" else "10" for a in TABLE2]
    for v, expected in (("7", 0.521), ("10", 0.482)):
        assert main(["ble", "whipple", *args, "--velocity-km-s", v, "--json"]) == 0
        assert abs(json.loads(capsys.readouterr().out)["critical_diameter_cm"] - expected) <= 1e-3


def test_plot_written_atomically_and_not_overwritten(tmp_path, capsys):
    png = tmp_path / "curve.png"
    out = run_json(capsys, "--velocity-km-s", "7", "--diameter-cm", "0.575", "--plot", str(png))
    assert out["plot"] == str(png)
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["curve.png"]  # no temporary left behind
    # an existing file is kept without --force
    assert main(["ble", "whipple", *TABLE2, "--velocity-km-s", "10", "--plot", str(png)]) == 2
    assert "--force" in capsys.readouterr().err
    assert png.read_bytes() == data
    assert main(["ble", "whipple", *TABLE2, "--velocity-km-s", "10", "--plot", str(png), "--force"]) == 0
    assert png.read_bytes() != data


@pytest.mark.parametrize("args, message", [
    (["--obliquity-deg", "95"], "obliquity_deg = 95.0"),
    (["--obliquity-deg", "90"], "obliquity_deg = 90.0"),
    (["--obliquity-deg", "nan"], "obliquity_deg"),
    (["--velocity-km-s", "0"], "velocity_km_s = 0.0"),
    (["--bumper-cm", "-0.1"], "bumper_thickness_cm = -0.1"),
    (["--spacing-cm", "0"], "spacing_cm = 0.0"),
    (["--projectile-density", "0"], "projectile_density = 0.0"),
    (["--diameter-cm", "0"], "diameter_cm = 0.0"),
    (["--plot", "curve.xyz"], "unknown plot format"),
    (["--plot", "no/such/folder/curve.png"], "does not exist"),
])
def test_bad_input_exit_2_nothing_written(tmp_path, monkeypatch, capsys, args, message):
    monkeypatch.chdir(tmp_path)
    base = dict(zip(TABLE2[::2], TABLE2[1::2])) | {"--velocity-km-s": "7"}
    base |= dict(zip(args[::2], args[1::2]))
    argv = [x for kv in base.items() for x in kv]
    assert main(["ble", "whipple", *argv]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


def test_single_wall(capsys):
    argv = ["ble", "single-wall", "--thickness-cm", "0.3175", "--velocity-km-s", "7", "--json"]
    assert main([*argv, "--diameter-cm", "0.1"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["critical_diameter_cm"] == pytest.approx(0.0968740, abs=1e-7)
    assert out["verdict"] == "perforation"
    assert main([*argv, "--mode", "incipient_spall", "--diameter-cm", "0.05"]) == 0
    assert json.loads(capsys.readouterr().out)["verdict"] == "no incipient spall"
    assert main(["ble", "single-wall", "--thickness-cm", "0.3175", "--velocity-km-s", "7"]) == 0
    assert "0.0969 cm" in capsys.readouterr().out
    assert main([*argv, "--mode", "melted"]) == 2
    assert "mode = 'melted'" in capsys.readouterr().err
    assert main([*argv, "--obliquity-deg", "95"]) == 2
