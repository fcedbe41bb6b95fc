"""TOML case files -> validated pydantic models.

Every case model derives from :class:`Section`: unknown keys are errors, NaN and
infinities are rejected, numbers are not silently converted from strings. A
failure becomes one :class:`~impactdyn._errors.InputError` naming the file and the
dotted key, e.g. ``case.toml: beam.EI_N_m2: must be > 0``.

A section is the one home of its settings' defaults and bounds.  The solvers take
their options as sections too (``shield.SPHOptions``, ``debris.IntegratorOptions``):
built in Python, a section takes keywords (or positional values in field order, as
the dataclasses they replaced did) and a bad value raises the same
:class:`~impactdyn._errors.InputError`, named by the class: ``SPHOptions: cfl: must
be less than or equal to 1``.  Where a case table spells a setting differently from
the option it feeds, :func:`field_of` declares it with the option's default and
bounds.  The validators the debris and Whipple cases share are here
(:data:`Range`, :data:`NodeCount`, :func:`check_ranges`).

Each default and bound is written once, where the library takes the value: a
field of a :class:`Section` (``debris.ParticleMaterial``, ``debris.ShellCloud``), or
an annotated keyword of a function decorated with :func:`checked`
(``pulse_width: Positive = 0.05``).  A case table declares the setting with
:func:`field_of`, which carries the default and the bounds along (the TOML key is
named in the error); a rule between several values is a public check function of
the library that its validator and the case's both call
(``debris.check_bulk_modulus``).
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
import json
import math
import re
import sys
import tomllib
import typing
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Annotated, Any, TypeVar

import tomli_w
from pydantic import (AfterValidator, BaseModel, ConfigDict, Field, TypeAdapter, ValidationError, create_model,
                      model_validator)
from pydantic.fields import FieldInfo

from impactdyn._errors import InputError, reading

M = TypeVar("M", bound=BaseModel)


def _normal(value: float) -> float:
    """A non-zero value below the smallest normal float (2.2e-308) has lost its precision and divides
    or powers to 0 or inf in the models' arithmetic (a yield stress of 5e-324 ksi made the JSC
    equations' bisection overflow): refused, as nothing in a case is that small."""
    if isinstance(value, float) and value != 0.0 and abs(value) < sys.float_info.min:
        raise ValueError(f"{value!r} is below the smallest normal float, {sys.float_info.min:.3g}")
    return value


Positive = Annotated[float, Field(gt=0), AfterValidator(_normal)]
NonNegative = Annotated[float, Field(ge=0), AfterValidator(_normal)]
# TOML arrays are lists; strict validation does not turn them into tuples.
Range = Annotated[list[float], Field(min_length=2, max_length=2)]
"""[lower, upper] of a coordinate, cm (the upper bound checked by :func:`check_ranges`)."""
NodeCount = Annotated[int, Field(ge=2)]
"""Nodes along one axis of a grid."""


class _Built(type(BaseModel)):
    """Metaclass of :class:`Section`: construction in Python (not from a case file) raises InputError."""

    def __call__(cls, *args: Any, **data: Any) -> Any:
        if args:
            names = list(cls.model_fields)
            if len(args) > len(names):
                raise TypeError(f"{cls.__name__} takes at most {len(names)} positional values, got {len(args)}")
            for name, value in zip(names, args):
                if name in data:
                    raise TypeError(f"{cls.__name__}: {name} given twice")
                data[name] = value
        try:
            return super().__call__(**data)
        except ValidationError as err:
            raise InputError(_format_error(cls.__name__, err, data)) from None


