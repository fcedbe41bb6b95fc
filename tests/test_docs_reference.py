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
    assert documented_settings(SPHOptions)["cfl"] == "time-step factors."
    assert shield.model_fields["cfl"].description == "time-step factors."


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
