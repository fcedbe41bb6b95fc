"""``impactdyn ble``: critical diameter, regime, verdict, plot, validate; bad input is exit 2 naming the option."""

import json

import numpy as np
import pytest

from impactdyn.ble import (
    DATABASE_PATH,
    DEFAULT_EQUATION,
    EQUATIONS,
    WhippleShield,
    critical_diameter,
    get_equation,
    nearby_shots,
    validate,
)
from impactdyn.cli import main

TABLE2 = ["--bumper-cm", "0.127", "--wall-cm", "0.3175", "--spacing-cm", "10.16", "--yield-ksi", "40",
          "--obliquity-deg", "25"]


def run_json(capsys, *args):
    assert main(["ble", "whipple", *TABLE2, "--json", *args]) == 0
    return json.loads(capsys.readouterr().out)


def test_table_output(capsys):
    assert main(["ble", "whipple", *TABLE2, "--velocity-km-s", "7", "--diameter-cm", "0.575", "--equation",
                 "jsc1993"]) == 0
    out = capsys.readouterr().out
    assert "0.5238 cm" in out and "shatter" in out and "perforation" in out and "jsc1993" in out
    assert main(["ble", "whipple", *TABLE2, "--velocity-km-s", "7", "--diameter-cm", "0.575"]) == 0
    out = capsys.readouterr().out
    default = critical_diameter(WhippleShield(0.127, 0.3175, 10.16, 40.0), 7.0, 25.0)
    assert f"{default:.4f} cm" in out and DEFAULT_EQUATION in out and f"{0.5238:.4f} cm" not in out


@pytest.mark.parametrize("velocity, diameter, verdict", [
    ("7", "0.575", "perforation"), ("7", "0.475", "no perforation"),
    ("10", "0.530", "perforation"), ("10", "0.430", "no perforation")])
def test_table2_shots_json(capsys, velocity, diameter, verdict):
    for eq in EQUATIONS:
        out = run_json(capsys, "--velocity-km-s", velocity, "--diameter-cm", diameter, "--equation", eq)
        shield = WhippleShield(0.127, 0.3175, 10.16, 40.0)
        assert out["critical_diameter_cm"] == critical_diameter(shield, float(velocity), 25.0, 2.7, eq)
        assert out["threshold_cm"] == out["critical_diameter_cm"] and out["note"] is None
        assert out["verdict"] == verdict and out["equation"] == eq
    assert run_json(capsys, "--velocity-km-s", velocity, "--diameter-cm", diameter)["equation"] == DEFAULT_EQUATION
    assert out["regime"] == ("shatter" if velocity == "7" else "hypervelocity")
    assert out["shield"]["spacing_cm"] == 10.16
    assert out["rear_wall_only_critical_diameter_cm"] < out["critical_diameter_cm"] / 4


def test_issue_numbers_on_the_command_line(capsys):
    args = [a if a != "10.16" else "10" for a in TABLE2]
    for v, expected in (("7", 0.521), ("10", 0.482)):
        assert main(["ble", "whipple", *args, "--velocity-km-s", v, "--json", "--equation", "jsc1993"]) == 0
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
    (["--obliquity-deg", "95"], "--obliquity-deg: obliquity_deg = 95.0"),
    (["--obliquity-deg", "90"], "--obliquity-deg: obliquity_deg = 90.0"),
    (["--obliquity-deg", "nan"], "--obliquity-deg: obliquity_deg"),
    (["--velocity-km-s", "0"], "--velocity-km-s: velocity_km_s = 0.0"),
    (["--bumper-cm", "-0.1"], "--bumper-cm: bumper_thickness_cm = -0.1"),
    (["--wall-cm", "0"], "--wall-cm: wall_thickness_cm = 0.0"),
    (["--spacing-cm", "0"], "--spacing-cm: spacing_cm = 0.0"),
    (["--yield-ksi", "-40"], "--yield-ksi: wall_yield_ksi = -40.0"),
    (["--projectile-density", "0"], "--projectile-density: projectile_density = 0.0"),
    (["--bumper-density", "0"], "--bumper-density: bumper_density_g_cm3 = 0.0"),
    (["--diameter-cm", "0"], "--diameter-cm: diameter_cm = 0.0"),
    (["--equation", "jsc1994"], "--equation: equation: unknown Whipple equation 'jsc1994'; choose one of jsc1993, jsc2011"),
    (["--plot", "curve.xyz"], "--plot: curve.xyz: unknown plot format"),
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


