import tomllib
from pathlib import Path

import pytest

from impactdyn._config import validate
from impactdyn.beam import BeamCase, load_case, simulate

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "beam"


def case_from(name: str, **tables) -> BeamCase:
    """An example case with some tables updated (``contact`` is replaced whole)."""
    raw = tomllib.loads((EXAMPLES / name).read_text())
    for table, values in tables.items():
        raw[table] = values if table == "contact" else {**raw.get(table, {}), **values}
    return validate(BeamCase, raw)


@pytest.fixture(scope="session")
def make_case():
    return case_from


@pytest.fixture(scope="session")
def impactb_result():
    return simulate(load_case(EXAMPLES / "impactb_sample.toml"))


@pytest.fixture(scope="session")
def impactc_result():
    return simulate(load_case(EXAMPLES / "impactc_sample.toml"))
