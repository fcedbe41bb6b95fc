"""The error contract over every key of every case table: any value, or none, gives a case or an
InputError naming the file and the key.

For each TOML case kind (beam, debris, Whipple) the tests start from the shipped examples
(and variants that reach the tables the examples leave out), walk the case model's fields
recursively (tables, the member of a tagged union the example uses, list elements) and set
one key at a time to any TOML value: integers of any size, floats with NaN and the
infinities, strings, booleans, lists, tables, values near the example's, a valid choice of
a named setting, or no value at all.  The case file is written and loaded as its CLI
command loads it, then put through what the command derives from the case before any
stage's work (:data:`KINDS`).  The outcome must be a case or an :class:`InputError` whose
message begins with the file and names the key (dotted, or its table and its name where a
rule between keys speaks of the table), never another exception.  The fourth kind, the
dc3din of ``debris legacy``, is covered with the legacy readers in
``tests/io/test_reader_properties.py``.

The inputs of ``whipple shot`` and ``whipple validate`` are covered too: a base case (``--from-case``) with
any value of a key, any ``--database`` reference, and selection rule files (``--select``, ``fix-rule``) with
any value of a key, run through the commands in this process (exit 0 or 2, one line, no traceback; the
validation's runs replaced, so nothing is simulated) and through :func:`~impactdyn.whipple.load_rule` and
:func:`~impactdyn.whipple.select_shots`.

The machine is shrunk to :data:`MEMORY`, so that a size a value asks for is refused or
built quickly (the same check, ``_limits.check_fits``, as on any machine).
"""

from __future__ import annotations

import copy
import math
import os
import re
import tomllib
import types
import typing
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal
from unittest import mock

import pytest
import tomli_w
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pydantic import BaseModel
from pydantic.fields import FieldInfo

from impactdyn import _limits
from impactdyn._config import dump_toml, load_case
from impactdyn._errors import InputError
from impactdyn.beam import CONTACT_LAWS, BeamCase
from impactdyn.beam._model import BeamModel
from impactdyn.beam._simulate import contact_law, initial_state, torque_schedule
from impactdyn.debris import INTEGRATORS, DebrisCase, build, load_debris_case, remap_grid, seed_and_select
from impactdyn.debris._case import hand_off_grid
from impactdyn.io import formats, write_grid
from impactdyn.materials import MATERIALS
from impactdyn.shield import BinningMethod
from impactdyn.wall import FAILURE_LAWS, MODELS
from impactdyn.wall._options import HOURGLASS_FORMS, SPREADS
from impactdyn.ble import read_database
from impactdyn.whipple import (SelectionRule, WhippleCase, load_rule, load_whipple_case, rule_hash, select_shots,
                               shield_problem)
from impactdyn.whipple._case import debris_case
from impactdyn.whipple._pipeline import deck_options
from impactdyn.whipple._report import ble_verdict

EXAMPLES = Path(__file__).parent.parent / "examples"

MEMORY = 64 * 2**20
"""Bytes of the machine the cases are checked on: the examples fit, sizes far beyond theirs do not."""

EXAMPLES_PER_KEY = int(os.environ.get("IMPACTDYN_EXAMPLES_PER_KEY", 15))
"""Values tried per key and base case (the environment variable searches longer)."""

GRID_FILE = "handoff_grid.h5"
"""The hand-off grid of the debris variant that reads one, beside its case file."""


def _beam(path: Path) -> None:
    """``beam run``: the case, then what ``simulate`` builds from it before its first step."""
    case = load_case(BeamCase, path)
    model = BeamModel.from_case(case)
    contact_law(case)
    torque_schedule(case)
    assert not model.gap(initial_state(case, model)) < 0, "simulate refuses this case, which validated"


def _debris(path: Path) -> None:
    """``debris run``: the case, its hand-off grid, wall and options, then the seeding."""
    case = load_debris_case(path)
    args = build(case, str(path))
    remap_grid(case)
    seed_and_select(args["grid"], args["wall"], args["material"], args["seed_filter"], args["seed_options"],
                    args["window"])
    dump_toml(case)


