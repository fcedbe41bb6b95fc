"""``impactdyn materials list|show``: the library and a case's own materials, every constant with its source."""

import json
from pathlib import Path

from impactdyn.cli import main
from impactdyn.materials import AL_6061_T6, MATERIALS

EXAMPLE = Path(__file__).parents[1] / "examples" / "whipple" / "ti6al4v_7a.toml"


def test_list_names_the_library_and_with_case_its_own(capsys):
    assert main(["materials", "list", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert set(rows) == set(MATERIALS) and "weibull_flaws" in rows["al6061-t6"]["groups"]
    assert main(["materials", "list", "--case", str(EXAMPLE)]) == 0
    assert "ti6al4v" in capsys.readouterr().out


def test_show_gives_every_constant_with_its_source(capsys):
    assert main(["materials", "show", "Al 6061-T6", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["rho0"] == AL_6061_T6.rho0 and data["units"]["rho0"] == "g/cm³"
    assert all(data[g]["source"] for g in ("johnson_cook", "johnson_cook_damage", "tuler_butcher", "weibull_flaws",
                                          "fracture_toughness", "phase"))
    assert main(["materials", "show", "ti6al4v", "--case", str(EXAMPLE)]) == 0
    assert "D5" in capsys.readouterr().out


def test_an_unknown_name_or_a_bad_case_is_exit_2(capsys, tmp_path):
    assert main(["materials", "show", "unobtainium"]) == 2
    assert "unknown material 'unobtainium'" in capsys.readouterr().err
    assert main(["materials", "list", "--case", str(tmp_path / "none.toml")]) == 2
    assert "no such file" in capsys.readouterr().err
