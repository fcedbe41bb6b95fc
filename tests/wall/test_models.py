"""The material-model registry, parametrised over its contents, and the Johnson–Cook damage law."""

import math

import numpy as np
import pytest

from impactdyn._errors import InputError
from impactdyn import wall
from impactdyn.constitutive import temperature
from impactdyn.materials import (AL_6061_T6, AL_6061_T6_JC_DAMAGE, AL_6061_T6_MAT13, CU_OFHC, MATERIALS,
                                 JohnsonCookDamage)
from impactdyn.wall._state import DAMAGE, EPS_P, FAILED, IE, P, RATE
from impactdyn.wall._step import step_kernels
from impactdyn.wallgrid import WallDeposition, WallGrid

from .conftest import drive, one_element


def test_registry_holds_both_models():
    assert {"mat13", "johnson_cook"} <= set(wall.MODELS)


def test_a_model_without_its_own_update_kernel_cannot_be_built():
    """The element pass runs the model's own kernel (WallModel.update_kernel, abstract): a model that
    brings none fails when it is built, instead of running another model's update."""
    members = {name: getattr(wall.Mat13Model, name) for name in wall.WallModel.__abstractmethods__}
    del members["update_kernel"]
    bare = type("Bare", (wall.WallModel,), members)
    with pytest.raises(TypeError, match="update_kernel"):
        bare()


def test_each_model_has_its_own_cached_element_pass():
    """step_kernels compiles the element pass and the step loop per update kernel, each cached on
    disk under a name of its own (numba's cache keys a kernel passed as an argument or closed
    over by a dispatcher that is new in every process, and never hits)."""
    names = set()
    for model_name in wall.MODELS:
        kernels = step_kernels(wall.wall_model(model_name, "al6061-t6").update_kernel)
        for kernel in kernels:
            assert type(kernel._cache).__name__ == "FunctionCache"
            assert type(kernel._cache._impl._locator).__name__.startswith("Package")
            names.add(kernel._cache._cache_file._index_name)
    assert len(names) == 2 * len(wall.MODELS)


def test_registered_model(model_name):
    cls = wall.MODELS[model_name]
    model = wall.wall_model(model_name, "al6061-t6")
    assert isinstance(model, cls) and model.name == model_name
    assert model.density == pytest.approx(2.703)
    prm, table = model.kernel_params(), model.kernel_table()
    assert prm.ndim == 1 and np.all(np.isfinite(prm)) and table.ndim == 2
    described = model.describe()
    assert described["model"] == model_name and described["density_g_cm3"] == pytest.approx(2.703)
    if model_name == "mat13":
        assert model.card is AL_6061_T6_MAT13
        assert described["yield_stress_Mbar"] == AL_6061_T6_MAT13.yield_stress
        assert model.wave_speed() == pytest.approx(0.634, abs=1e-3)       # docs/theory/wall-solver.md: c_L = 0.634 cm/µs
        assert not model.erodes
    else:
        assert model.damage is AL_6061_T6_JC_DAMAGE and not model.erodes      # failed: kept, compressive p
        assert described["damage"]["D1"] == -0.77 and "UCRL-JC-134118" in described["damage"]["source"]
        assert described["damage"]["failure_strain_floor"] == AL_6061_T6_JC_DAMAGE.efmin
        assert described["spall_law"] == "tuler_butcher" and described["spall_strength_Mbar"] is None
        assert described["tuler_butcher"]["sigma0_Mbar"] == AL_6061_T6.spall_strength
    # a short run of the solver with the model, by name
    grid = WallGrid.uniform((0.0, 0.4), (0.0, 0.3), (-0.2, 0.2), (5, 4, 5))
    dep = WallDeposition(element=np.array([0, 1, 4, 5]), time=np.zeros(4), impulse=np.array([[0.0, 2e-5, 0.0]] * 4))
    res = wall.run_wall(grid, dep, "al6061-t6", wall.WallOptions(material_model=model_name, end_time_us=2.0))
    assert res.verdict in wall.VERDICTS
    assert res.model["model"] == model_name
    assert abs(res.measures["energy"]["balance_error"]) < 1e-10