def _whipple(path: Path) -> None:
    """``whipple run``: the case and what the stages derive from it alone (the SPH problem, the
    debris case, the decks' options, the ballistic-limit verdict)."""
    case = load_whipple_case(path)
    dump_toml(case)
    shield_problem(case)
    debris_case(case, GRID_FILE)
    deck_options(case)
    ble_verdict(case)


def _example(name: str) -> dict:
    return tomllib.loads((EXAMPLES / name).read_text())


def _replaced(data: dict, table: str, value: Any) -> dict:
    out = copy.deepcopy(data)
    *parents, last = table.split(".")
    node = out
    for p in parents:
        node = node[p]
    node[last] = value
    return out


@dataclass(frozen=True)
class Kind:
    model: type[BaseModel]
    load: Callable[[Path], None]
    bases: dict[str, dict]


IMPACTB, SHELL = _example("beam/impactb_sample.toml"), _example("debris/shell_cloud.toml")

KINDS = {
    "beam": Kind(BeamCase, _beam, {
        "impactb": IMPACTB,
        "impactc": _example("beam/impactc_sample.toml"),
        "hunt_crossley": _replaced(_replaced(IMPACTB, "contact", {
            "model": "hunt_crossley", "stiffness_N_m_n": 3.2e9, "exponent": 1.5, "restitution": 0.8}),
            "initial", {"theta_rad": 3.3, "q_m": [0.0, 0.0, 0.0], "q_dot_m_s": [0.0, 0.0, 0.0]}),
    }),
    "debris": Kind(DebrisCase, _debris, {
        "shell_cloud": SHELL,
        "grid_file_and_remap": _replaced(_replaced(SHELL, "grid", {"file": GRID_FILE, "format": "hdf5"}),
                                         "wall.remap", {"x_cm": [0.0, 4.0], "z_cm": [-2.0, 6.0], "nodes": [11, 21]}),
    }),
    "whipple": Kind(WhippleCase, _whipple, {"table2_7a": _example("whipple/table2_7a.toml")}),
}

#: Valid choices of the settings that name something, by the key's last part: the registries themselves,
#: so that a new plug-in is drawn too.
CHOICES: dict[str, list[str]] = {
    "material": list(MATERIALS), "method": list(INTEGRATORS) + list(typing.get_args(BinningMethod)),
    "material_model": list(MODELS), "spall_law": list(FAILURE_LAWS), "hourglass": list(HOURGLASS_FORMS), "spread": list(SPREADS),
    "format": list(formats()), "model": list(CONTACT_LAWS), "restitution_law": ["listing", "constant"],
}


def _members(annotation: Any) -> list[Any]:
    """The types an annotation admits (Annotated and unions unwrapped)."""
    origin = typing.get_origin(annotation)
    if origin is typing.Annotated:
        return _members(typing.get_args(annotation)[0])
    if origin in (typing.Union, types.UnionType):
        return [m for a in typing.get_args(annotation) for m in _members(a)]
    return [annotation]


def _keys(model: type[BaseModel], data: Any, prefix: str = "") -> Iterator[tuple[str, FieldInfo]]:
    """Every dotted key of ``model`` as filled by ``data``: fields, the fields of its tables that
    ``data`` gives or that have a default, and the elements of the lists ``data`` gives."""
    for name, info in model.model_fields.items():
        key, value = prefix + name, data.get(name) if isinstance(data, dict) else None
        yield key, info
        sections = [m for m in _members(info.annotation) if isinstance(m, type) and issubclass(m, BaseModel)]
        if len(sections) > 1:  # a tagged union: the member the example uses
            sections = [s for s in sections if (value or {}).get("model") in
                        typing.get_args(s.model_fields["model"].annotation)]
        if sections and (isinstance(value, dict) or (value is None and info.default is not None
                                                     and not info.is_required())):
            yield from _keys(sections[0], value or {}, key + ".")
        elif isinstance(value, list):
            for i in range(len(value)):
                yield f"{key}[{i}]", info


DELETE = object()
"""The key left out of the file."""

TEXT = st.text(st.characters(codec="utf-8"), max_size=8)
INTS = st.one_of(st.integers(-10, 10), st.integers(-2**63, 2**63 - 1), st.integers(2**63, 2**80),
                 st.integers(-2**80, -2**63))
