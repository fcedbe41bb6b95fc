"""Which test shots judge the simulation: selection rules as data, fixed before they are run.

A rule (a TOML file) picks shots from the test database (:func:`impactdyn.ble.read_database`):

1. **eligible**: the alloys the pipeline models (``projectile_alloys``, ``plate_alloys`` for
   bumper and wall), speed and diameter ranges, the smallest stand-off and wall thickness
   (bounds inclusive);
2. **distance** to a reference shield: D = |ln(t_b/t_b,ref)| + |ln(t_w/t_w,ref)| + |ln(S/S_ref)|;
3. **counts**: the ``perforated`` perforated (or spalled) and ``held`` not perforated eligible
   shots of smallest D (ties: file line); while fewer than ``min_oblique`` of them are oblique,
   the normal-incidence shot of largest D of one outcome is replaced by the nearest oblique one
   of the same outcome not yet taken, alternating outcomes, perforated first;
4. **after**: the shots of the rules named there are not eligible, so a set made "after" the
   earlier ones is disjoint from them.

Twins (one firing reported twice, :attr:`~impactdyn.ble.ShotDatabase.twin_group`) are never
split by a rule: a shot whose twin is taken by a rule named in ``after`` is not eligible, and
a chosen shot's twins are not eligible either, so the same firing cannot be counted twice.

A rule is **fixed** before its shots are run: ``impactdyn whipple fix-rule RULE.toml`` writes
the date and the SHA-256 of its content into it (:func:`fix_rule`).  A fixed rule whose
content no longer matches its hash is refused (:func:`load_rule`): a set is never rescored
under a changed rule, and a spent set stays spent.

The package ships the validation sets of the wall stage, ``set-1`` … ``set-4`` (files in
``whipple/rules/``; their history is in each file's ``description``).
"""

from __future__ import annotations

import hashlib
import json
from datetime import date
from pathlib import Path
from typing import Annotated

import numpy as np
import tomli_w
from pydantic import Field, field_validator

from impactdyn._config import Positive, Section, load_toml, validate
from impactdyn._errors import InputError, reading
from impactdyn._runfolder import atomic_output
from impactdyn.ble import ShotDatabase, read_database
from impactdyn.whipple._database_shot import ALLOYS

RULES_DIR = Path(__file__).parent / "rules"

Count = Annotated[int, Field(ge=0)]


class Eligible(Section):
    """Rule step 1: the shots the pipeline can model (bounds inclusive).

    projectile_alloys : the database's names of the projectile alloys a shot may have, each one the
        pipeline models (:data:`impactdyn.whipple.ALLOYS` maps them to library materials).
    plate_alloys : the alloys its bumper and its wall may have (both must be listed).
    velocity_km_s : the range of impact speeds a shot may have, [lowest, highest], both ends
        included.
    diameter_cm : the range of projectile diameters a shot may have, [smallest, largest], both
        ends included.
    min_spacing_cm : the smallest stand-off between bumper and wall (the hand-off grid must fit in
        it); 0: any.
    min_wall_thickness_cm : the thinnest wall; 0: any.
    """

    projectile_alloys: list[str] = Field(min_length=1)
    plate_alloys: list[str] = Field(min_length=1)
    velocity_km_s: Annotated[list[float], Field(min_length=2, max_length=2)]
    diameter_cm: Annotated[list[float], Field(min_length=2, max_length=2)]
    min_spacing_cm: float = 0.0
    min_wall_thickness_cm: float = 0.0

    @field_validator("projectile_alloys", "plate_alloys")
    @classmethod
    def _modelled(cls, alloys: list[str]) -> list[str]:
        unknown = [a for a in alloys if a not in ALLOYS]
        if unknown:
            raise ValueError(f"{', '.join(unknown)}: no library material (modelled: {', '.join(sorted(ALLOYS))})")
        return alloys


