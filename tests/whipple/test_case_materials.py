"""A case's own materials (``[materials.NAME]``): the shipped Ti-6Al-4V example end to end, the errors of
bad material input (one message naming the file and the key, exit 2, nothing written), and the registry."""

import json
import math
import tomllib
from pathlib import Path

import pytest
import tomli_w
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from impactdyn._config import set_dotted
from impactdyn._errors import InputError
from impactdyn.ble import jsc_verdict
from impactdyn.cli import main
from impactdyn.materials import AL_6061_T6, MATERIALS, get_material, register_material
from impactdyn.whipple import load_whipple_case
from impactdyn.whipple._case import ble_shield

from .conftest import COARSE, EXAMPLES

EXAMPLE = EXAMPLES / "ti6al4v_7a.toml"


def _write(tmp_path: Path, data: dict, name: str = "case.toml") -> Path:
    path = tmp_path / name
    path.write_text(tomli_w.dumps(data))
    return path


def _example(**changes) -> dict:
    data = tomllib.loads(EXAMPLE.read_text())
    for key, value in changes.items():
        data = set_dotted(data, key, value)
    return data


def test_every_group_of_the_example_names_its_source():
    tables = _example()["materials"]["ti6al4v"]
    assert tables and all(group["source"].strip() for group in tables.values())


def test_the_example_runs_end_to_end_and_the_equations_take_its_density(tmp_path):
    case = _write(tmp_path, _example(**COARSE))
    out = tmp_path / "run"
    assert main(["whipple", "run", str(case), "-o", str(out)]) == 0
    s = json.loads((out / "summary.json").read_text())
    loaded = load_whipple_case(case)
    ti = get_material("ti6al4v")
    assert ti.rho0 == 4.419 and ti.yield_stress == pytest.approx(0.0133) and ti.johnson_cook_damage.D5 == 3.87
    expected = jsc_verdict(ble_shield(loaded), loaded.projectile.diameter_cm, loaded.projectile.velocity_km_s,
                           loaded.projectile.obliquity_deg, ti.rho0)
    assert s["ble"]["projectile_density_g_cm3"] == 4.419
    assert s["ble"]["critical_diameter_cm"] == expected["critical_diameter_cm"]
    aluminium = jsc_verdict(ble_shield(loaded), loaded.projectile.diameter_cm, loaded.projectile.velocity_km_s,
                            loaded.projectile.obliquity_deg, AL_6061_T6.rho0)
    assert s["ble"]["critical_diameter_cm"] != aluminium["critical_diameter_cm"]
    # the debris particles take its density and moduli; the run folder's case keeps its tables
    assert json.loads((out / "shield" / "stage.json").read_text())["settings"]["materials"]["ti6al4v"]
    assert "ti6al4v" in tomllib.loads((out / "case.toml").read_text())["materials"]
    debris = tomllib.loads((out / "debris" / "config.resolved.toml").read_text())
    assert debris["material"]["rho_ref_g_cm3"] == 4.419 and debris["material"]["mu_Mbar"] == pytest.approx(0.419)


def test_the_equations_take_the_wall_materials_tensile_yield_when_the_case_gives_none(tmp_path):
    """σ_y of the JSC equations: ``wall.yield_stress_ksi`` when given, else the wall material's tensile
    yield (a case's own material, or the library's 6061-T6 at its 40 ksi)."""
    titanium = _example(**{"wall.material": "ti6al4v", "wall_solver.spall_law": "cutoff"})
    del titanium["wall"]["yield_stress_ksi"]
    case = load_whipple_case(_write(tmp_path, titanium))
    assert case.wall_yield_ksi == pytest.approx(880.0 / 6.894757293168361)
    assert ble_shield(case).wall_yield_ksi == case.wall_yield_ksi
    given = load_whipple_case(_write(tmp_path, _example(**{"wall.material": "ti6al4v", "wall_solver.spall_law": "cutoff"}),
                                     "given.toml"))
    assert given.wall_yield_ksi == 40.0
    del titanium["wall"]["material"]
    library = load_whipple_case(_write(tmp_path, titanium, "library.toml"))
    assert library.wall.material == "al6061-t6" and library.wall_yield_ksi == 40.0


def test_the_debris_case_of_a_run_carries_the_materials_its_wall_names(tmp_path):
    """A Whipple run's debris case (its ``config.resolved.toml``) reruns alone in a fresh process: with a
    wall of the case's own alloy, the alloy's table goes with it."""
    from impactdyn._config import dump_toml
    from impactdyn.debris import load_debris_case
    from impactdyn.whipple._case import debris_case

    data = _example(**{"wall.material": "ti6al4v", "wall_solver.spall_law": "cutoff"})
    case = load_whipple_case(_write(tmp_path, data))
    config = tmp_path / "config.resolved.toml"
    config.write_text(dump_toml(debris_case(case, str(tmp_path / "grid.h5"))))
    MATERIALS.unregister("ti6al4v")          # as in a fresh process
    again = load_debris_case(config)
    assert again.wall.material == "ti6al4v" and get_material("ti6al4v").rho0 == 4.419


