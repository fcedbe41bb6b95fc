"""The case-file reference of the documentation lists every key of the four kinds of case file.

The reference is generated when the docs are built (``docs/_ext/impactdyn_reference.py``); this
walks the case models on its own and compares.
"""

from __future__ import annotations

import pathlib
import re
import sys
import typing

import pytest
from pydantic import BaseModel

from impactdyn.beam import BeamCase
from impactdyn.debris import DebrisCase
from impactdyn.whipple import SelectionRule, WhippleCase

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "docs" / "_ext"))
import impactdyn_reference  # noqa: E402

CASES = (WhippleCase, DebrisCase, BeamCase, SelectionRule)


def _tables(annotation) -> list[type[BaseModel]]:
    """The tables a field holds (``Section``, ``Section | None``, a union of sections)."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return [annotation]
    return [table for arg in typing.get_args(annotation) for table in _tables(arg)]


def _keys(model: type[BaseModel], prefix: str = "") -> set[str]:
    keys = set()
    for name, info in model.model_fields.items():
        named = impactdyn_reference._named_table(info.annotation)
        tables = _tables(info.annotation)
        if named is not None:
            keys |= _keys(named, f"{prefix}{name}.NAME.")
        elif tables:
            for table in tables:
                keys |= _keys(table, f"{prefix}{name}.")
        else:
            keys.add(f"{prefix}{name}")
    return keys


def _section(page: str, model: type[BaseModel]) -> str:
    """The part of the reference about one case kind (from its heading to the next)."""
    kind = next(k for k in impactdyn_reference.CASE_KINDS if k.model is model)
    return page.split(f"\n## {kind.title}\n")[1].split("\n## ")[0]


@pytest.fixture(scope="module")
def page() -> str:
    return impactdyn_reference.case_reference()


def test_the_reference_covers_the_four_case_kinds():
    assert {kind.model for kind in impactdyn_reference.CASE_KINDS} == set(CASES)


@pytest.mark.parametrize("model", CASES, ids=lambda m: m.__name__)
def test_every_key_is_listed(page, model):
    listed = set(re.findall(r"^\| `([\w.\[\]]+)` \|", _section(page, model), flags=re.MULTILINE))
    assert _keys(model) == listed


def test_a_row_carries_unit_default_and_bounds(page):
    row = next(line for line in _section(page, WhippleCase).splitlines()
               if line.startswith("| `projectile.obliquity_deg` |"))
    assert [cell.strip() for cell in row.strip("|").split("|")][:5] == [
        "`projectile.obliquity_deg`", "number", "°", "`0.0`", "≥ 0, < 90"]


def test_a_setting_documented_in_its_class_docstring_keeps_its_description_in_a_case_table():
    """``name : text`` entries of an options class (here SPHOptions') describe the case keys that
    take the option over (``field_of``), so the reference has a description for them."""
    from impactdyn._config import documented_settings
    from impactdyn.shield import SPHOptions

    shield = WhippleCase.model_fields["shield"].annotation
    assert documented_settings(SPHOptions)["cfl"].startswith("the Courant factor of the time step")
    assert shield.model_fields["cfl"].description == documented_settings(SPHOptions)["cfl"]


def _text(key) -> str:
    """A key's description without the tag of its member of a union of tables, ``(model = "hertz")``."""
    tag = re.match(r"\(\w+ = [^)]*\) ?", key.description)
    return key.description[tag.end():] if tag else key.description


@pytest.mark.parametrize("model", CASES, ids=lambda m: m.__name__)
def test_every_key_has_a_description(model):
    """Each key of the four case kinds says what it means: a Field description or a ``name : text``
    entry of its section's docstring (:func:`impactdyn._config.documented_settings`)."""
    empty = [key.dotted for key in impactdyn_reference.case_keys(model) if not _text(key).strip()]
    assert empty == [], f"{model.__name__}: keys without a description: {', '.join(empty)}"


def test_a_rendered_row_carries_its_description(page):
    row = next(line for line in _section(page, WhippleCase).splitlines() if line.startswith("| `filter.dencut` |"))
    assert "bulk density ratio" in row.strip("|").split("|")[-1]


#: Words that carry no meaning of their own: a description needs more than these and symbols.
_FUNCTION_WORDS = frozenset("a an and as at by for from in into is it its of on or per than that the their "
                            "them these this to where which with none off default".split())


def _meaning_words(text: str) -> list[str]:
    """The words of ``text`` of three letters or more that are not function words (ρ₀, G, k, εₚ,f are not)."""
    return [w for w in re.findall(r"[^\W\d_]{3,}", text) if w.lower() not in _FUNCTION_WORDS]


@pytest.mark.parametrize("model", CASES, ids=lambda m: m.__name__)
def test_every_description_is_a_sentence_a_user_can_act_on(model):
    """A key's description says what the value means and does: at least five words ending with a full stop,
    not the key's name repeated, and at least three words of meaning besides its symbols ("G.", "A and B
    (≥ 0).", "the constants." are not descriptions)."""
    weak = []
    for key in impactdyn_reference.case_keys(model):
        text = _text(key).strip()
        name = key.dotted.rsplit(".", 1)[-1].replace("_", " ").lower()
        said = re.sub(r"[\W_]+", " ", text).strip().lower()
        problems = [problem for problem, found in [
            ("the key's name repeated", said in (name, name.replace(" ", ""))),
            ("fewer than 5 words", len(text.split()) < 5),
            ("no full stop at the end", not re.search(r"\.\)?$", text)),
            ("symbols without the meaning", len(_meaning_words(text)) < 3)] if found]
        if problems:
            weak.append(f"{key.dotted} ({', '.join(problems)}): {text!r}")
    assert weak == [], f"{model.__name__}: weak descriptions:\n" + "\n".join(weak)


def test_the_key_that_chooses_a_member_of_a_union_of_tables_is_listed_once_with_its_choices():
    """``contact.model`` chooses the beam's contact law: one row with every law and what each is, not one row
    per law that repeats its value."""
    rows = [key for key in impactdyn_reference.case_keys(BeamCase) if key.dotted == "contact.model"]
    assert len(rows) == 1
    assert rows[0].type == 'one of "momentum", "hertz", "hunt_crossley", "lankarani_nikravesh"'
    assert rows[0].description.startswith("the law of the contact between the beam and the stop")
    assert "IMPACTB's compliant contact" in rows[0].description


@pytest.mark.parametrize("model, key, bounds", [
    (DebrisCase, "integrator.steps_per_period", "> π"),  # not > 3.141592653589793
    (WhippleCase, "wall.spacing_cm", "> 0"),  # its own validator words the error; the bound is still shown
    (WhippleCase, "shield.cfl", "> 0, ≤ 1"),  # declared on the option and in its type: shown once
])
def test_bounds_are_printed_for_people(model, key, bounds):
    assert next(k for k in impactdyn_reference.case_keys(model) if k.dotted == key).bounds == bounds


@pytest.mark.parametrize("model, parameter, words", [
    ("impactdyn.wall.WallOptions", "q1", "float ≥ 0"),  # not Annotated[float, Ge(ge=0), AfterValidator(...)]
    ("impactdyn.wall.WallOptions", "courant", "float > 0, ≤ 1"),
    ("impactdyn.wall.WallOptions", "end_time_us", "float > 0 or None"),
    ("impactdyn.wall.WallOptions", "spall_law", 'a registered wall failure law: "tuler_butcher", "cutoff"'),
    ("impactdyn.debris.IntegratorOptions", "steps_per_period", "float > π or None"),
    ("impactdyn.wall.WallOptions", "mesh", 'one of "graded", "report"'),  # not Literal['graded', 'report']
])
def test_an_api_parameter_reads_as_its_type_and_bounds(model, parameter, words):
    import importlib
    import types

    module, _, name = model.rpartition(".")
    obj = getattr(importlib.import_module(module), name)
    app = types.SimpleNamespace(config=types.SimpleNamespace(autodoc_type_aliases={}))
    lines: list[str] = []
    impactdyn_reference._types_for_people(app, "class", model, obj, None, lines)
    assert f":type {parameter}: {words}" in lines
    assert not any(internal in line for line in lines for internal in ("Annotated", "Validator", "Literal"))


def test_the_api_pages_leave_out_pydantic_settings():
    assert impactdyn_reference._skip_model_config(None, "attribute", "model_config", {}, False, None) is True
    assert impactdyn_reference._skip_model_config(None, "attribute", "courant", 0.9, False, None) is None