def test_no_fixed_point_is_said(capsys, tmp_path):
    r = validate("jsc2011")
    db = r.database
    i = int(np.flatnonzero(np.isnan(r.limit.critical_diameter_cm) & (r.limit.regime == "hypervelocity"))[0])
    options = {"--bumper-cm": db.bumper_thickness_cm, "--wall-cm": db.wall_thickness_cm, "--spacing-cm": db.spacing_cm,
               "--yield-ksi": db.wall_yield_ksi, "--bumper-density": db.bumper_density_g_cm3,
               "--velocity-km-s": db.velocity_km_s, "--obliquity-deg": db.obliquity_deg,
               "--projectile-density": db.projectile_density_g_cm3, "--diameter-cm": db.diameter_cm}
    args = [x for option, values in options.items() for x in (option, repr(float(values[i])))]
    assert main(["ble", "whipple", *args, "--json", "--equation", "jsc2011"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["critical_diameter_cm"] is None and out["regime"] == "hypervelocity"
    assert out["note"].startswith("hypervelocity regime: no fixed point")
    assert out["threshold_cm"] == pytest.approx(db.spacing_cm[i] / 30, rel=1e-14)
    assert out["verdict"] == ("perforation" if r.called[i] else "no perforation")
    png = tmp_path / "c.png"
    assert main(["ble", "whipple", *args, "--plot", str(png), "--test-shots"]) == 0
    text = capsys.readouterr().out
    assert "none (no fixed point)" in text and "perforation threshold" in text and png.read_bytes()[:4] == b"\x89PNG"


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
    for args, message in ((["--mode", "melted"], "--mode: mode = 'melted'"),
                          (["--obliquity-deg", "95"], "--obliquity-deg: obliquity_deg = 95.0"),
                          (["--thickness-cm", "0"], "--thickness-cm: thickness_cm = 0.0"),
                          (["--brinell", "-1"], "--brinell: brinell_hardness = -1.0"),
                          (["--diameter-cm", "0"], "--diameter-cm: diameter_cm = 0.0")):
        assert main([*argv, *args]) == 2
        err = capsys.readouterr().err
        assert message in err and "Traceback" not in err


# ------------------------------------------------------------------ ble validate


def test_validate_json_every_equation(capsys):
    assert main(["ble", "validate", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["shots"] == 1135 == len(validate(DEFAULT_EQUATION).database) and out["database"] == str(DATABASE_PATH)
    assert [e["equation"] for e in out["equations"]] == list(EQUATIONS)
    for e in out["equations"]:
        assert e == json.loads(json.dumps(validate(e["equation"]).as_dict()))
    assert main(["ble", "validate", "--json", "--equation", "jsc1993"]) == 0
    assert [e["equation"] for e in json.loads(capsys.readouterr().out)["equations"]] == ["jsc1993"]


def test_validate_tables(capsys):
    assert main(["ble", "validate"]) == 0
    out = capsys.readouterr().out
    for name in EQUATIONS:
        s = validate(name).overall
        assert f"{name}: {get_equation(name).title}" in out
        assert f"{100 * s.accuracy:.1f} %" in out and f"{100 * s.false_safe_rate:.1f} %" in out
    for group in ("regime: hypervelocity", "obliquity 45–65°", "with a fixed point"):
        assert group in out


def test_validate_configuration_and_plot(capsys, tmp_path):
    png = tmp_path / "v.png"
    config = ["--bumper-cm", "0.16", "--wall-cm", "0.318", "--spacing-cm", "10.16", "--obliquity-deg", "0"]
    assert main(["ble", "validate", *config, "--plot", str(png), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    near = nearby_shots(WhippleShield(0.16, 0.318, 10.16, 40.0), 0.0)
    c = out["configuration"]
    assert c["nearby_shots"] == len(near) > 0 and c["nearby_lines"] == near.line.tolist()
    for name in EQUATIONS:
        assert c["scores"][name] == json.loads(json.dumps(validate(name, near).overall.as_dict()))
    assert out["plot"] == str(png) and png.read_bytes()[:4] == b"\x89PNG"
    assert main(["ble", "validate", *config, "--plot", str(png)]) == 2  # exists, no --force
    assert "--force" in capsys.readouterr().err
    assert main(["ble", "validate", *config, "--band", "0.05"]) == 0
    assert f"{len(nearby_shots(WhippleShield(0.16, 0.318, 10.16, 40.0), 0.0, band=0.05))} shots near" in \
        capsys.readouterr().out


@pytest.mark.parametrize("args, message", [
    (["--equation", "nasa"], "--equation: equation: unknown Whipple equation 'nasa'"),
    (["--bumper-cm", "0.1"], "--bumper-cm, --wall-cm and --spacing-cm describe one configuration"),
    (["--bumper-cm", "0", "--wall-cm", "0.3", "--spacing-cm", "10"], "--bumper-cm: bumper_thickness_cm = 0.0"),
    (["--bumper-cm", "0.1", "--wall-cm", "-0.3", "--spacing-cm", "10"], "--wall-cm: wall_thickness_cm = -0.3"),
    (["--bumper-cm", "0.1", "--wall-cm", "0.3", "--spacing-cm", "10", "--obliquity-deg", "90"],
     "--obliquity-deg: obliquity_deg = 90.0"),
    (["--bumper-cm", "0.1", "--wall-cm", "0.3", "--spacing-cm", "10", "--band", "0"], "--band: band = 0.0"),
    (["--plot", "v.txt"], "--plot: v.txt: unknown plot format"),
    (["--database", "missing.csv"], "missing.csv: no such file"),
])
def test_validate_bad_options_exit_2(tmp_path, monkeypatch, capsys, args, message):
    monkeypatch.chdir(tmp_path)
    assert main(["ble", "validate", *args]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("line, old, new, message", [
    (1, ",standoff,", ",spacing,", ":1: missing column(s) 'standoff'"),
    (2, ",deg,", ",rad,", ":2: units row: column 'angle' has unit 'rad', expected 'deg'"),
    (600, ",0.634,", ",0.634 cm,", ":600: column 'proj_diam': '0.634 cm' is not a number"),
])
def test_validate_malformed_database_names_file_and_line(tmp_path, capsys, line, old, new, message):
    lines = DATABASE_PATH.read_text(encoding="utf-8-sig").splitlines()
    assert old in lines[line - 1]
    lines[line - 1] = lines[line - 1].replace(old, new, 1)
    bad = tmp_path / "bad.csv"
    bad.write_text("\n".join(lines) + "\n")
    png = tmp_path / "v.png"
    assert main(["ble", "validate", "--database", str(bad), "--plot", str(png)]) == 2
    err = capsys.readouterr().err
    assert f"{bad}{message}" in err and "Traceback" not in err
    assert not png.exists()
    good = tmp_path / "good.csv"
    good.write_bytes(DATABASE_PATH.read_bytes())
    assert main(["ble", "validate", "--database", str(good), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["database"] == str(good)
