"""Sphinx extension: the case-file and command-line reference pages, generated from the code.

At ``builder-inited`` it writes ``user-guide/case-files.md`` (every key of the four case kinds,
walked from their pydantic :class:`~impactdyn._config.Section` models: dotted key, type, unit,
default, bounds, description) and ``user-guide/cli.md`` (every command of the typer app with its
arguments and options).  Both files are build outputs (ignored by git), so they cannot drift
from the code; ``tests/test_docs_reference.py`` checks the case reference against the models.
"""

from __future__ import annotations

import dataclasses
import re
import types
import typing

from pathlib import Path
from typing import Annotated, Any, Literal, Union

import annotated_types
from pydantic import BaseModel
from pydantic.fields import FieldInfo
from pydantic_core import PydanticUndefined

from impactdyn._config import documented_settings
from impactdyn.beam import BeamCase
from impactdyn.debris import DebrisCase
from impactdyn.whipple import WhippleCase
from impactdyn.whipple._selection import SelectionRule


@dataclasses.dataclass(frozen=True)
class CaseKind:
    title: str
    model: type[BaseModel]
    used_by: str
    example: str


CASE_KINDS = (
    CaseKind("Whipple shot", WhippleCase, "`impactdyn whipple run|campaign|limit`", "examples/whipple/table2_7a.toml"),
    CaseKind("Debris cloud", DebrisCase, "`impactdyn debris run`", "examples/debris/shell_cloud.toml"),
    CaseKind("Rotating beam", BeamCase, "`impactdyn beam run|sweep`", "examples/beam/impactb_sample.toml"),
    CaseKind("Test-shot selection rule", SelectionRule, "`impactdyn whipple validate --select`, `fix-rule`",
             "src/impactdyn/whipple/rules/set-1.toml"),
)

# A key's unit is written in its name (docs/ARCHITECTURE.md, conventions); the longest suffix wins.
UNITS = {
    "_cm": "cm", "_us": "µs", "_km_s": "km/s", "_Mbar": "Mbar", "_Mbar_us": "Mbar·µs", "_deg": "°",
    "_ksi": "ksi", "_g_cm3": "g/cm³", "_m": "m", "_s": "s", "_m_s": "m/s", "_m_s2": "m/s²", "_rad": "rad",
    "_rad_s": "rad/s", "_kg_m": "kg/m", "_N_m": "N·m", "_N_m2": "N·m²", "_N_m_s": "N·m·s",
    "_N_m1_5": "N/m^1.5", "_N_m_n": "N/mⁿ", "_s_m": "s/m",
}
_BOUNDS = {annotated_types.Gt: "> {}", annotated_types.Ge: "≥ {}", annotated_types.Lt: "< {}",
           annotated_types.Le: "≤ {}", annotated_types.MinLen: "length ≥ {}", annotated_types.MaxLen: "length ≤ {}"}


@dataclasses.dataclass(frozen=True)
class Key:
    """One key of a case file."""

    dotted: str
    type: str
    unit: str
    default: str
    bounds: str
    description: str


def unit_of(name: str) -> str:
    suffixes = [s for s in UNITS if name.endswith(s)]
    return UNITS[max(suffixes, key=len)] if suffixes else ""


def _sections(annotation: Any) -> list[type[BaseModel]]:
    """The section models a field holds: one table, optional, or a discriminated union of tables."""
    members = typing.get_args(annotation) if _is_union(annotation) else (annotation,)
    members = [typing.get_args(m)[0] if typing.get_origin(m) is Annotated else m for m in members]
    if typing.get_origin(annotation) is Annotated:
        return _sections(typing.get_args(annotation)[0])
    return [m for m in members if isinstance(m, type) and issubclass(m, BaseModel)]


def _is_union(annotation: Any) -> bool:
    return typing.get_origin(annotation) in (Union, types.UnionType)


def type_name(annotation: Any) -> str:
    origin, args = typing.get_origin(annotation), typing.get_args(annotation)
    if origin is Annotated:
        return type_name(args[0])
    if _is_union(annotation):
        return " or ".join("none" if a is type(None) else type_name(a) for a in args)
    if origin is Literal:
        return "one of " + ", ".join(f'"{a}"' if isinstance(a, str) else str(a) for a in args)
    if origin is list:
        return f"list of {type_name(args[0])}"
    return {str: "string", float: "number", int: "integer", bool: "boolean"}.get(annotation, str(annotation))


def bounds_of(info: FieldInfo) -> str:
    """Bounds of the value (and, for a list, of each item)."""
    found = [_BOUNDS[type(m)].format(*dataclasses.astuple(m)) for m in info.metadata if type(m) in _BOUNDS]
    lengths = [dataclasses.astuple(m)[0] for m in info.metadata if isinstance(m, (annotated_types.MinLen,
                                                                                   annotated_types.MaxLen))]
    if len(lengths) == 2 and lengths[0] == lengths[1]:
        found = [f for f in found if not f.startswith("length")] + [f"length {lengths[0]}"]
    inner = info.annotation
    for arg in typing.get_args(inner):  # float | None, list[Annotated[int, Field(ge=2)]]
        if typing.get_origin(arg) is Annotated:
            bounded = [m for m in typing.get_args(arg)[1:] if isinstance(m, FieldInfo)]
            prefix = "each " if typing.get_origin(inner) is list else ""
            found += [prefix + bounds_of(b) for b in bounded]
    return ", ".join(found)


def default_of(info: FieldInfo) -> str:
    if info.is_required():
        return "required"
    value = info.get_default(call_default_factory=True)
    if value is None:
        return "none"
    if isinstance(value, BaseModel):
        return "(table)"
    return f'"{value}"' if isinstance(value, str) else str(value).replace("True", "true").replace("False", "false")


