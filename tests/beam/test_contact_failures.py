"""A contact the solver cannot follow ends the run with one SimulationError naming the ``[contact]`` keys that
drive it, over the whole declared range of every contact key of every registered law; never another exception."""

import typing

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from impactdyn import SimulationError
from impactdyn.beam import CONTACT_LAWS, simulate

from .conftest import contact_section

STRIKE = {"torque": {"amplitude_N_m": 0.0}, "initial": {"theta_rad": 0.002, "theta_dot_rad_s": -8.0},
          "time": {"end_s": 5e-3, "output_step_s": 1e-4}, "solver": {"max_steps": 100_000}}
"""The IMPACTB beam struck at 4.1 m/s (the sample's 4.0 m/s) 2.5e-4 s after the start, then its contact (4e-5 s
with the sample's law) and the rebounds until 5e-3 s (eight contacts with the sample's law and with IMPACTC's):
the contact keys alone decide the outcome.  The step budget ends, naming the contact's keys, a contact the
steps crawl through (while a dashpot of 1e11 s/m holds the stop point they shrink to 3e-11 s), so that no
example takes more than a second."""

INT64_MAX = 2**63 - 1
"""The largest integer a TOML file holds."""


def declared_values(annotation: typing.Any, metadata: list) -> st.SearchStrategy:
    """Every value a contact key's type and bounds admit: its choices, or the integers or normal floats
    (a nonzero subnormal is refused) between its bounds."""
    if typing.get_origin(annotation) is typing.Literal:
        return st.sampled_from(typing.get_args(annotation))
    bounds = {kind: getattr(m, kind) for m in metadata for kind in ("gt", "ge", "lt", "le") if hasattr(m, kind)}
    if annotation is int:
        return st.integers(bounds.get("ge", bounds.get("gt", -INT64_MAX - 2) + 1),
                           bounds.get("le", bounds.get("lt", INT64_MAX + 1) - 1))
    assert annotation is float, f"no strategy for a contact key of type {annotation}"
    return st.floats(min_value=bounds.get("gt", bounds.get("ge")), max_value=bounds.get("lt", bounds.get("le")),
                     exclude_min="gt" in bounds, exclude_max="lt" in bounds, allow_nan=False, allow_infinity=False,
                     allow_subnormal=False)


def contact_tables(law: str) -> st.SearchStrategy:
    """``[contact]`` tables of ``law`` with every key drawn from its declared range."""
    fields = contact_section(law).model_fields
    return st.fixed_dictionaries({"model": st.just(law)} | {
        key: declared_values(info.annotation, info.metadata) for key, info in fields.items() if key != "model"})


@pytest.mark.parametrize("law", sorted(CONTACT_LAWS))
def test_every_declared_contact_value_runs_or_fails_naming_its_key(make_case, law):
    keys = [key for key in contact_section(law).model_fields if key != "model"]

    @settings(max_examples=25, deadline=None, derandomize=True)
    @given(table=contact_tables(law))
    def runs_or_names_a_key(table):
        case = make_case("impactb_sample.toml", contact=table, **STRIKE)
        try:
            simulate(case)
        except SimulationError as err:
            assert any(f"contact.{key} = " in str(err) for key in keys), err

    runs_or_names_a_key()


@pytest.mark.parametrize("damping, named", [(1e11, "contact.damping_s_m = 1e+11: "),
                                            (1e15, "contact.damping_s_m = 1e+15, contact.stiffness_N_m1_5")])
def test_a_dashpot_too_stiff_to_follow_names_the_damping(make_case, damping, named):
    """1e11 s/m: the dashpot stops the stop point within 1e-11 s and would let it go only at 5e-17 m/s, below
    the round-off of the gap rate (2e-14 m/s); 1e15 s/m: it stops it within 1e-13 s, faster than the steps
    can follow."""
    table = {"model": "hertz", "stiffness_N_m1_5": 3.2e9, "damping_s_m": damping}
    with pytest.raises(SimulationError, match="the contact phase cannot go on") as err:
        simulate(make_case("impactb_sample.toml", contact=table, **STRIKE))
    assert str(err.value).startswith(named), err.value


def test_a_step_budget_spent_in_a_contact_names_its_keys(make_case):
    """The sample's contact law with a budget of 100 steps, spent 5e-6 s into the first contact."""
    case = make_case("impactb_sample.toml", **STRIKE | {"solver": {"max_steps": 100}})
    with pytest.raises(SimulationError, match="more than solver.max_steps = 100 steps") as err:
        simulate(case)
    assert "contact.damping_s_m = 0.006, contact.stiffness_N_m1_5 = 3.2e+09" in str(err.value), err.value


@pytest.mark.parametrize("method, key", [("Radau", "stiffness_N_m1_5"), ("BDF", "stiffness_N_m1_5"),
                                         ("LSODA", "stiffness_N_m1_5"), ("BDF", "damping_s_m"),
                                         ("LSODA", "damping_s_m")])
def test_a_scipy_method_on_a_contact_force_that_overflows_names_the_contact_keys(make_case, method, key):
    """A key at 1e300 makes the contact force overflow: SciPy's steppers then raise ValueError (Radau, BDF:
    the Jacobian holds infinities) or take a step of no length (LSODA); each ends as one SimulationError
    naming the contact's keys, never another exception."""
    table = {"model": "hertz", "stiffness_N_m1_5": 3.2e9, "damping_s_m": 0.006} | {key: 1e300}
    case = make_case("impactb_sample.toml", contact=table, **STRIKE | {"solver": {"method": method}})
    with pytest.raises(SimulationError, match="the contact phase cannot go on") as err:
        simulate(case)
    assert f"contact.{key} = 1e+300" in str(err.value) and f'solver.method = "{method}" failed' in str(err.value)
