"""Each default and bound written once (issue 10): the library owns it, the case tables take it.

The debris material (:class:`ParticleMaterial`), the shell cloud (:class:`ShellCloud`,
:func:`shell_cloud_grid`), the hand-off cell size (:func:`bin_to_hydrogrid`), the LS-DYNA
pulse width and end time (:func:`write_lsdyna_deck`) and the seeding's ``legacy_*``
keywords: a bad value is refused by the library and, in a case file, at load time with
the TOML key named; the tables' defaults are the library's.  Also the seeding's
particle-count check (:func:`seed_particles` refuses, before allocating, a count the
machine's memory cannot hold).
"""

from __future__ import annotations

import inspect
import math
import re
import time
import tomllib
import tracemalloc
from pathlib import Path

import numpy as np
import pytest
import tomli_w

from impactdyn import _limits, units
from impactdyn._config import set_dotted, validate
from impactdyn._errors import InputError
from impactdyn.cli import main
from impactdyn.debris import (ArrivalWindow, DebrisCase, OutputSection, ParticleMaterial, SeedOptions, ShellCloud,
                              build, load_debris_case, seed_particles, shell_cloud_grid)
from impactdyn.debris import _seed
from impactdyn.debris._tets import initial_state
from impactdyn.hydrogrid import DC3D_CELL_CM, HydroGrid
from impactdyn.io import write_lsdyna_deck
from impactdyn.shield import bin_to_hydrogrid
from impactdyn.whipple import WhippleCase
from impactdyn.wallgrid import WallGrid

EXAMPLES = Path(__file__).parents[2] / "examples"
DEBRIS = tomllib.loads((EXAMPLES / "debris" / "shell_cloud.toml").read_text())
WHIPPLE = tomllib.loads((EXAMPLES / "whipple" / "table2_7a.toml").read_text())


def _refused(model, data: dict, key: str, value, words: str) -> None:
    with pytest.raises(InputError) as err:
        validate(model, set_dotted(data, key, value), source="case.toml")
    assert str(err.value).startswith("case.toml: ") and words in str(err.value), str(err.value)


@pytest.mark.parametrize("key, value, words", [
    ("material.mu_Mbar", 0.0, "material.mu_Mbar: must be greater than 0"),
    ("material.rho_ref_g_cm3", -2.7, "material.rho_ref_g_cm3: must be greater than 0"),
    ("material.eta_Mbar_us", 0.0, "material.eta_Mbar_us: must be greater than 0"),
    ("material.eta_Mbar_us", math.inf, "material.eta_Mbar_us: must be a finite number"),
    ("material.zeta_Mbar_us", -1.0, "material.zeta_Mbar_us: must be greater than or equal to 0"),
    ("material.lambda_Mbar", -1.0, "material: lambda_Mbar + 2/3 mu_Mbar must be > 0"),
    ("grid.shell.radius_cm", 0.0, "grid.shell.radius_cm: must be greater than 0"),
    ("grid.shell.thickness_cm", 1.5, "grid.shell: thickness_cm = 1.5 exceeds radius_cm = 1.0"),
    ("grid.shell.velocity_km_s", [0.0, 0.0, 0.0], "grid.shell: velocity_km_s = [0.0, 0.0, 0.0]"),
    ("grid.shell.expansion_velocity_km_s", -1.0, "grid.shell.expansion_velocity_km_s: must be greater than or"),
    ("grid.shell.cap_half_angle_deg", 181.0, "grid.shell.cap_half_angle_deg: must be less than or equal to 180"),
    ("grid.shell.density_g_cm3", 0.0, "grid.shell.density_g_cm3: must be greater than 0"),
    ("grid.shell.void_fraction", 1.0, "grid.shell.void_fraction: must be less than 1"),
    ("grid.shell.sound_speed_km_s", -1.0, "grid.shell.sound_speed_km_s: must be greater than or equal to 0"),
    ("grid.shell.cell_size_cm", 0.0, "grid.shell.cell_size_cm: must be greater than 0"),
    ("grid.shell.subsamples", 9, "grid.shell.subsamples: must be less than or equal to 8"),
    ("output.pulse_width_us", 0.0, "output.pulse_width_us: must be greater than 0"),
    ("output.end_time_us", -1.0, "output.end_time_us: must be greater than 0"),
])
def test_debris_case_names_the_key_of_a_library_bound(key, value, words):
    _refused(DebrisCase, DEBRIS, key, value, words)


@pytest.mark.parametrize("key, value, words", [
    ("debris.mu_Mbar", -0.1, "debris.mu_Mbar: must be greater than 0"),
    ("debris.eta_Mbar_us", 0.0, "debris.eta_Mbar_us: must be greater than 0"),
    ("debris.zeta_Mbar_us", -1.0, "debris.zeta_Mbar_us: must be greater than or equal to 0"),
    ("debris.lambda_Mbar", -1.0, "debris.lambda_Mbar + 2/3 debris.mu_Mbar must be > 0"),
    ("binning.cell_size_cm", 0.0, "binning.cell_size_cm: must be greater than 0"),
    ("output.pulse_width_us", -0.05, "output.pulse_width_us: must be greater than 0"),
])
def test_whipple_case_names_the_key_of_a_library_bound(key, value, words):
    data = set_dotted(WHIPPLE, "debris.mu_Mbar", 0.27) if key == "debris.lambda_Mbar" else WHIPPLE
    _refused(WhippleCase, data, key, value, words)