def _plain(text: str) -> str:
    """A docstring's reST into one Markdown table cell."""
    text = re.sub(r":\w+:`~?([^`]+)`", r"`\1`", text)
    return text.replace("``", "`").replace("|", "\\|").replace("\n", " ")


def case_keys(model: type[BaseModel], prefix: str = "", variant: str = "") -> list[Key]:
    """Every key of ``model``, tables walked; a key of one member of a union of tables names it."""
    keys = []
    described = documented_settings(model)
    for name, info in model.model_fields.items():
        dotted = f"{prefix}{name}"
        sections = _sections(info.annotation)
        if sections:
            for section in sections:
                tag = ""
                if len(sections) > 1:  # a discriminated union: each member says which value selects it
                    tag_field = section.model_fields[info.discriminator] if isinstance(info.discriminator, str) else None
                    tag = f"{info.discriminator} = " + " or ".join(
                        f'"{v}"' for v in typing.get_args(tag_field.annotation)) if tag_field else ""
                keys += case_keys(section, f"{dotted}.", tag)
            continue
        description = info.description or described.get(name, "")
        if variant:
            description = f"({variant}) {description}"
        keys.append(Key(dotted, type_name(info.annotation), unit_of(name), default_of(info), bounds_of(info),
                        _plain(description.strip())))
    return keys


def _table_doc(model: type[BaseModel], table: str) -> str:
    """The docstring of the section that holds ``table``, first paragraph."""
    node: Any = model
    for part in table.split("."):
        sections = _sections(node.model_fields[part].annotation)
        node = sections[0] if len(sections) == 1 else None
        if node is None:
            return ""
    return _plain((node.__doc__ or "").strip().split("\n\n")[0])


def case_reference() -> str:
    lines = [
        "# Case-file reference",
        "",
        "Every key of the four kinds of case file, generated from the configuration sections when these "
        "pages are built. A key's unit is the suffix of its name (`_cm`: cm, `_us`: µs, `_km_s`: km/s, "
        "`_Mbar`: Mbar = 100 GPa, `_Mbar_us`: Mbar·µs, `_ksi`: ksi, `_deg`: degrees; the beam: SI). "
        "Unknown keys, wrong types, non-finite numbers and values outside the bounds are errors that "
        "name the file and the dotted key (exit code 2). Rules between keys (for example the wall must "
        "lie beyond the debris' reach at the hand-off) are checked too and named in their messages. "
        "Every run folder holds `config.resolved.toml`: the case with every default filled in.",
        "",
    ]
    for kind in CASE_KINDS:
        lines += [f"## {kind.title}", "", f"Used by {kind.used_by}; example: `{kind.example}`. "
                  f"{_plain((kind.model.__doc__ or '').strip())}", ""]
        table = None
        for key in case_keys(kind.model):
            section = key.dotted.rpartition(".")[0]
            if section != table:
                table = section
                heading = f"### `[{section}]`" if section else "### Top level"
                doc = _table_doc(kind.model, section) if section else ""
                lines += ["", heading, "", *([doc, ""] if doc else []),
                          "| key | type | unit | default | bounds | description |", "| --- | --- | --- | --- | --- | --- |"]
            lines.append(f"| `{key.dotted}` | {key.type} | {key.unit} | {_plain(key.default)} | {key.bounds} | "
                         f"{key.description} |")
        lines.append("")
    return "\n".join(lines)


def _commands(command: Any, path: str) -> list[tuple[str, Any]]:
    found = [(path, command)]
    for name, sub in sorted(getattr(command, "commands", {}).items()):
        found += _commands(sub, f"{path} {name}")
    return found


def cli_reference() -> str:
    import typer.main

    from impactdyn.cli import app

    lines = ["# Command-line reference", "",
             "Every command of the `impactdyn` console script, generated from the command-line app when "
             "these pages are built (`impactdyn COMMAND --help` prints the same). Exit codes: 0 done, "
             "1 simulation failed, 2 bad input or an output that cannot be written, 130 interrupted; "
             "none of them prints a traceback.", ""]
    for path, command in _commands(typer.main.get_command(app), "impactdyn"):
        depth = min(path.count(" ") + 2, 4)
        arguments = [p for p in command.params if p.param_type_name == "argument"]
        usage = " ".join([path, *(p.name.upper() if p.required else f"[{p.name.upper()}]" for p in arguments),
                          "[OPTIONS]" if len(arguments) < len(command.params) else "",
                          "COMMAND" if hasattr(command, "commands") else ""])
        lines += [f"{'#' * depth} `{path}`", "", _plain(command.help or ""), "", f"```text\n{usage.strip()}\n```", ""]
        if command.params:
            lines += ["| argument / option | required | default | help |", "| --- | --- | --- | --- |"]
            for p in command.params:
                name = p.name.upper() if p.param_type_name == "argument" else " ".join(p.opts)
                default = "" if p.required or p.default is None else f"`{p.default}`"
                lines.append(f"| `{name}` | {'yes' if p.required else ''} | {default} | "
                             f"{_plain(getattr(p, 'help', None) or '')} |")
            lines.append("")
    return "\n".join(lines)


GENERATED = {"user-guide/case-files.md": case_reference, "user-guide/cli.md": cli_reference}


def write_pages(app: Any) -> None:
    for name, page in GENERATED.items():
        path = Path(app.srcdir) / name
        text = page()
        if not path.exists() or path.read_text(encoding="utf-8") != text:  # unchanged: no rebuild
            path.write_text(text, encoding="utf-8")


def setup(app: Any) -> dict[str, Any]:
    app.connect("builder-inited", write_pages)
    return {"parallel_read_safe": True}
