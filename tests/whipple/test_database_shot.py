"""A test-database shot as a Whipple case: the validation cases reproduced, the lookup, the command's errors."""

import json
import tomllib
from pathlib import Path

import numpy as np
import pytest

from impactdyn import InputError
from impactdyn.ble import read_database
from impactdyn.cli import main
from impactdyn.whipple import ALLOYS, WhippleCase, ble_verdict, database_shot, database_shot_case, load_whipple_case

#: Validation set 1's cases as ``validation/run_validation_shots.py`` built them before its rules moved
#: into the package: file line → {shot_id, case}.
SET1 = json.loads((Path(__file__).parent / "data" / "validation_set1_cases.json").read_text())
EXAMPLE = tomllib.loads((Path(__file__).parents[2] / "examples" / "whipple" / "table2_7a.toml").read_text())


@pytest.fixture(scope="module")
def db():
    return read_database()


@pytest.mark.parametrize("line", sorted(SET1, key=int))
def test_validation_set1_cases_are_reproduced(db, line):
    shot = database_shot(int(line), db)
    case = database_shot_case(shot)
    expected = SET1[line]["case"]
    assert shot.shot_id == SET1[line]["shot_id"]
    # the title and the [test_shot] record are labels ("test shot" now, "validation shot" then; the record is
    # newer than the fixture); every other value is equal
    labels = ("title", "test_shot")
    assert {k: v for k, v in case.items() if k not in labels} == {k: v for k, v in expected.items() if k not in labels}
    assert all(word in case["title"] for word in (shot.source, shot.shot_id, f"line {line}"))


def test_the_set1_cases_cover_every_rule():
    """The fixture exercises each geometry rule both ways (else its equality above proves little)."""
    cases = [entry["case"] for entry in SET1.values()]
    standoffs = {c["wall"]["spacing_cm"] for c in cases}
    assert min(standoffs) < EXAMPLE["wall"]["spacing_cm"] < max(standoffs)  # extent shrunk and grown
    assert any(c["filter"]["t_cut_us"] > EXAMPLE["filter"]["t_cut_us"] for c in cases)
    assert any(c["shield"]["spacing_cm"] < EXAMPLE["shield"]["spacing_cm"] for c in cases)
    assert any(c["shield"]["spacing_cm"] == EXAMPLE["shield"]["spacing_cm"] for c in cases)
    assert len({c["wall"]["material"] for c in cases}) == 2


def test_set1_windows_per_flight_time_are_at_least_the_documented_share_of_the_examples():
    """The module docstring's claim: t_cut·V/S ≥ 0.88 of the example's on set 1 (speed does not stretch it)."""
    def share(c):
        return c["filter"]["t_cut_us"] * c["projectile"]["velocity_km_s"] / c["wall"]["spacing_cm"]

    ratios = [share(e["case"]) / share(EXAMPLE) for e in SET1.values()]
    assert 0.88 <= min(ratios) < 0.89


def test_shot_values_go_into_the_case_and_the_case_validates(db):
    shot = database_shot("B31", db)  # 20.32 cm stand-off: twice the example's
    case = database_shot_case(shot)
    WhippleCase.model_validate(case)
    assert case["wall"]["spacing_cm"] == shot.spacing_cm == 20.32
    assert case["wall"]["nodes"] == [101, 5, 201]  # the example's 0.16 cm elements over twice the extent
    assert case["wall"]["x_cm"] == [0.0, 16.0] and case["wall"]["z_cm"] == [-8.0, 24.0]
    assert case["filter"]["t_cut_us"] == 50.0
    assert case["shield"]["handoff_us"] == EXAMPLE["shield"]["handoff_us"]
    assert (case["projectile"]["diameter_cm"], case["projectile"]["velocity_km_s"]) == (shot.diameter_cm,
                                                                                        shot.velocity_km_s)
    assert case["wall"]["yield_stress_ksi"] == shot.wall_yield_ksi
    assert case["projectile"]["material"] == ALLOYS[shot.alloys["projectile"]]
    # the test itself rides along for the report, by the database file's name
    assert case["test_shot"] == {"database": "database_whipple_pyBLOSSUM.csv", "line": 292,
                                 "source": "TP-2003-210788", "shot_id": "B31", "perforated": shot.perforated}
    assert WhippleCase.model_validate(case).test_shot.outcome == shot.outcome


@pytest.mark.parametrize("perforated, words", [(True, "perforation or detached spall"), (False, "no perforation")])
def test_the_tests_outcome_is_said_in_the_verdicts_words(db, perforated, words):
    line = int(db.line[np.flatnonzero(db.perforated == perforated)[0]])
    assert database_shot(line, db).outcome == words