FLOATS = st.one_of(st.floats(), st.sampled_from([0.0, -0.0, math.nan, math.inf, -math.inf, 1e308, -1e308, 5e-324]))
SCALARS = st.one_of(INTS, FLOATS, st.booleans(), TEXT)
ANY = st.one_of(st.just(DELETE), SCALARS, st.lists(SCALARS, max_size=4), st.dictionaries(TEXT, SCALARS, max_size=3))
FACTORS = st.sampled_from([-1.0, 0.0, 1e-9, 0.01, 0.1, 0.5, 0.9, 1.1, 2.0, 10.0, 100.0, 1e6, 1e12, 1e300])


def _near(value: Any) -> st.SearchStrategy:
    """Values a user might write instead of ``value``: scaled, negated, one more or less element."""
    if isinstance(value, bool) or value is None:
        return st.booleans() if isinstance(value, bool) else FLOATS
    if isinstance(value, int):
        return st.one_of(st.integers(value - 3, value + 3), FACTORS.map(lambda f: int(value * min(f, 1e15))))
    if isinstance(value, float):
        return st.one_of(FACTORS.map(lambda f: value * f if value else f), st.floats(-10.0, 10.0))
    if isinstance(value, list):
        return st.lists(st.one_of(*(TEXT if isinstance(v, str) else _near(v) for v in value)) if value else FLOATS,
                        min_size=max(0, len(value) - 1), max_size=len(value) + 1)
    return st.nothing()


def _values(key: str, info: FieldInfo, data: dict) -> st.SearchStrategy:
    """Any value, values near the key's own (the example's, else its default) and its valid choices."""
    current = _get(data, key)
    if current is None and not key.endswith("]") and not isinstance(info.default, BaseModel):
        current = info.default
    last = re.sub(r"\[\d+\]$", "", key).rsplit(".", 1)[-1]
    literal = [a for m in _members(info.annotation) if typing.get_origin(m) is Literal for a in typing.get_args(m)]
    named = literal + CHOICES.get(last, [])
    return st.one_of(ANY, _near(current), *([st.sampled_from(named)] if named else []))


def _split(key: str) -> tuple[list[str], int | None]:
    m = re.fullmatch(r"(.*)\[(\d+)\]", key)
    return (m.group(1).split("."), int(m.group(2))) if m else (key.split("."), None)


def _get(data: dict, key: str) -> Any:
    parts, index = _split(key)
    node: Any = data
    for p in parts:
        node = node.get(p) if isinstance(node, dict) else None
    return node[index] if index is not None and isinstance(node, list) and index < len(node) else node


def _set(data: dict, key: str, value: Any) -> dict:
    """A copy of ``data`` with ``key`` set to ``value`` (or left out: :data:`DELETE`)."""
    out = copy.deepcopy(data)
    parts, index = _split(key)
    node = out
    for p in parts[:-1]:
        node = node.setdefault(p, {})
    node, name = (node[parts[-1]], index) if index is not None else (node, parts[-1])
    if value is not DELETE:
        node[name] = value
    elif index is not None:
        del node[name]
    else:
        node.pop(name, None)
    return out


def _names(message: str, key: str) -> bool:
    """The message names ``key``: dotted, or its table and its own name (a rule between keys)."""
    base = re.sub(r"\[\d+\]$", "", key)
    table, _, name = base.rpartition(".")
    return base in message or (name in message and (not table or table in message))


CASES = [(kind, base, key, info) for kind, k in KINDS.items() for base, data in k.bases.items()
         for key, info in _keys(k.model, data)]


@pytest.fixture(scope="module")
def folder(tmp_path_factory) -> Path:
    """A folder for the case files, with the shell example's hand-off grid as a file."""
    path = tmp_path_factory.mktemp("cases")
    with mock.patch.object(_limits, "physical_memory", lambda: MEMORY):
        case = load_debris_case(EXAMPLES / "debris" / "shell_cloud.toml")
        write_grid(path / GRID_FILE, hand_off_grid(case))
    return path