def test_unknown_and_duplicate_models():
    with pytest.raises(InputError, match="material_model"):
        wall.wall_model("mat999")
    with pytest.raises(ValueError):
        wall.register_model(wall.Mat13Model)
    with pytest.raises(InputError, match="Johnson-Cook"):
        wall.wall_model("johnson_cook", "al7075-t6")           # no JC constants in the library
    assert wall.wall_model("johnson_cook", "cu-ofhc").damage is CU_OFHC.johnson_cook_damage


def test_failure_criteria_say_what_can_fail_the_wall():
    jc = wall.wall_model("johnson_cook", "al2024-t4")
    assert jc.failure_criteria() == ("ductile_damage", "ductile_damage_at_floor", "spall_damage")
    assert jc.describe()["failure_criteria"] == list(jc.failure_criteria())
    assert wall.wall_model("johnson_cook", "al6061-t6", damage=None).failure_criteria() == ("spall_damage",)
    assert wall.wall_model("johnson_cook", "al6061-t6", damage=None,
                           spall_law="cutoff").failure_criteria() == ("tensile_pressure",)
    assert wall.wall_model("johnson_cook", "al6061-t6", damage=None, spall=False).failure_criteria() == ()
    # the report's card: ε_f 1.5, and its p_cut −1.2e34 Mbar means no pressure cutoff
    assert wall.wall_model("mat13", "al6061-t6").failure_criteria() == ("plastic_strain",)
    assert wall.wall_model("mat13", "al2024-t4").failure_criteria() == ("plastic_strain", "tensile_pressure")


@pytest.mark.parametrize("material", sorted(n for n, m in MATERIALS.items() if m.johnson_cook_damage))
def test_jc_damage_in_shear_follows_the_formula(material):
    # simple shear: σ* = −p/σ_eq stays near 0 (only the Grüneisen pressure of the plastic heating),
    # so D ≈ εₚ/(D1 + D2) up to the rate and heating factors; the test integrates
    # D = Σ Δεₚ/ε_f(σ*, ε̇*, T*) from the element's own states, for every material with damage data
    model = wall.wall_model("johnson_cook", material, erosion=False, spall=False)
    s = one_element(model)
    table = model.kernel_table()
    d, jc = model.material.johnson_cook_damage, model.material.johnson_cook
    rows = []

    def record(s):
        S = s.S[0]
        seq = math.sqrt(1.5 * (S[0] ** 2 + S[1] ** 2 + S[2] ** 2) + 3.0 * (S[3] ** 2 + S[4] ** 2 + S[5] ** 2))
        rho = s.mesh.element_mass[0] / s.es[0, 7]
        t_star = (temperature(rho, s.es[0, IE], table, 0) - jc.t_room) / (jc.t_melt - jc.t_room)
        rows.append((s.es[0, EPS_P], s.es[0, P], seq, min(max(t_star, 0.0), 1.0), s.es[0, RATE]))
        return False

    drive(s, [[0.0, 0.02, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]], steps=600, stop=record)
    eps_p, p, seq, t_star, rate = np.array(rows).T
    assert eps_p[-1] > 0.02
    assert np.abs(p / seq)[eps_p > 0.0].max() < 0.1                         # |σ*| small while it flows
    rate_factor = 1.0 + d.D4 * np.log(np.maximum(rate / jc.reference_strain_rate, 1.0))
    eps_f = (d.D1 + d.D2 * np.exp(d.D3 * -p / np.maximum(seq, 1e-30))) * rate_factor * (1.0 + d.D5 * t_star)
    expected = np.sum(np.diff(eps_p, prepend=0.0) / eps_f)
    assert s.es[0, DAMAGE] == pytest.approx(expected, rel=1e-3)
    assert s.es[0, DAMAGE] == pytest.approx(eps_p[-1] / ((d.D1 + d.D2) * rate_factor[-1]), rel=0.1)


