import tomllib
import typing
from pathlib import Path

import pytest

from impactdyn._config import validate
from impactdyn.beam import CONTACT_LAWS, BeamCase, load_case, simulate

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "beam"


def case_from(name: str, **tables) -> BeamCase:
    """An example case with some tables updated (``contact`` is replaced whole)."""
    raw = tomllib.loads((EXAMPLES / name).read_text())
    for table, values in tables.items():
        raw[table] = values if table == "contact" else {**raw.get(table, {}), **values}
    return validate(BeamCase, raw)


def contact_section(law: str) -> type:
    """The ``[contact]`` table's section that accepts ``model = law`` (one per registered law)."""
    union = BeamCase.model_fields["contact"].annotation
    if typing.get_origin(union) is typing.Annotated:
        union = typing.get_args(union)[0]
    for section in typing.get_args(union):
        if law in typing.get_args(section.model_fields["model"].annotation):
            return section
    raise AssertionError(f"contact law {law!r} is registered but no [contact] table accepts it")


#: Test values of the required numbers of a ``[contact]`` table, by key.
REQUIRED = {"stiffness_N_m1_5": 3.2e9, "stiffness_N_m_n": 1e9}


def contact_table(law: str, **values) -> dict:
    """A ``[contact]`` table for the registered ``law``: its required keys from :data:`REQUIRED`,
    ``values`` over them and over its defaults."""
    fields = contact_section(law).model_fields
    missing = [k for k, f in fields.items() if f.is_required() and k != "model" and k not in REQUIRED | values]
    assert not missing, f"contact law {law!r}: give test values of {missing} in tests/beam/conftest.py REQUIRED"
    return {"model": law} | {k: v for k, v in REQUIRED.items() if k in fields} | values


@pytest.fixture(scope="session")
def make_case():
    return case_from


@pytest.fixture(scope="session")
def impactb_result():
    return simulate(load_case(EXAMPLES / "impactb_sample.toml"))


@pytest.fixture(scope="session")
def impactc_result():
    return simulate(load_case(EXAMPLES / "impactc_sample.toml"))