class Reference(Section):
    """Rule step 2: the shield the distance D is measured from.

    bumper_thickness_cm, wall_thickness_cm, spacing_cm : the reference shield's t_b,ref, t_w,ref and
        S_ref in D = |ln(t_b/t_b,ref)| + |ln(t_w/t_w,ref)| + |ln(S/S_ref)| (the shipped sets: the
        report's Table 2 shield).
    """

    bumper_thickness_cm: Positive
    wall_thickness_cm: Positive
    spacing_cm: Positive


class Counts(Section):
    """Rule step 3: how many shots of each outcome, and how many of them at least oblique.

    perforated : the number of perforated (or spalled) shots to take, nearest first.
    held : the number of shots that did not perforate to take, nearest first.
    min_oblique : how many of the chosen shots at least must be oblique; nearer normal-incidence
        shots are swapped for oblique ones until they are (module docstring); 0: no such swap.
    """

    perforated: Count
    held: Count
    min_oblique: Count = 0


class Fixed(Section):
    """When the rule was fixed and the SHA-256 of its content then (:func:`rule_hash`).  Written by
    ``impactdyn whipple fix-rule``, not by hand.

    date : the day the rule was fixed (ISO 8601, YYYY-MM-DD), before its shots were run.
    sha256 : the SHA-256 of the rule's content (every key but ``[fixed]``) then; a rule whose
        content no longer matches it is refused.
    """

    date: str
    sha256: str


class SelectionRule(Section):
    """A selection rule (module docstring).

    name : the rule's name, recorded with the scores of its set (``whipple validate --select``);
        a shipped rule's is its file's name (``set-1`` …).
    description : free text: what the set is for, and its history.
    after : rules (shipped names or file paths) whose shots, and their twins, this rule may not
        take, so that its set is disjoint from theirs.
    """

    name: str = Field(min_length=1)
    description: str = ""
    after: list[str] = []
    eligible: Eligible
    distance: Reference
    counts: Counts
    fixed: Fixed | None = None


def rule_hash(rule: SelectionRule) -> str:
    """SHA-256 of the rule's content (every key but ``fixed``), as canonical JSON."""
    content = rule.model_dump(mode="json", exclude={"fixed"})
    return hashlib.sha256(json.dumps(content, sort_keys=True).encode()).hexdigest()


def rule_path(name_or_path: str | Path) -> Path:
    """A shipped rule's file by its name (``set-1``), or else the path given."""
    shipped = RULES_DIR / f"{name_or_path}.toml"
    if shipped.is_file():
        return shipped
    path = Path(name_or_path)
    if not path.is_file():
        names = ", ".join(sorted(p.stem for p in RULES_DIR.glob("*.toml")))
        raise InputError(f"{name_or_path}: no such rule file, nor a shipped rule ({names})")
    return path


def shipped_rule(name: str, sha256: str) -> SelectionRule | None:
    """The shipped rule ``name`` if its content has the hash ``sha256`` (:func:`rule_hash`), else None: a rule
    file of another's name, or a shipped rule changed since, is not that rule."""
    path = RULES_DIR / f"{name}.toml"
    if not path.is_file():
        return None
    rule = validate(SelectionRule, load_toml(path), source=str(path))
    return rule if rule_hash(rule) == sha256 else None


def load_rule(name_or_path: str | Path) -> SelectionRule:
    """The rule, validated; a fixed rule must still match its hash, and the rules named in its
    ``after`` must load and must not lead back to it."""
    return _load_rule(rule_path(name_or_path), ())


def _load_rule(path: Path, named_by: tuple[Path, ...]) -> SelectionRule:
    """:func:`load_rule` of the file ``path``, reached through the ``after`` of the rules ``named_by``."""
    with reading(path, "rule file"):
        rule = validate(SelectionRule, load_toml(path), source=str(path))
    if rule.fixed is not None and rule.fixed.sha256 != rule_hash(rule):
        raise InputError(f"{path}: the rule was changed after it was fixed on {rule.fixed.date} (its content no "
                         "longer matches fixed.sha256); a fixed set is never rescored under another rule: "
                         "write a new rule under a new name")
    chain = (*named_by, path.resolve())
    for i, earlier in enumerate(rule.after):
        try:
            earlier_path = rule_path(earlier)
        except InputError as err:
            raise InputError(f"{path}: after[{i}]: {err}") from None
        if earlier_path.resolve() in chain:
            raise InputError(f"{path}: after[{i}] = {earlier!r} leads back to {earlier_path}: a rule cannot be "
                             "selected after itself")
        _load_rule(earlier_path, chain)
    return rule