@pytest.mark.parametrize("with_damage", [True, False, "not at the floor"])
def test_unbounded_fit_and_cutoff_reproduce_the_old_failure(with_damage):
    # the options "unbounded" and "cutoff" are the model before the floor and the Tuler–Butcher law:
    # uniaxial strain in tension: σ* = −p/σ_eq passes 1.35 as the element yields, where the 6061-T6
    # fit gives ε_f ≤ 0: JC damage fails it at once, near −0.45 GPa; without damage, or without its
    # increments at the floor, the spall cut-off fails it at p = −1.2 GPa
    kwargs = {True: {}, False: {"damage": None}, "not at the floor": {"damage_at_floor": False}}[with_damage]
    model = wall.wall_model("johnson_cook", "al6061-t6", erosion=False, fracture_strain_floor="unbounded",
                            spall_law="cutoff", **kwargs)
    s = one_element(model)
    pmin = [0.0]

    def failed(s):
        pmin[0] = min(pmin[0], s.es[0, P])
        return bool(s.failed[0])

    drive(s, [[0.0, 0.0, 0.0], [0.0, 0.05, 0.0], [0.0, 0.0, 0.0]], steps=400, dt=0.001, stop=failed)
    assert s.failed[0]
    p_spall = AL_6061_T6.spall_strength
    cause = wall.FAILURE_CAUSES[s.flags[0, FAILED] - 1]
    if with_damage is True:
        assert -0.6 * p_spall < pmin[0] < -0.25 * p_spall
        assert s.es[0, DAMAGE] >= 1.0 and s.es[0, EPS_P] < 1e-3
        assert cause == "ductile_damage_at_floor"
    else:
        assert pmin[0] == pytest.approx(-p_spall, rel=0.05)
        assert s.es[0, DAMAGE] < 1.0
        assert cause == "tensile_pressure"
    assert math.isfinite(s.es[0, P]) and s.es[0, P] >= 0.0          # failed: no tension left


#: The failure cause each wall model records when simple shear breaks an element.
SHEAR_CAUSE = {"johnson_cook": "ductile_damage", "mat13": "plastic_strain"}


def test_shear_to_failure_records_its_criterion(model_name):
    if model_name not in SHEAR_CAUSE:
        pytest.fail(f"wall model {model_name!r}: state the cause it records in shear (SHEAR_CAUSE)")
    cause = SHEAR_CAUSE[model_name]
    # simple shear: Johnson–Cook damage with a constant fracture strain of 0.1 (D1 alone: the fit far
    # above its floor) fails at εₚ = 0.1; the type-13 card fails at its plastic strain 1.5
    if model_name == "johnson_cook":
        model = wall.wall_model(model_name, "al6061-t6", erosion=False, spall=False,
                                damage=JohnsonCookDamage(D1=0.1, D2=0.0, D3=0.0, D4=0.0, D5=0.0))
        limit = 0.1
    else:
        model, limit = wall.wall_model(model_name, "al6061-t6"), AL_6061_T6_MAT13.failure_strain
    s = one_element(model)
    drive(s, [[0.0, 0.4, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]], steps=3000, dt=0.005,
          stop=lambda s: bool(s.failed[0]))
    assert s.failed[0]
    assert wall.FAILURE_CAUSES[s.flags[0, FAILED] - 1] == cause
    assert s.es[0, EPS_P] == pytest.approx(limit, rel=0.02)


def test_failed_mass_by_cause_sums_the_failed_elements():
    grid = WallGrid.uniform((0.0, 0.3), (0.0, 0.1), (0.0, 0.2), (4, 2, 3))
    mesh = wall.build_mesh(grid, 2.7)
    code = np.zeros(mesh.n_elements, dtype=np.uint8)
    code[[0, 4]] = 1 + wall.FAILURE_CAUSES.index("tensile_pressure")
    code[2] = 1 + wall.FAILURE_CAUSES.index("ductile_damage_at_floor")
    by = wall.failed_mass_by_cause(mesh, code)
    assert list(by) == list(wall.FAILURE_CAUSES)
    m = mesh.element_mass
    assert by["tensile_pressure"] == pytest.approx(m[0] + m[4])
    assert by["ductile_damage_at_floor"] == pytest.approx(m[2])
    assert by["ductile_damage"] == 0.0 and by["plastic_strain"] == 0.0