def test_bad_bound_through_the_cli_exits_2_before_any_stage(tmp_path, capsys):
    case = tmp_path / "case.toml"
    case.write_text((EXAMPLES / "debris" / "shell_cloud.toml").read_text().replace(
        "eta_Mbar_us = 0.01", "eta_Mbar_us = 0.0"))
    assert main(["debris", "run", str(case), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert f"{case}: material.eta_Mbar_us: must be greater than 0" in err and "Traceback" not in err
    assert not (tmp_path / "out").exists()


def test_the_tables_defaults_are_the_librarys():
    shell = type(validate(DebrisCase, DEBRIS).grid.shell).model_fields
    cloud = ShellCloud.model_fields
    for key, name in [("cap_half_angle_deg", "cap_half_angle_deg"), ("density_g_cm3", "density"),
                      ("void_fraction", "void_fraction"), ("time_us", "time")]:
        assert shell[key].default == cloud[name].default
    assert shell["sound_speed_km_s"].default == units.cm_us_to_km_s(cloud["sound_speed"].default)
    grid_defaults = inspect.signature(shell_cloud_grid).parameters
    assert shell["cell_size_cm"].default == grid_defaults["cell_size"].default == DC3D_CELL_CM
    assert shell["subsamples"].default == grid_defaults["subsamples"].default
    assert WhippleCase.model_fields["binning"].default.cell_size_cm == DC3D_CELL_CM
    assert inspect.signature(bin_to_hydrogrid).parameters["cell_size_cm"].default == DC3D_CELL_CM
    deck = inspect.signature(write_lsdyna_deck).parameters
    assert OutputSection().pulse_width_us == deck["pulse_width"].default
    assert DebrisCase.model_fields["material"].annotation.model_fields["zeta_Mbar_us"].default == \
        ParticleMaterial.model_fields["zeta"].default
    seeding = inspect.signature(initial_state).parameters
    assert SeedOptions().legacy_fdot_scaling is seeding["legacy_fdot_scaling"].default
    assert SeedOptions().legacy_inertia_transform is seeding["legacy_inertia_transform"].default
    assert ArrivalWindow().legacy_abs_arrival is inspect.signature(
        _seed.arrival_times).parameters["legacy_abs_arrival"].default


def test_the_library_refuses_the_same_values():
    good = dict(mu=0.276, lam=0.56, rho_ref=2.703)
    with pytest.raises(InputError, match="ParticleMaterial: rho_ref: must be greater than 0"):
        ParticleMaterial(**good | {"rho_ref": 0.0})
    with pytest.raises(InputError, match=r"ParticleMaterial: lam \+ 2/3 mu must be > 0"):
        ParticleMaterial(**good | {"lam": -1.0})
    assert ParticleMaterial(**good).eta == math.inf  # no plastic flow: the library takes inf
    cloud = dict(centre=(0.0, -3.0, 0.0), velocity=(0.0, 0.65, 0.0), expansion_velocity=0.2, radius=1.0,
                 thickness=0.2)
    with pytest.raises(InputError, match="ShellCloud: thickness = 1.2 exceeds radius = 1.0"):
        ShellCloud(**cloud | {"thickness": 1.2})
    with pytest.raises(InputError, match="ShellCloud: velocity = .*the cloud must move"):
        ShellCloud(**cloud | {"velocity": [0.0, 0.0, 0.0]})
    with pytest.raises(InputError, match="shell_cloud_grid: cell_size = 0.0: must be greater than 0"):
        shell_cloud_grid(ShellCloud(**cloud), 0.0)
    with pytest.raises(InputError, match="shell_cloud_grid: subsamples = 0: must be greater than or equal to 1"):
        shell_cloud_grid(ShellCloud(**cloud), 0.5, subsamples=0)
    with pytest.raises(InputError, match="bin_to_hydrogrid: cell_size_cm = nan: must be a finite number"):
        bin_to_hydrogrid(None, math.nan)
    wall = WallGrid.uniform((0.0, 1.0), (0.0, 0.3), (0.0, 1.0), (3, 2, 3))
    with pytest.raises(InputError, match="write_lsdyna_deck: pulse_width = -1.0: must be greater than 0"):
        write_lsdyna_deck("never-written.k", wall, pulse_width=-1.0)


def _grid(n: int) -> HydroGrid:
    nodes = [np.linspace(0.0, 0.1 * n, n + 1)] * 3
    ones = np.ones((n, n, n))
    return HydroGrid(*nodes, density=2.7 * ones, void_fraction=0.0 * ones, mass=2.7e-3 * ones,
                     pressure=0.0 * ones, temperature=300.0 * ones, specific_energy=0.0 * ones,
                     sound_speed=0.5 * ones, velocity=np.zeros((n, n, n, 3)), staggered=False)


def test_seeding_refuses_more_particles_than_memory_before_allocating(monkeypatch):
    """On a 1-MiB machine the 8000 cells' 40 000 particles (23 MB) are refused before any is made."""
    grid, material = _grid(20), ParticleMaterial(mu=0.276, lam=0.56, rho_ref=2.7)
    monkeypatch.setattr(_limits, "physical_memory", lambda: 2**20)

    def never(*args, **kwargs):
        raise AssertionError("particles were allocated")

    monkeypatch.setattr(_seed, "initial_state", never)
    tracemalloc.start()
    start = time.perf_counter()
    try:
        with pytest.raises(InputError) as err:
            seed_particles(grid, material)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert time.perf_counter() - start < 1.0 and peak < 2**20
    assert str(err.value).startswith(
        "hand-off grid: 8000 of its 20x20x20 cells pass the seed filters, 5 particles each: 4e+04 debris "
        "particles need at least 22.28 MiB, more than this machine's 1 MiB of memory"), str(err.value)


def test_seeding_count_through_the_cli_exits_2_and_writes_nothing(tmp_path, monkeypatch, capsys):
    case = tmp_path / "case.toml"
    case.write_text((EXAMPLES / "debris" / "shell_cloud.toml").read_text().replace(
        "cell_size_cm = 0.1", "cell_size_cm = 0.25"))
    monkeypatch.setattr(_seed, "PARTICLE_BYTES", 2**60)  # every particle as large as a machine
    assert main(["debris", "run", str(case), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert f"{case}: grid.shell.cell_size_cm = 0.25 for the 1 cm shell" in err
    assert "pass the seed filters, 5 particles each" in err and "debris particles need at least" in err
    assert "Traceback" not in err and not (tmp_path / "out").exists()


def test_a_case_that_seeds_more_particles_than_memory_names_its_key_before_seeding(tmp_path, monkeypatch):
    """The shell at 0.03-cm cells: its grid (12 MiB) passes the cell check, but the 34 128 cells with debris
    make 170 640 particles (95 MiB): refused on a 64-MiB machine, naming the cell size, before any particle
    is made."""
    case = tmp_path / "case.toml"
    case.write_text((EXAMPLES / "debris" / "shell_cloud.toml").read_text().replace(
        "cell_size_cm = 0.1", "cell_size_cm = 0.03"))
    monkeypatch.setattr(_limits, "physical_memory", lambda: 64 * 2**20)

    def never(*args, **kwargs):
        raise AssertionError("particles were seeded")

    monkeypatch.setattr(_seed, "initial_state", never)
    start = time.perf_counter()
    with pytest.raises(InputError) as err:
        build(load_debris_case(case), str(case))
    assert time.perf_counter() - start < 10.0
    message = str(err.value)
    assert message.startswith(f"{case}: grid.shell.cell_size_cm = 0.03 for the 1 cm shell, seed filters of "
                              "[filter]: the hand-off grid: "), message
    assert message.endswith("34128 of its 34x67x67 cells pass the seed filters, 5 particles each: 1.706e+05 debris "
                            "particles need at least 95.04 MiB, more than this machine's 64 MiB of memory"), message
    monkeypatch.setattr(_limits, "physical_memory", lambda: 256 * 2**20)  # where they fit, the case builds
    assert build(load_debris_case(case), str(case))["grid"].shape == (34, 67, 67)


def test_a_wall_inside_the_cloud_is_refused_with_its_key(tmp_path):
    data = set_dotted(DEBRIS, "wall.y_cm", [-8.0, -7.7])  # the shell reaches y = -7.5 cm
    case = tmp_path / "case.toml"
    case.write_text(tomli_w.dumps(data))
    with pytest.raises(InputError, match=rf"^{re.escape(str(case))}: wall.y_cm\[0\] = -8: the wall's front face lies "
                                         r"behind or inside the debris of grid.shell \(centre_cm = \[0.0, -8.5, 0.0\], "
                                         r"radius_cm = 1\), which reaches y = -7.5 cm"):
        build(load_debris_case(case), str(case))


@pytest.mark.parametrize("key, value, words", [
    ("debris.lambda_Mbar", -0.6, "debris.lambda_Mbar + 2/3 debris.mu_Mbar (default: from projectile.material = "
                                 "'al6061-t6') must be > 0"),
    ("debris.mu_Mbar", 1e4, "(debris.lambda_Mbar (default: from projectile.material = 'al6061-t6') + 2 "
                            "debris.mu_Mbar) / the density of projectile.material = 'al6061-t6' gives a "
                            "longitudinal wave speed of"),
    ("wall.material", "al7075-t6", "wall.material = 'al7075-t6' with wall_solver.material_model = 'johnson_cook': "
                                   "johnson_cook: material 'al7075-t6' has no Johnson-Cook constants"),
])
def test_whipple_rules_with_the_projectiles_defaults_name_the_keys(key, value, words):
    """What the stages would derive from the case (the debris material with μ and λ from the projectile, the
    wall model) is checked when it loads."""
    _refused(WhippleCase, WHIPPLE, key, value, words)