def fix_rule(path: str | Path, today: str | None = None) -> SelectionRule:
    """Write ``[fixed]`` (today's date and the content's hash) into the rule file ``path``.

    A rule fixed already is left as it is if unchanged, and refused (by :func:`load_rule`) if changed.
    """
    path = Path(path)
    rule = load_rule(path)
    if rule.fixed is not None:
        return rule
    fixed = {"fixed": {"date": today or date.today().isoformat(), "sha256": rule_hash(rule)}}
    text = path.read_text()
    with atomic_output(path) as tmp:  # appended, so the rule's own text and comments stay as written
        tmp.write_text(text + ("" if text.endswith("\n") else "\n") + "\n" + tomli_w.dumps(fixed))
    return load_rule(path)


def select_shots(rule: SelectionRule, database: ShotDatabase | None = None) -> np.ndarray:
    """Indices into ``database`` (default: the packaged one) of the shots ``rule`` picks, in file order."""
    db = read_database() if database is None else database
    taken = np.zeros(len(db), dtype=bool)
    for earlier in rule.after:
        taken[select_shots(load_rule(earlier), db)] = True
    eligible = _eligible(rule.eligible, db) & ~db.with_twins(taken)
    distance = sum(np.abs(np.log(getattr(db, key) / ref)) for key, ref in rule.distance.model_dump().items())
    order = sorted(np.flatnonzero(eligible), key=lambda i: (distance[i], db.line[i]))
    chosen = {True: [], False: []}
    for i in order:  # nearest first, a firing once: a shot's twin is not taken beside it
        wanted = rule.counts.perforated if db.perforated[i] else rule.counts.held
        group_taken = any(db.twin_group[j] == db.twin_group[i] for o in chosen for j in chosen[o])
        if len(chosen[bool(db.perforated[i])]) < wanted and not group_taken:
            chosen[bool(db.perforated[i])].append(i)
    _meet_oblique(chosen, order, db, distance, rule.counts.min_oblique)
    return np.array(sorted(chosen[True] + chosen[False]), dtype=int)


def _eligible(e: Eligible, db: ShotDatabase) -> np.ndarray:
    (v_lo, v_hi), (d_lo, d_hi) = e.velocity_km_s, e.diameter_cm
    return (np.isin(db.projectile_material, e.projectile_alloys) & np.isin(db.bumper_material, e.plate_alloys)
            & np.isin(db.wall_material, e.plate_alloys)
            & (db.velocity_km_s >= v_lo) & (db.velocity_km_s <= v_hi)
            & (db.diameter_cm >= d_lo) & (db.diameter_cm <= d_hi)
            & (db.spacing_cm >= e.min_spacing_cm) & (db.wall_thickness_cm >= e.min_wall_thickness_cm))


def _meet_oblique(chosen: dict[bool, list[int]], order: list[int], db: ShotDatabase, distance: np.ndarray,
                  min_oblique: int) -> None:
    """Rule step 3's swaps, in place: normal-incidence shots of largest D out, the nearest oblique in
    (never a twin of a chosen shot); ends when a round over both outcomes finds nothing to swap."""
    oblique = lambda i: db.obliquity_deg[i] > 0  # noqa: E731
    outcome, idle = True, 0
    while sum(oblique(i) for o in chosen for i in chosen[o]) < min_oblique and idle < 2:
        groups = {db.twin_group[i] for o in chosen for i in chosen[o]}
        normal = [i for i in chosen[outcome] if not oblique(i)]
        spare = [i for i in order if bool(db.perforated[i]) == outcome and oblique(i)
                 and db.twin_group[i] not in groups]
        if normal and spare:
            chosen[outcome].remove(max(normal, key=lambda i: distance[i]))
            chosen[outcome].append(spare[0])
            idle = 0
        else:
            idle += 1
        outcome = not outcome
