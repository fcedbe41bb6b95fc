"""The packaged test database, its reader's checks, and the shots near a configuration."""

import fnmatch
import hashlib
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest

from impactdyn import InputError
from impactdyn.ble import DATABASE_PATH, ShotDatabase, WhippleShield, nearby_shots, read_database

ROOT = Path(__file__).resolve().parents[2]
DATA = DATABASE_PATH.parent


def test_packaged_file_is_the_published_one_with_its_licence():
    notice = (DATA / "README.md").read_text()
    sha = re.search(r"sha256\s+`([0-9a-f]{64})`", notice)[1]
    assert hashlib.sha256(DATABASE_PATH.read_bytes()).hexdigest() == sha
    assert 'MIT, "Copyright (c) 2023 shannonjryan"' in notice
    licence = (DATA / "LICENSE").read_text()
    assert licence.startswith("MIT License") and "Copyright (c) 2023 shannonjryan" in licence
    assert "The above copyright notice and this permission notice shall be included" in licence


def test_package_data_ships_the_database_and_its_notices():
    patterns = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["package-data"]["impactdyn"]
    pkg = ROOT / "src" / "impactdyn"
    for f in (DATABASE_PATH, DATA / "LICENSE", DATA / "README.md"):
        rel = f.relative_to(pkg).as_posix()
        assert any(fnmatch.fnmatch(rel, p) for p in patterns), rel


def test_reads_every_shot():
    db = read_database()
    notice = (DATA / "README.md").read_text()
    shots, p, np_ = map(int, re.search(r"(\d+) light-gas-gun shots .*?\((\d+) perforated, (\d+) not\)", notice,
                                       re.S).groups())
    assert len(db) == shots and int(db.perforated.sum()) == p and int((~db.perforated).sum()) == np_
    lines = DATABASE_PATH.read_text(encoding="utf-8-sig").splitlines()
    assert len(lines) == shots + 2
    # spot-check against the raw text, one row in fifty
    header = lines[0].split(",")
    for i in range(0, len(db), 50):
        row = dict(zip(header, lines[db.line[i] - 1].split(",")))
        assert db.diameter_cm[i] == float(row["proj_diam"]) and db.velocity_km_s[i] == float(row["velocity"])
        assert db.spacing_cm[i] == float(row["standoff"]) and db.wall_yield_ksi[i] == float(row["wall_yield"])
        assert db.shot_id[i] == row["shotID"].strip() and db.perforated[i] == (row["result"] == "P")
    assert db.path == str(DATABASE_PATH)


def test_subset():
    db = read_database()
    mask = db.velocity_km_s > 7.0
    sub = db.subset(mask)
    assert isinstance(sub, ShotDatabase) and len(sub) == mask.sum() and sub.path == db.path
    assert np.array_equal(sub.line, db.line[mask]) and np.array_equal(sub.perforated, db.perforated[mask])


def _write(tmp_path, text, name="db.csv"):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def _edit(line: int, old: str, new: str) -> str:
    """The packaged text with ``old`` replaced by ``new`` on (1-based) line ``line``."""
    lines = DATABASE_PATH.read_text(encoding="utf-8-sig").splitlines()
    assert old in lines[line - 1]
    lines[line - 1] = lines[line - 1].replace(old, new, 1)
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("text, where, message", [
    (lambda: _edit(1, ",velocity,", ",speed,"), ":1:", "missing column(s) 'velocity'"),
    (lambda: _edit(2, ",km/s,", ",m/s,"), ":2:", "column 'velocity' has unit 'm/s', expected 'km/s'"),
    (lambda: _edit(2, ",ksi,", ",MPa,"), ":2:", "column 'wall_yield' has unit 'MPa', expected 'ksi'"),
    (lambda: _edit(40, ",P,1", ",P"), ":40:", "16 cells, expected 17"),
    (lambda: _edit(7, ",2.7,", ",2,7,"), ":7:", "18 cells, expected 17"),
    (lambda: _edit(100, ",7.52,", ",7.52x,"), ":100:", "column 'velocity': '7.52x' is not a number"),
    (lambda: _edit(5, ",0,", ",95,"), ":5:", "column 'angle': '95' must be in [0, 90)"),
    (lambda: _edit(1136, ",P,1", ",P,0"), ":1136:", "'perforated_class': '0' contradicts result P"),
    (lambda: _edit(12, ",NP,", ",maybe,"), ":12:", "column 'result': 'maybe' must be P or NP"),
    (lambda: "", ":1:", "empty file"),
    (lambda: DATABASE_PATH.read_text(encoding="utf-8-sig").splitlines()[0] + "\n", ":2:", "no units row"),
    (lambda: "\n".join(DATABASE_PATH.read_text(encoding="utf-8-sig").splitlines()[:2]) + "\n", ":3:", "no shots"),
])
def test_malformed_file_names_file_and_line(tmp_path, text, where, message):
    p = _write(tmp_path, text())
    with pytest.raises(InputError) as err:
        read_database(p)
    assert f"{p}{where}" in str(err.value) and message in str(err.value)


def test_non_numeric_cell_names_the_column(tmp_path):
    p = _write(tmp_path, _edit(9, ",9.", ",nine."))
    with pytest.raises(InputError, match=re.escape(f"{p}:9: column 'velocity': 'nine.") + r".*is not a number"):
        read_database(p)