def test_a_base_case_gives_its_numerics(tmp_path, db, make_case):
    base = make_case(tmp_path)  # the coarse 7a: 0.45 cm projectile, 0.1 cm SPH spacing, 3 cm wall spacing
    shot = database_shot(375, db)  # 0.3175 cm at 5.08 cm
    case = database_shot_case(shot, base)
    assert case["shield"]["spacing_cm"] == pytest.approx(0.1 * 0.3175 / 0.45)
    assert case["wall"]["spacing_cm"] == 5.08
    assert case["wall"]["nodes"] == [round(15 * 5.08 / 3.0) + 1, 3, round(30 * 5.08 / 3.0) + 1]


# --- lookup ---------------------------------------------------------------------------------------------------

def test_a_shot_is_found_by_line_or_by_id(db):
    by_line, by_id = database_shot(292, db), database_shot("B31", db)
    assert by_line == by_id == database_shot("292", db) == database_shot("line:292", db) == database_shot("id:B31", db)
    assert (by_line.line, by_line.shot_id, by_line.perforated) == (292, "B31", db.perforated[db.line == 292][0])
    assert by_line.alloys == {"projectile": "AA2017-T4", "bumper": "AA6061-T6", "wall": "AA6061-T6"}


def test_a_numeric_id_is_reached_with_its_prefix(db):
    shot = database_shot("id:9", db)
    assert shot.shot_id == "9" and shot.line != 9


@pytest.mark.parametrize("key, words", [
    (99999, ["line 99999"]),
    ("line:2", ["line 2"]),
    ("nosuch", ["'nosuch'"]),
    ("4-2110", ["'4-2110'", "3", "1126"]),  # an ID on two lines: both are named to choose from
    ("9", ["'9'", "line:9", "id:9"]),  # a line and an ID
    ("line:x", ["line:x"]),
])
def test_bad_keys_are_refused_naming_them(db, key, words):
    with pytest.raises(InputError) as err:
        database_shot(key, db)
    assert all(w in str(err.value) for w in words), str(err.value)


def test_an_unmapped_alloy_is_refused_naming_the_line_and_alloy(db):
    shot = database_shot(9, db)  # an AA2219-T87 wall
    with pytest.raises(InputError, match=r":9: shot 8-3260: wall alloy 'AA2219-T87'"):
        database_shot_case(shot)


# --- the command ----------------------------------------------------------------------------------------------

def test_write_case_writes_the_functions_case_and_it_loads(tmp_path, capsys):
    path = tmp_path / "b31.toml"
    assert main(["whipple", "shot", "--database", "B31", "--write-case", str(path)]) == 0
    assert tomllib.loads(path.read_text()) == database_shot_case(database_shot("B31"))
    assert load_whipple_case(path).wall.spacing_cm == 20.32  # what `whipple run` loads
    assert str(path) in capsys.readouterr().out
    assert [p.name for p in tmp_path.iterdir()] == ["b31.toml"]  # no staging file left


def test_write_case_refuses_to_overwrite_without_force(tmp_path, capsys):
    path = tmp_path / "case.toml"
    path.write_text("kept\n")
    assert main(["whipple", "shot", "--database", "B31", "--write-case", str(path)]) == 2
    refused = capsys.readouterr()
    assert "--force" in refused.err and path.read_text() == "kept\n"
    assert refused.out == ""  # the refusal alone: no note of a case that was not written
    assert main(["whipple", "shot", "--database", "B31", "--write-case", str(path), "--force"]) == 0
    assert tomllib.loads(path.read_text())["wall"]["spacing_cm"] == 20.32


def _bad_from_case(d: Path) -> list[str]:
    bad = d / "bad.toml"
    bad.write_text('[projectile]\ndiameter_cm = 0.5\nbogus = 1\n')
    return ["--from-case", str(bad)]


