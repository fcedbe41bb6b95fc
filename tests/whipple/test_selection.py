"""Selection rules as data: the shipped validation sets are the shots that were run, a fixed rule
cannot change, and a rule never splits a firing reported twice."""

import shutil

import numpy as np
import pytest

from impactdyn._errors import InputError
from impactdyn.ble import read_database
from impactdyn.whipple._selection import RULES_DIR, fix_rule, load_rule, rule_hash, select_shots

#: The file lines of the validation sets as they were selected and run (sets 1-3 scored, set 4 unrun),
#: by the rule in validation/select_validation_shots.py before it became data.
SETS_AS_RUN = {
    "set-1": [136, 138, 146, 164, 232, 292, 331, 332, 375, 569, 580, 609],
    "set-2": [224, 486, 533, 639, 674, 730, 751, 875, 882, 1000, 1008, 1020],
    "set-3": [82, 266, 596, 637, 641, 647, 705, 735, 958, 961, 970, 994],
    "set-4": [57, 410, 517, 588, 589, 604, 628, 734, 739, 786, 831, 1012],
}


@pytest.fixture(scope="module")
def db():
    return read_database()


@pytest.mark.parametrize("name", sorted(SETS_AS_RUN))
def test_the_shipped_rules_select_the_sets_that_were_run(db, name):
    rule = load_rule(name)
    chosen = select_shots(rule, db)
    assert [int(db.line[i]) for i in chosen] == SETS_AS_RUN[name]
    assert db.perforated[chosen].sum() == 6 and (~db.perforated[chosen]).sum() == 6
    assert (db.obliquity_deg[chosen] > 0).sum() >= 3
    assert rule.fixed is not None and rule.fixed.sha256 == rule_hash(rule)


def test_the_sets_are_disjoint_and_no_firing_is_in_two_of_them(db):
    groups = [db.twin_group[select_shots(load_rule(name), db)] for name in sorted(SETS_AS_RUN)]
    every = np.concatenate(groups)
    assert len(np.unique(every)) == len(every) == 48


def test_a_fixed_rule_that_was_changed_is_refused(tmp_path):
    path = tmp_path / "set-1.toml"
    shutil.copy(RULES_DIR / "set-1.toml", path)
    path.write_text(path.read_text().replace("perforated = 6", "perforated = 5"))
    with pytest.raises(InputError, match="changed after it was fixed on 2026-11-24"):
        load_rule(path)


def test_fixing_a_rule_stamps_its_hash_and_keeps_its_text(tmp_path):
    path = tmp_path / "mine.toml"
    text = (RULES_DIR / "set-1.toml").read_text()
    path.write_text(text[:text.index("[fixed]")].replace('name = "set-1"', 'name = "mine"'))
    rule = fix_rule(path, today="2026-12-01")
    assert rule.fixed.date == "2026-12-01" and rule.fixed.sha256 == rule_hash(rule)
    assert path.read_text().startswith(text[:text.index("[fixed]")].replace('name = "set-1"', 'name = "mine"'))
    assert fix_rule(path, today="2027-01-01").fixed.date == "2026-12-01", "a fixed rule is fixed once"


@pytest.mark.parametrize("change, key", [
    (("min_oblique = 3", "min_oblique = 3\nbogus = 1"), "counts.bogus"),
    (("perforated = 6", "perforated = -1"), "counts.perforated"),
    (("spacing_cm = 10.16", "spacing_cm = 0.0"), "distance.spacing_cm"),
    (('plate_alloys = ["AA6061-T6"', 'plate_alloys = ["AA1100-O"'), "eligible.plate_alloys: .*AA1100-O: no library"),
])
def test_a_bad_rule_names_its_key(tmp_path, change, key):
    path = tmp_path / "bad.toml"
    text = (RULES_DIR / "set-1.toml").read_text()
    path.write_text(text[:text.index("[fixed]")].replace(*change))
    with pytest.raises(InputError, match=f"{path}: {key}"):
        load_rule(path)


def test_an_unknown_rule_is_named(tmp_path):
    with pytest.raises(InputError, match="set-9: no such rule file, nor a shipped rule .*set-1"):
        load_rule("set-9")