def test_every_key_is_walked():
    """The walk reaches the nested tables, the union member, the optional tables and list elements."""
    keys = {(kind, key) for kind, _, key, _ in CASES}
    for kind, key in [("beam", "contact.stiffness_N_m_n"), ("beam", "contact.max_impacts"),
                      ("beam", "initial.q_m[2]"), ("beam", "solver.max_steps"), ("debris", "grid.shell.time_us"),
                      ("debris", "wall.remap.nodes[1]"), ("debris", "grid.file"), ("debris", "legacy.abs_arrival"),
                      ("whipple", "wall_solver.min_step_fraction"), ("whipple", "wall.nodes[2]")]:
        assert (kind, key) in keys
    assert len(CASES) > 300


@pytest.mark.parametrize("kind, base", [(kind, base) for kind, k in KINDS.items() for base in k.bases])
def test_the_bases_are_valid(folder, kind, base):
    path = folder / f"{kind}-{base}.toml"
    path.write_text(tomli_w.dumps(KINDS[kind].bases[base]))
    with mock.patch.object(_limits, "physical_memory", lambda: MEMORY):
        KINDS[kind].load(path)


@pytest.mark.parametrize("kind, base, key, info", [
    pytest.param(*case, id=f"{case[0]}-{case[1]}-{case[2]}")
    for case in CASES])
def test_any_value_gives_a_case_or_an_error_naming_the_key(folder, kind, base, key, info):
    path = folder / f"{kind}-{base}-{key.replace('[', '_').replace(']', '')}.toml"
    data = KINDS[kind].bases[base]

    @settings(max_examples=EXAMPLES_PER_KEY, deadline=None, derandomize=True)
    @given(value=_values(key, info, data))
    def check(value):
        path.write_text(tomli_w.dumps(_set(data, key, value)))
        try:
            KINDS[kind].load(path)
        except InputError as err:
            message = str(err)
            assert message.startswith(f"{path}: "), message
            assert _names(message, key), message

    with mock.patch.object(_limits, "physical_memory", lambda: MEMORY):
        check()


# --- the inputs of `whipple shot` and `whipple validate`: the base case, the shot, the selection rule ---------

SHOT_LINE = 136
"""A test shot of the packaged database (set-1 takes it): its case is the base case with the shot's shield."""

SHOT_KEYS = [key for key, _ in _keys(WhippleCase, KINDS["whipple"].bases["table2_7a"])]


def _shot_cli(capsys, argv: list[str]) -> tuple[int, str]:
    """``impactdyn ARGV`` in this process: (exit code, stderr); an exception other than the contract's escapes."""
    from impactdyn.cli import main

    code = main(argv)
    return code, capsys.readouterr().err


@pytest.mark.parametrize("key", SHOT_KEYS[::3], ids=str)
def test_a_bad_base_case_of_whipple_shot_exits_2_naming_the_key(folder, capsys, key):
    """``whipple shot --from-case BASE --write-case``: a base case with any value of a key writes the shot's
    case or exits 2 with one line naming the file or the shot and the key (or the key of the rule between keys
    that refuses it, where the shot's own values meet the base's numerics), never a traceback.
    ``whipple validate --from-case`` builds each shot's case the same way."""
    data = KINDS["whipple"].bases["table2_7a"]
    info = dict(_keys(WhippleCase, data))[key]
    base, written = folder / "shot-base.toml", folder / "shot-case.toml"

    @settings(max_examples=4, deadline=None, derandomize=True)
    @given(value=_values(key, info, data))
    def check(value):
        base.write_text(tomli_w.dumps(_set(data, key, value)))
        code, err = _shot_cli(capsys, ["whipple", "shot", "--database", str(SHOT_LINE), "--from-case", str(base),
                                       "--write-case", str(written), "--force"])
        assert code in (0, 2), err
        if code == 2:
            assert "Traceback" not in err and err.count("\n") == 1, err
            # the key, or (a rule between keys: the shot's values against the base's numerics) another key
            assert str(base) in err or "test shot" in err, err
            assert _names(err, key) or any(re.sub(r"\[\d+\]$", "", k) in err for k in SHOT_KEYS), err

    check()


@given(token=st.one_of(TEXT, INTS.map(str), st.sampled_from(["0", "-1", "line:1", "id:", "id:B343", "136", "1e3"])))
@settings(max_examples=25, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.function_scoped_fixture])
def test_any_database_reference_of_whipple_shot_gives_its_case_or_exit_2(tmp_path_factory, capsys, token):
    written = tmp_path_factory.mktemp("shot") / "case.toml"
    code, err = _shot_cli(capsys, ["whipple", "shot", "--database", token, "--write-case", str(written)])
    assert code in (0, 2), err
    assert code == 0 or ("Traceback" not in err and err.count("\n") == 1), err