def test_unreadable_files(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        read_database(tmp_path / "nope.csv")
    with pytest.raises(InputError, match="is a folder"):
        read_database(tmp_path)
    bad = tmp_path / "latin1.csv"
    bad.write_bytes(b"source,shotID\xe9\n")
    with pytest.raises(InputError, match=f"{re.escape(str(bad))}: not UTF-8 text"):
        read_database(bad)


def test_columns_in_another_order_and_extra_columns_are_read(tmp_path):
    lines = DATABASE_PATH.read_text(encoding="utf-8-sig").splitlines()
    rows = [line.split(",") for line in lines]
    order = list(range(len(rows[0])))[::-1]
    text = "\n".join(",".join([r[i] for i in order] + ["extra"]) for r in rows) + "\n\n"
    db = read_database(_write(tmp_path, text))
    ref = read_database()
    for name in ("diameter_cm", "velocity_km_s", "obliquity_deg", "perforated", "spacing_cm"):
        assert np.array_equal(getattr(db, name), getattr(ref, name))


# ------------------------------------------------------------------ shots near a configuration


@pytest.mark.parametrize("band", [0.05, 0.10, 0.25])
def test_nearby_shots_are_within_the_bands_and_no_others(band):
    shield = WhippleShield(0.16, 0.318, 10.16, 40.0)
    db = read_database()
    near = nearby_shots(shield, database=db, band=band)
    rel = np.stack([db.bumper_thickness_cm / 0.16, db.wall_thickness_cm / 0.318, db.spacing_cm / 10.16]) - 1
    inside = np.all(np.abs(rel) <= band, axis=0)
    assert len(near) == inside.sum() > 0
    assert np.array_equal(near.line, db.line[inside])


def test_nearby_shots_obliquity_band():
    shield = WhippleShield(0.16, 0.318, 10.16, 40.0)
    everything = nearby_shots(shield)
    near = nearby_shots(shield, 45.0, obliquity_band_deg=5.0)
    assert 0 < len(near) < len(everything)
    assert np.all(np.abs(near.obliquity_deg - 45.0) <= 5.0)
    assert set(everything.line[np.abs(everything.obliquity_deg - 45.0) <= 5.0]) == set(near.line)
    assert len(nearby_shots(WhippleShield(5.0, 5.0, 500.0, 40.0))) == 0
    with pytest.raises(InputError, match="band"):
        nearby_shots(shield, band=0.0)
    with pytest.raises(InputError, match="obliquity_deg"):
        nearby_shots(shield, 90.0)


# ------------------------------------------------------------------ twins: one firing reported twice


def test_twin_groups_and_conflicts_in_the_packaged_file():
    db = read_database()
    labels, size = np.unique(db.twin_group, return_counts=True)
    twins = labels[size > 1]
    assert len(twins) == 17 and size.max() == 2  # 15 AFML pairs, Piekutowski 4-2011, JSC A151
    afml = {frozenset(db.source[db.twin_group == g]) for g in twins}
    assert afml == {frozenset({"AFML-TR-67-324", "AFML-TR-68-257"}), frozenset({"Piekutowski_2011", "Piekutowski_2013"}),
                    frozenset({"ELC_87-163", "TP-2003-210788"})}
    for g in twins:
        assert len(set(db.shot_id[db.twin_group == g])) == 1
    # one conflicting pair: shot 2225, held in AFML-TR-67-324 (line 301), perforated in AFML-TR-68-257 (line 452)
    assert sorted(db.line[db.twin_conflict]) == [301, 452]
    assert set(db.shot_id[db.twin_conflict]) == {"2225"}
    # lines 180 and 181: shot 2046 in both AFML reports, one group, same outcome
    at = {line: i for i, line in enumerate(db.line)}
    assert db.twin_group[at[180]] == db.twin_group[at[181]] and not db.twin_conflict[at[180]]
    # ID 1 is shot 1 of Kinslow 1971 (line 41) and of AFML-TR-70-135 (line 1113): two firings, d 0.153 and 0.318 cm
    assert db.twin_group[at[41]] != db.twin_group[at[1113]] and db.shot_id[at[41]] == db.shot_id[at[1113]] == "1"


def test_materials_are_read():
    db = read_database()
    assert db.projectile_material[0] == "AA2017-T4" and db.wall_material[1] == "AA2219-T87"
    assert set(db.bumper_material) >= {"AA6061-T6", "Alclad 7075-T6"}


def test_with_twins_never_splits_a_group():
    db = read_database()
    rng = np.random.default_rng(7)
    for fraction in (0.02, 0.3, 0.7):
        mask = rng.random(len(db)) < fraction
        grown = db.with_twins(mask)
        assert np.all(grown[mask])  # only grows
        for g in np.unique(db.twin_group):
            inside = grown[db.twin_group == g]
            assert inside.all() or not inside.any()
        # it grows by the twins of the chosen shots and nothing else
        assert set(db.twin_group[grown]) == set(db.twin_group[mask])
    at = {line: i for i, line in enumerate(db.line)}
    one = np.zeros(len(db), dtype=bool)
    one[at[301]] = True
    assert sorted(db.line[db.with_twins(one)]) == [301, 452]


def test_subset_keeps_twin_labels():
    db = read_database()
    sub = db.subset(db.source == "AFML-TR-68-257")
    assert np.all(np.isin(sub.twin_group, db.twin_group)) and sub.twin_conflict.sum() == 1
