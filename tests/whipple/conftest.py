"""A coarse version of the Table 2 "7a" example, for tests that run the whole pipeline in seconds."""

import tomllib
from pathlib import Path

import pytest
import tomli_w

from impactdyn._config import set_dotted

EXAMPLES = Path(__file__).parents[2] / "examples" / "whipple"
#: The 7a example coarsened to a few hundred SPH particles and a coarse wall, so a run takes seconds.
COARSE = {"shield.spacing_cm": 0.1, "shield.handoff_us": 1.0, "binning.cell_size_cm": 0.1,
          "wall.spacing_cm": 3.0, "wall.x_cm": [0.0, 3.0], "wall.z_cm": [-2.0, 4.0], "wall.nodes": [16, 3, 31],
          "projectile.diameter_cm": 0.45,
          # the report's mesh of the coarse grid: these tests are about the pipeline, whose many shots
          # would take the graded wall's 8 layers of 0.04-cm cores ~20 s each; one run keeps the default
          # (test_whipple_pipeline's ``run``), and tests/wall the mesh itself
          "wall_solver.mesh": "report"}


def coarse_case(tmp_path: Path, name: str = "case.toml", **changes) -> Path:
    data = tomllib.loads((EXAMPLES / "table2_7a.toml").read_text())
    for key, value in (COARSE | {k.replace("__", "."): v for k, v in changes.items()}).items():
        data = set_dotted(data, key, value)
    path = tmp_path / name
    path.write_text(tomli_w.dumps(data))
    return path


@pytest.fixture(scope="session")
def make_case():
    """``make_case(tmp_path, name="case.toml", **changes)`` writes the coarse case (keys as a__b = value)."""
    return coarse_case