RULE = tomllib.loads((Path(__file__).parent.parent / "src/impactdyn/whipple/rules/set-2.toml").read_text())
RULES = {"fixed": RULE, "unfixed": {k: v for k, v in RULE.items() if k != "fixed"}}
"""A shipped rule as it is (fixed: only its ``[fixed]`` keys can change without its refusal) and without
``[fixed]`` (every other key)."""

RULE_CASES = [(base, key, info) for base, data in RULES.items()
              for key, info in _keys(SelectionRule, data) if (base == "fixed") == key.startswith("fixed")]
CHOICES["after"] = ["set-1", "set-2", "set-3"]  # rule names a user might write in after = [...]


def test_every_rule_key_is_walked():
    keys = {key for _, key, _ in RULE_CASES}
    assert {"after", "eligible.velocity_km_s[1]", "distance.spacing_cm", "counts.min_oblique", "fixed.sha256"} <= keys


@pytest.mark.parametrize("base, key, info", [pytest.param(*c, id=f"{c[0]}-{c[1]}") for c in RULE_CASES])
def test_any_value_of_a_rule_key_gives_a_rule_or_an_error_naming_it(folder, base, key, info):
    """A selection rule file (``whipple validate --select``, ``fix-rule``) with any value of a key: a rule
    whose shots ``select_shots`` picks, or an InputError that begins with the file and names the key."""
    path = folder / f"rule-{base}-{key.replace('[', '_').replace(']', '')}.toml"
    data = RULES[base]
    db = read_database()

    @settings(max_examples=6, deadline=None, derandomize=True)
    @given(value=_values(key, info, data))
    def check(value):
        path.write_text(tomli_w.dumps(_set(data, key, value)))
        try:
            rule = load_rule(path)
            select_shots(rule, db)
            rule_hash(rule)
        except InputError as err:
            message = str(err)
            assert message.startswith(f"{path}: "), message
            assert _names(message, key), message

    check()


@given(data=st.data())
@settings(max_examples=15, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.function_scoped_fixture])
def test_a_bad_rule_file_exits_2_from_validate_and_fix_rule(tmp_path_factory, capsys, data):
    """The commands that read a rule: exit 0 or 2 with one message naming the key, no traceback; nothing
    is simulated (the validation's runs are replaced)."""
    base, key, info = data.draw(st.sampled_from([c for c in RULE_CASES if c[0] == "unfixed"]))
    value = data.draw(_values(key, info, RULES[base]))
    folder = tmp_path_factory.mktemp("rule")
    path = folder / "rule.toml"
    path.write_text(tomli_w.dumps(_set(RULES[base], key, value)))
    accuracy = {"count": 0, "of": 0, "low": 0.0, "high": 1.0}
    scores = {who: {"overall": {"accuracy": accuracy}} for who in ("simulated", "jsc")}
    with mock.patch("impactdyn.whipple.run_validation", return_value=scores):
        for argv in (["whipple", "validate", "--select", str(path), "-o", str(folder / "out")],
                     ["whipple", "fix-rule", str(path)]):
            code, err = _shot_cli(capsys, argv)
            assert code in (0, 2), err
            if code == 2:
                assert "Traceback" not in err and err.count("\n") == 1, err
                assert _names(err, key), err


def test_an_unknown_rule_in_after_is_named_with_the_file_and_the_key(tmp_path):
    path = tmp_path / "rule.toml"
    path.write_text(tomli_w.dumps(_set(RULES["unfixed"], "after", ["no-such-rule"])))
    with pytest.raises(InputError) as err:
        select_shots(load_rule(path), read_database())
    assert str(err.value).startswith(f"{path}: after"), str(err.value)


def test_a_rule_after_itself_is_an_input_error(tmp_path):
    path = tmp_path / "rule.toml"
    path.write_text(tomli_w.dumps(_set(RULES["unfixed"], "after", [str(path)])))
    with pytest.raises(InputError, match="after"):
        select_shots(load_rule(path), read_database())