class Section(BaseModel, metaclass=_Built):
    """Base of every config table and solver option set: strict keys, finite numbers, frozen."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False, frozen=True, strict=True,
                              use_attribute_docstrings=True)

    def replaced(self, **changes: Any) -> Any:
        """A copy with ``changes``, validated as a new section (``model_copy`` would not check them)."""
        return type(self)(**{**self.model_dump(), **changes})


_NO_DEFAULT: Any = object()


def field_of(source: Any, name: str, default: Any = _NO_DEFAULT) -> Any:
    """The setting ``name`` of ``source``, to declare it again under another name or in another table.

    ``source`` is a :class:`Section` (the field's default, bounds and description
    come along; the description written under the field or in the class docstring,
    :func:`documented_settings`), a function (its keyword's default, and the bounds of its
    annotation, ``Annotated[float, Field(gt=0)]``, which :func:`checked` enforces
    in the function) or a dataclass (its field's default), e.g.
    ``t_min_us: float = field_of(ArrivalWindow, "t_min")``.  ``default``: the
    table's own default where it differs from the source's (``None`` for "not
    given"); the bounds still come along.  A source's ``allow_inf_nan`` does not:
    a case file's numbers stay finite.  Bounds written into the source's
    annotation as a ``Literal`` do not come along: annotate with the same type
    alias.
    """
    if isinstance(source, type) and issubclass(source, BaseModel):
        info = source.model_fields[name]
        if info.description is None and name in documented_settings(source):
            info = FieldInfo.merge_field_infos(info, description=documented_settings(source)[name])
    elif dataclasses.is_dataclass(source):
        info = Field(default={f.name: f for f in dataclasses.fields(source)}[name].default)
    else:
        parameter = inspect.signature(source).parameters[name]
        hint = typing.get_type_hints(source, include_extras=True).get(name)
        info = FieldInfo.from_annotated_attribute(hint, parameter.default) if _bounded(hint) else Field(
            default=parameter.default)
        if parameter.default is inspect.Parameter.empty and default is _NO_DEFAULT:
            raise TypeError(f"{source.__qualname__}: {name} has no default")
    if default is not _NO_DEFAULT:
        info = FieldInfo.merge_field_infos(info, default=default)
    if any(getattr(m, "allow_inf_nan", None) for m in info.metadata):
        info = FieldInfo.merge_field_infos(info)
        info.metadata = [m for m in info.metadata if getattr(m, "allow_inf_nan", None) is None]
    return info


#: A docstring line that documents settings: ``name : text`` or ``a, b : text``.
SETTING_ENTRY = re.compile(r"^(\w+(?:, \w+)*) : (.*)$")


def documented_settings(cls: type) -> dict[str, str]:
    """The ``name : description`` entries of the docstrings of ``cls`` and its bases, e.g.
    ``cfl, force_cfl : time-step factors.`` (both named; indented lines continue an entry).

    The description of a setting documented in its class's docstring rather than under the
    field (where pydantic takes it as the field's ``description``)."""
    entries: dict[str, str] = {}
    for klass in reversed(cls.__mro__):
        names: list[str] = []
        for line in inspect.cleandoc(klass.__dict__.get("__doc__") or "").splitlines():
            entry = SETTING_ENTRY.match(line)
            if entry:
                names = entry.group(1).split(", ")
                entries.update(dict.fromkeys(names, entry.group(2).strip()))
            elif names and line.startswith(" "):
                entries.update(dict.fromkeys(names, f"{entries[names[0]]} {line.strip()}"))
            else:
                names = []
    return entries


def section_of(name: str, base: type[M], source: Any, names: Sequence[str], module: str) -> type[M]:
    """A :class:`Section` named ``name`` derived from ``base`` with the settings ``names`` of
    ``source`` (:func:`field_of`: their types, defaults and bounds), e.g. a case table that exposes
    some of a solver's options under the same keys.  The types keep their ``Annotated`` bounds (a
    bound written inside an optional type, ``Positive | None``, lives there, not in the field)."""
    hints = typing.get_type_hints(source, include_extras=True)
    return create_model(name, __base__=base, __module__=module,
                        **{key: (hints[key], field_of(source, key)) for key in names})


def _bounded(hint: Any) -> bool:
    """``hint`` is ``Annotated[..., Field(...)]`` (bounds a function's argument must keep)."""
    return typing.get_origin(hint) is Annotated and any(isinstance(m, FieldInfo) for m in hint.__metadata__)


_LAX = ConfigDict(allow_inf_nan=False)


def checked(function: Callable) -> Callable:
    """Check ``function``'s arguments against the bounds of their annotations before it runs.

    A parameter annotated ``Annotated[float, Field(gt=0)]`` (:data:`Positive`, …) keeps
    its bound there, once: a value outside it (or not finite) raises an
    :class:`~impactdyn._errors.InputError` naming the function and the parameter
    (``write_lsdyna_deck: pulse_width = 0.0: must be greater than 0``), and
    :func:`field_of` carries the bound into a case table.  The function receives
    the values as given.
    """
    signature = inspect.signature(function)

    @functools.cache
    def adapters() -> dict[str, TypeAdapter]:
        hints = typing.get_type_hints(function, include_extras=True)
        return {name: TypeAdapter(hint, config=_LAX) for name, hint in hints.items() if _bounded(hint)}

    @functools.wraps(function)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        bound = signature.bind(*args, **kwargs)
        bound.apply_defaults()
        for name, adapter in adapters().items():
            value = bound.arguments[name]
            try:
                adapter.validate_python(value)
            except ValidationError as err:
                msg = err.errors()[0]["msg"].replace("Input should be", "must be")
                raise InputError(f"{function.__name__}: {name} = {value}: {msg}") from None
        return function(*args, **kwargs)

    return wrapper


def rule(check: Callable[..., None], *keys: str) -> Any:
    """A section's validator that runs a library's rule between several values, ``check(*values, keys)``.

    ``check`` raises a ValueError naming the ``keys`` it is given, so the library's
    own type and every case table that repeats the values under other keys share
    one rule, e.g. ``_bulk = rule(check_bulk_modulus, "lambda_Mbar", "mu_Mbar")``.
    """

    def run(self: Any) -> Any:
        check(*(getattr(self, key) for key in keys), keys)
        return self

    return model_validator(mode="after")(run)


MAX_REACH = 2**26
"""How far from the origin a grid may reach, in its own node spacings.  Its nodes' coordinates then
carry a spacing to 26 bits (1.5e-8), which the geometry built on them needs (edge vectors, volumes,
inertia tensors); much further out, neighbouring nodes round to the same number."""


def check_ranges(ranges: list[tuple[str, list[float], int]], nodes_key: str) -> None:
    """Each ``(name, [lower, upper], nodes)`` has upper > lower, and ``nodes`` equally spaced nodes over it
    (set by ``nodes_key``) are distinct numbers: no more than :data:`MAX_REACH` spacings from the origin
    (a model validator's ValueError otherwise)."""
    for name, (lo, hi), nodes in ranges:
        if not hi > lo:
            raise ValueError(f"{name} = [{lo}, {hi}]: the upper bound must exceed the lower")
        spacing = (hi - lo) / (nodes - 1)
        if not max(abs(lo), abs(hi)) <= MAX_REACH * spacing < math.inf:
            raise ValueError(f"{name} = [{lo}, {hi}] with {nodes} nodes ({nodes_key}): their spacing {spacing:.4g} "
                             f"is not resolved that far from the origin (at most {MAX_REACH} spacings out)")


def _key_path(loc: tuple, data: Any) -> str:
    """Dotted key of an error location, without the tags pydantic inserts for unions."""
    parts, node = [], data
    for i, p in enumerate(loc):
        if isinstance(node, dict) and p not in node and not isinstance(p, int) and parts and i < len(loc) - 1:
            continue  # a union member's name, not a key of the file
        parts.append(f"[{p}]" if isinstance(p, int) else str(p))
        node = node.get(p) if isinstance(node, dict) else (
            node[p] if isinstance(node, list) and isinstance(p, int) and p < len(node) else None)
    return ".".join(parts).replace(".[", "[")


def _format_error(source: str, err: ValidationError, data: Any,
                  line_of: Callable[[str], int | None] | None = None) -> str:
    lines = []
    for e in err.errors():
        key = _key_path(e["loc"], data)
        msg = e["msg"]
        if e["type"] == "extra_forbidden":
            msg = "unknown key"
        elif e["type"] == "missing":
            msg = "missing key"
        msg = msg.replace("Input should be", "must be").replace("Value error, ", "")
        line = line_of(key) if line_of else None
        where = source if line is None else f"{source}:{line}"
        lines.append(f"{where}: {key}: {msg}" if key else f"{where}: {msg}")
    return "\n".join(lines)


def validate(model: type[M], data: dict[str, Any], source: str = "<case>",
             line_of: Callable[[str], int | None] | None = None) -> M:
    """Build ``model`` from a plain dict, raising :class:`InputError` on failure.

    ``line_of``: where the values come from the records of another file (``source``, e.g. a
    dc3din), the line of ``source`` that holds a dotted key's value; the message names it.
    """
    try:
        return model.model_validate(data)
    except ValidationError as err:
        raise InputError(_format_error(source, err, data, line_of)) from None


def load_toml(path: str | Path) -> dict[str, Any]:
    """Read a TOML file; unreadable or malformed files raise :class:`InputError`."""
    p = Path(path)
    try:
        with reading(p, "case file"), p.open("rb") as fh:
            return tomllib.load(fh)
    except UnicodeDecodeError:
        raise InputError(f"{p}: not a UTF-8 text file") from None
    except tomllib.TOMLDecodeError as err:
        raise InputError(f"{p}: invalid TOML: {err}") from None


def load_case(model: type[M], path: str | Path) -> M:
    """Load and validate a TOML case file."""
    return validate(model, load_toml(path), source=str(path))


def set_dotted(data: dict[str, Any], key: str, value: Any) -> dict[str, Any]:
    """Return a copy of ``data`` with ``a.b.c = value`` (tables created as needed)."""
    out = _deepcopy(data)
    parts = key.split(".")
    node = out
    for p in parts[:-1]:
        node = node.setdefault(p, {})
        if not isinstance(node, dict):
            raise InputError(f"{key}: '{p}' is not a table")
    node[parts[-1]] = value
    return out


def non_defaults(model: BaseModel, prefix: str = "") -> dict[str, Any]:
    """Dotted key → value of each setting of ``model`` (its tables' too) that has a default and is not at it;
    the settings without a default (the shot's own) are left out."""
    out: dict[str, Any] = {}
    for name, info in type(model).model_fields.items():
        value = getattr(model, name)
        if isinstance(value, BaseModel):
            out |= non_defaults(value, f"{prefix}{name}.")
        elif not info.is_required() and value != info.get_default(call_default_factory=True):
            out[prefix + name] = value
    return out


def parse_range(option: str, spec: str, example: str) -> list[float]:
    """``START:STOP:N`` → N values from START to STOP inclusive; ``option`` and ``example`` go into the error."""
    import numpy as np

    from impactdyn._limits import CASE_BYTES, check_fits

    try:
        start, stop, n = spec.split(":")
        count, lo, hi = int(n), float(start), float(stop)
    except ValueError:
        raise InputError(f"{option} {spec!r}: expected START:STOP:N, e.g. {example}") from None
    if count >= 1:
        check_fits(f"{option} {spec!r}: N", count, CASE_BYTES, "cases")
    with np.errstate(over="ignore", invalid="ignore"):
        values = np.linspace(lo, hi, max(count, 0))
    if count < 1 or not np.all(np.isfinite(values)):
        raise InputError(f"{option} {spec!r}: N must be at least 1 and the bounds finite")
    return values.tolist()


def parse_assignment(text: str) -> tuple[str, Any]:
    """``KEY=VALUE`` of a command-line option → (KEY, VALUE read as JSON: ``false``, ``null``, ``0.5``);
    a VALUE that is not JSON stays a string (a bare word: ``material_model=mat13``)."""
    key, sep, value = text.partition("=")
    if not sep or not key:
        raise InputError(f"expected KEY=VALUE, got {text!r}")
    try:
        return key, json.loads(value)
    except json.JSONDecodeError:
        return key, value


def _deepcopy(d: Any) -> Any:
    if isinstance(d, dict):
        return {k: _deepcopy(v) for k, v in d.items()}
    if isinstance(d, list):
        return [_deepcopy(v) for v in d]
    return d


def dump_toml(model: BaseModel) -> str:
    """Every parameter actually used, defaults included, as TOML."""
    return tomli_w.dumps(_drop_none(model.model_dump(mode="json")))


def _drop_none(d: Any) -> Any:
    if isinstance(d, dict):
        return {k: _drop_none(v) for k, v in d.items() if v is not None}
    if isinstance(d, list):
        return [_drop_none(v) for v in d]
    if isinstance(d, float) and not math.isfinite(d):
        raise ValueError("non-finite value in resolved config")
    return d