@pytest.mark.parametrize("args, words", [
    (["--database", "line:99999"], ["line 99999"]),
    (["--database", "nosuch"], ["'nosuch'"]),
    (["--database", "4-2110"], ["1126"]),
    (["--database", "9"], ["id:9"]),
    (["--database", "line:9"], ["'AA2219-T87'"]),
    (["--database", "B31", "--from-case", "nowhere.toml"], ["nowhere.toml"]),
    (["--database", "B31", "BAD"], ["bad.toml"]),
], ids=["line", "id", "ambiguous id", "line or id", "alloy", "missing base", "bad base"])
@pytest.mark.parametrize("output", ["-o", "--write-case"])
def test_bad_input_exits_2_naming_it_and_writes_nothing(tmp_path, capsys, monkeypatch, args, words, output):
    monkeypatch.chdir(tmp_path)
    args = [a for arg in args for a in (_bad_from_case(tmp_path) if arg == "BAD" else [arg])]
    before = sorted(tmp_path.iterdir())
    assert main(["whipple", "shot", *args, output, str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("error: ") == 1 and all(w in err for w in words), err
    assert sorted(tmp_path.iterdir()) == before


def test_the_command_needs_exactly_one_of_out_and_write_case(tmp_path, capsys):
    assert main(["whipple", "shot", "--database", "B31"]) == 2
    assert main(["whipple", "shot", "--database", "B31", "-o", str(tmp_path / "run"),
                 "--write-case", str(tmp_path / "case.toml")]) == 2
    assert capsys.readouterr().err.count("--write-case") == 2
    assert list(tmp_path.iterdir()) == []


def test_a_run_prints_the_tests_outcome_beside_the_verdicts(tmp_path, capsys, monkeypatch):
    """The run path, with the pipeline replaced by a stand-in (a real run is tests/whipple/test_whipple_pipeline.py's):
    the shot's case goes to the pipeline, the run's summary is echoed as `whipple run` echoes it, then the verdicts."""
    import impactdyn.whipple

    ran = {}

    def pipeline(case, out, start, force, progress, keep):
        ran.update(case=case, out=out, start=start, keep=keep)
        return {"ble": {"equation": "jsc2011", "threshold_cm": 0.6, "regime": "shatter", "verdict": "perforation"},
                "cloud": {},
                "deposition": {"peak_areal_momentum_N_s_cm2": 0.1, "impulse_on_wall_normal_N_s_full_model": 0.3},
                "wall_time_s": 1.0, "wall": {"verdict": "detached spall", "criterion": "spall"},
                "draws": {"n_draws": 1, "draws": [{"seed": 1, "verdict": "detached spall", "perforated": True}],
                          "perforated": 1, "probability": 1.0, "wilson_95": [0.21, 1.0]}}

    monkeypatch.setattr(impactdyn.whipple, "run_whipple", pipeline)
    out = tmp_path / "run"
    assert main(["whipple", "shot", "--database", "B31", "-o", str(out)]) == 0
    assert ran == {"case": WhippleCase.model_validate(database_shot_case(database_shot("B31"))), "out": out,
                   "start": "shield", "keep": "lean"}
    printed = [line for line in capsys.readouterr().out.splitlines() if line.strip()]  # the bars leave blank lines
    assert printed[0] == ("note: projectile: AA2017-T4 modelled as al2024-t4, the library's nearest alloy "
                          "(the same Al-Cu family, 2.79 against 2.785 g/cm³)")
    printed = printed[1:]
    assert printed[0].startswith("ballistic limit (jsc2011)")
    assert printed[-2].startswith("wall response: detached spall")
    outcome = "perforation or detached spall" if database_shot("B31").perforated else "no perforation"
    assert printed[-1] == (f"test TP-2003-210788 B31 (line 292 of database_whipple_pyBLOSSUM.csv): {outcome}; "
                           "simulated: detached spall; JSC: perforation")


def test_write_case_prints_the_tests_outcome_the_jsc_verdict_and_each_substituted_alloy(tmp_path, capsys):
    path = tmp_path / "b31.toml"
    assert main(["whipple", "shot", "--database", "B31", "--write-case", str(path)]) == 0
    out = capsys.readouterr().out
    shot = database_shot("B31")
    assert shot.alloys["projectile"] == "AA2017-T4"  # modelled as the library's 2024-T4
    jsc = ble_verdict(WhippleCase.model_validate(database_shot_case(shot)))["verdict"]
    assert f"{shot.name}: {shot.outcome}; simulated: not run" in out and out.rstrip().endswith(f"JSC: {jsc}")
    assert "projectile: AA2017-T4 modelled as al2024-t4, the library's nearest alloy" in out
    text = path.read_text()
    assert f"# the test: {shot.outcome}" in text
    assert load_whipple_case(path).test_shot == shot.record  # `whipple run` of the file reports the test
    material = text.index('material = "al2024-t4"')
    assert text.rfind("# projectile: AA2017-T4 modelled as al2024-t4", 0, material) > text.index("[projectile]")


def test_a_written_case_rounds_the_scaled_sph_pitch_and_says_how_it_was_derived(tmp_path):
    path = tmp_path / "emi.toml"
    assert main(["whipple", "shot", "--database", "line:232", "--write-case", str(path)]) == 0
    shot, written = database_shot(232), tomllib.loads(path.read_text())
    exact = database_shot_case(shot)["shield"]["spacing_cm"]
    assert exact < EXAMPLE["shield"]["spacing_cm"] and written["shield"]["spacing_cm"] != exact  # scaled, rounded
    assert written["shield"]["spacing_cm"] == pytest.approx(exact, rel=5e-4) and len(repr(written["shield"]["spacing_cm"])) <= 8
    assert f"× d/d₀ = {shot.diameter_cm:g}/{EXAMPLE['projectile']['diameter_cm']:g}" in path.read_text()
    # everything else is the case `whipple shot -o` runs
    assert {k: v for k, v in written.items() if k != "shield"} == {
        k: v for k, v in database_shot_case(shot).items() if k != "shield"}


def test_every_alloy_mapped_to_another_alloys_material_says_why():
    from impactdyn.whipple._database_shot import SUBSTITUTED

    other = {alloy for alloy, material in ALLOYS.items() if alloy.lower().removeprefix("aa") != material.removeprefix("al")}
    assert other == set(SUBSTITUTED) == {"AA2017-T4", "AA2024-T3", "AA2024-T351"}