BAD = [
    ({"materials.ti6al4v.strength": None}, "materials.ti6al4v.strength: missing key"),
    ({"materials.ti6al4v.eos.c0_m_s": 5130.0}, "materials.ti6al4v.eos.c0_m_s: unknown key"),
    ({"materials.ti6al4v.strength.shear_modulus_GPa": -41.9},
     "materials.ti6al4v.strength.shear_modulus_GPa: must be greater than 0"),
    ({"materials.ti6al4v.eos.source": " "}, "materials.ti6al4v.eos.source: must say where"),
    ({"projectile.material": "ti-6al-4v-eli"}, "projectile.material: unknown material 'ti-6al-4v-eli'"),
    ({"bumper.material": "ti64"}, "bumper.material: unknown material 'ti64'"),
    ({"materials.al6061-t6": {"eos": {}, "strength": {}}}, "materials.al6061-t6.eos.density_g_cm3: missing key"),
    ({"materials.ti6al4v.phase.boiling_K": 1000.0}, "materials.ti6al4v.phase: needs solidus_K <= liquidus_K"),
    ({"shield.failure_model": "fragmentation"}, "needs the Weibull flaws"),
    ({"wall.material": "cu-ofhc", "wall.yield_stress_ksi": None},
     "wall.yield_stress_ksi: not given, and the wall's material 'cu-ofhc' has no tensile yield"),
    ({"shield.failure_model": "fragmentation", "shield.failed_fragments": "grady"},
     "no fracture toughness for projectile.material = 'ti6al4v'"),
]


@pytest.mark.parametrize("changes, message", BAD)
def test_bad_material_input_is_one_message_naming_file_and_key_and_writes_nothing(changes, message, tmp_path,
                                                                                   capsys):
    data = _example()
    for key, value in changes.items():
        if value is None:
            head, _, last = key.rpartition(".")
            node = data
            for part in head.split("."):
                node = node[part]
            del node[last]
        else:
            data = set_dotted(data, key, value)
    case = _write(tmp_path, data)
    out = tmp_path / "run"
    assert main(["whipple", "run", str(case), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"error: {case}:") and message in err, err
    assert "Traceback" not in err and "unknown material 'ti6al4v'" not in err     # no echo of a failed table
    assert not out.exists()


def test_a_name_of_the_library_cannot_be_redefined(tmp_path):
    tables = _example()["materials"]
    data = _example(**{"materials": {"AL6061_T6": tables["ti6al4v"]}, "projectile.material": "al6061-t6"})
    with pytest.raises(InputError, match="a library material 'al6061-t6' is registered under this name"):
        load_whipple_case(_write(tmp_path, data))
    assert get_material("al6061-t6") is AL_6061_T6
    with pytest.raises(InputError, match="library material"):
        register_material(get_material("ti6al4v").__class__(**{**get_material("ti6al4v").__dict__,
                                                              "name": "Cu OFHC"}))


#: The numeric keys of the example's material tables (group, key).
NUMBERS = [(group, key) for group, table in _example()["materials"]["ti6al4v"].items()
           for key, value in table.items() if isinstance(value, float)]


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(where=st.sampled_from(NUMBERS),
       value=st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10, 10), st.text(max_size=3),
                       st.booleans(), st.just(5e-324)))
def test_any_value_of_a_material_key_gives_a_material_or_an_error_naming_file_and_key(where, value, tmp_path):
    group, key = where
    case = _write(tmp_path, _example(**{f"materials.ti6al4v.{group}.{key}": value}))
    try:
        loaded = load_whipple_case(case)
    except InputError as err:
        first = str(err).splitlines()[0]
        assert first.startswith(f"{case}: ") and (f"materials.ti6al4v.{group}" in first
                                                    or "projectile.material" in first), first
        return
    m = get_material(loaded.projectile.material)
    assert m.name == "ti6al4v" and all(math.isfinite(v) for v in (m.rho0, m.c0, m.shear_modulus, m.yield_stress))


def test_a_later_case_redefines_its_own_material(tmp_path):
    load_whipple_case(_write(tmp_path, _example(**{"materials.ti6al4v.eos.density_g_cm3": 4.43}), "a.toml"))
    assert MATERIALS["ti6al4v"].rho0 == 4.43
    load_whipple_case(_write(tmp_path, _example(), "b.toml"))
    assert MATERIALS["ti6al4v"].rho0 == 4.419
