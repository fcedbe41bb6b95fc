"""Sphinx extension: the reference pages generated from the code, and the docstrings made reST.

At ``builder-inited`` it writes ``user-guide/case-files.md`` (every key of the four case kinds,
walked from their pydantic :class:`~impactdyn._config.Section` models: dotted key, type, unit,
default, bounds, description), ``user-guide/cli.md`` (every command of the typer app with its
arguments and options) and ``api/*.md`` (each public module's ``__all__``, every object on the
page of the package that defines it).  They are build outputs (ignored by git), so they cannot
drift from the code; ``tests/test_docs_reference.py`` checks the case reference against the models.

The docstrings write maths in plain text (``|p|``, ``a*b``) and document settings as
``name : text`` lines; :func:`as_rest` escapes the one and turns the other into a definition
list before autodoc parses them.  On the API pages a parameter typed with pydantic's metadata
(``Annotated[float, Ge(ge=0), AfterValidator(...)]``) reads as its type and bounds in the case-file
reference's words (``float ≥ 0``, :func:`annotation_for_people`), and a model's ``model_config``,
pydantic's settings rather than the model's, is left out.
"""

from __future__ import annotations

import dataclasses
import inspect
import math
import re
import types
import typing

from pathlib import Path
from typing import Annotated, Any, Literal, Union

import annotated_types
from pydantic import BaseModel
from pydantic.fields import FieldInfo
from pydantic_core import PydanticUndefined

from impactdyn._config import SETTING_ENTRY, documented_settings
from impactdyn.beam import BeamCase
from impactdyn.debris import DebrisCase
from impactdyn.whipple import SelectionRule, WhippleCase


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


def _named_table(annotation: Any) -> type[BaseModel] | None:
    """The section of a field that holds tables by name (``dict[str, Section]``, optional), else None."""
    if typing.get_origin(annotation) is Annotated or _is_union(annotation):
        return next((t for a in typing.get_args(annotation) if (t := _named_table(a))), None)
    if typing.get_origin(annotation) is dict:
        value = typing.get_args(annotation)[1]
        return value if isinstance(value, type) and issubclass(value, BaseModel) else None
    return None


#: The placeholder of a table's own name in a key (``[materials.NAME]``).
NAME = "NAME"


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


#: Bounds that are a named number, printed by name: steps per period > π (stability of the leapfrog).
_NAMED_NUMBERS = {math.pi: "π"}


def bound_number(value: Any) -> str:
    """A bound for people: a named number by its name (π, not 3.141592653589793), else at most nine
    significant digits (the light-speed bound 299.792458 km/s keeps its digits) without ``e+``."""
    if isinstance(value, float):
        named = next((name for number, name in _NAMED_NUMBERS.items() if math.isclose(value, number)), None)
        return named or f"{value:.9g}".replace("e+", "e")
    return str(value)


def registered_names(info: FieldInfo) -> str:
    """'a registered wall failure law: "tuler_butcher", "cutoff"' for a key typed ``REGISTRY.name_type()``
    (:class:`impactdyn._registry.Registry`), else ''."""
    for m in info.metadata:
        registry = getattr(getattr(m, "func", None), "registry", None)
        if registry is not None:
            return f"a registered {registry.what}: " + ", ".join(f'"{n}"' for n in registry.names())
    return ""


def bounds_of(info: FieldInfo) -> str:
    """Bounds of the value (and, for a list, of each item), each once."""
    found = [_BOUNDS[type(m)].format(*map(bound_number, dataclasses.astuple(m)))
             for m in info.metadata if type(m) in _BOUNDS]
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
    return ", ".join(dict.fromkeys(found))  # a bound declared on the field and in its type: once


def default_of(info: FieldInfo) -> str:
    if info.is_required():
        return "required"
    value = info.get_default(call_default_factory=True)
    if value is None:
        return "none"
    if isinstance(value, BaseModel):
        return "(table)"
    toml = f'"{value}"' if isinstance(value, str) else str(value).replace("True", "true").replace("False", "false")
    return f"`{toml}`"


def _plain(text: str) -> str:
    """A docstring's reST into one Markdown table cell."""
    text = re.sub(r":\w+:`~?([^`]+)`", r"`\1`", text)
    return text.replace("``", "`").replace("|", "\\|").replace("\n", " ")


def _choices(section: type[BaseModel], discriminator: str) -> tuple[str, ...]:
    """The values of ``discriminator`` that select ``section`` (its ``Literal``)."""
    return typing.get_args(section.model_fields[discriminator].annotation)


def _discriminator_key(dotted: str, info: FieldInfo, sections: list[type[BaseModel]], description: str) -> Key:
    """The key that chooses a member of a union of tables, listed once: every choice, each with the first
    paragraph of its table's docstring, after the union's own description."""
    discriminator = str(info.discriminator)
    choices = [value for section in sections for value in _choices(section, discriminator)]
    meanings = " ".join(
        " or ".join(f'`"{value}"`' for value in _choices(section, discriminator)) + ": "
        + " ".join(inspect.cleandoc(section.__doc__ or "").split("\n\n")[0].split()) for section in sections)
    default = "required" if info.is_required() else f'`"{getattr(info.get_default(), discriminator)}"`'
    return Key(f"{dotted}.{discriminator}", "one of " + ", ".join(f'"{v}"' for v in choices), "", default,
               "", _plain(f"{description.strip()} {meanings}".strip()))


def case_keys(model: type[BaseModel], prefix: str = "", variant: str = "", discriminator: str = "") -> list[Key]:
    """Every key of ``model``, tables walked.  A union of tables has its discriminator listed once with
    its choices; a key of one member names the member (``(model = "hertz")``)."""
    keys = []
    described = documented_settings(model)
    for name, info in model.model_fields.items():
        if name == discriminator:  # listed once, with the union
            continue
        dotted = f"{prefix}{name}"
        named = _named_table(info.annotation)
        if named is not None:
            keys += case_keys(named, f"{dotted}.{NAME}.", variant)
            continue
        sections = _sections(info.annotation)
        if sections:
            union_of = info.discriminator if len(sections) > 1 and isinstance(info.discriminator, str) else ""
            if union_of:
                keys.append(_discriminator_key(dotted, info, sections, info.description or described.get(name, "")))
            for section in sections:
                tag = f"{union_of} = " + " or ".join(f'"{v}"' for v in _choices(section, union_of)) if union_of else ""
                keys += case_keys(section, f"{dotted}.", tag, union_of)
            continue
        description = info.description or described.get(name, "")
        if variant:
            description = f"({variant}) {description}"
        keys.append(Key(dotted, registered_names(info) or type_name(info.annotation), unit_of(name), default_of(info), bounds_of(info),
                        _plain(description.strip())))
    return keys


def _table_doc(model: type[BaseModel], table: str) -> str:
    """The docstring of the section that holds ``table``, first paragraph."""
    node: Any = model
    for part in table.split("."):
        if part == NAME:
            continue
        named = _named_table(node.model_fields[part].annotation)
        sections = [named] if named is not None else _sections(node.model_fields[part].annotation)
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
            lines.append(f"| `{key.dotted}` | {key.type} | {key.unit} | {key.default} | {key.bounds} | "
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
        usage = " ".join(word for word in [
            path, *(p.name.upper() if p.required else f"[{p.name.upper()}]" for p in arguments),
            "[OPTIONS]" if len(arguments) < len(command.params) else "",
            "COMMAND" if hasattr(command, "commands") else ""] if word)
        lines += [f"{'#' * depth} `{path}`", "", _plain(command.help or ""), "", f"```text\n{usage.strip()}\n```", ""]
        if command.params:
            lines += ["| argument / option | required | default | help |", "| --- | --- | --- | --- |"]
            for p in command.params:
                name = p.name.upper() if p.param_type_name == "argument" else ", ".join(p.opts)
                default = "" if p.required or p.default is None or getattr(p, "is_flag", False) else f"`{p.default}`"
                lines.append(f"| `{name}` | {'yes' if p.required else ''} | {default} | "
                             f"{_plain(getattr(p, 'help', None) or '')} |")
            lines.append("")
    return "\n".join(lines)


API_MODULES = {
    "whipple": "The end-to-end Whipple pipeline, its cases, campaigns, limits and validation.",
    "shield": "The built-in SPH shield-impact stage and the binning to a hand-off grid.",
    "debris": "DC3D's deformable particles: seeding, integrators, deposition on the wall.",
    "wall": "Explicit finite elements of the rear wall, its failure and verdict.",
    "ble": "Ballistic-limit equations and the test database.",
    "beam": "The rotating flexible beam with impact.",
    "io": "File formats: grids, legacy DC3D and CTH files, LS-DYNA and DYNA3D decks, VTK.",
    "hydrogrid": "The hand-off state on a rectilinear grid.",
    "wallgrid": "The wall's brick mesh and the deposited momentum.",
    "materials": "One record per alloy, the registry, and the library with its sources.",
    "constitutive": "Compiled equation-of-state and strength kernels shared by the SPH and FE solvers.",
    "units": "Unit conversions.",
}


def _home(module: str, obj: Any) -> str:
    """The public module whose page documents ``obj``: the package that defines it, else ``module``."""
    defined = getattr(obj, "__module__", None) or module
    for name in ["impactdyn", *(f"impactdyn.{m}" for m in API_MODULES)]:
        if defined.startswith(f"{name}.") and name != "impactdyn" or defined == name:
            return name
    return "impactdyn" if getattr(obj, "__name__", None) in _exports("impactdyn") else module


def _exports(module: str) -> list[str]:
    import importlib

    imported = importlib.import_module(module)
    return list(getattr(imported, "__all__", [n for n in vars(imported) if not n.startswith("_")]))


def api_page(module: str, summary: str) -> str:
    import importlib

    imported = importlib.import_module(module)
    own, elsewhere = [], []
    for name in _exports(module):
        home = _home(module, getattr(imported, name))
        (own if home == module else elsewhere).append((name, home))
    lines = [f"# {module}", "", summary, "", "```{eval-rst}", f".. automodule:: {module}",
             f"   :members: {', '.join(n for n, _ in own)}" if own else "   :no-members:",
             *([f"   :exclude-members: {', '.join(n for n, _ in elsewhere)}"] if elsewhere else []), "```", ""]
    if elsewhere:
        lines += ["Also exported here, documented where they are defined: " + ", ".join(
            f"[`{n}`]({home.replace('impactdyn.', '') if home != 'impactdyn' else 'impactdyn'}.md)"
            for n, home in elsewhere) + ".", ""]
    return "\n".join(lines)


def api_index() -> str:
    lines = ["# API reference", "",
             "The public names of each module: those its `__init__` exports (`__all__`). Names that start "
             "with an underscore are private and may change without notice.", "",
             "| module | what it holds |", "| --- | --- |",
             "| [`impactdyn`](impactdyn.md) | the two errors every command and function raises |",
             *(f"| [`impactdyn.{m}`]({m}.md) | {s} |" for m, s in API_MODULES.items()),
             "", "```{toctree}", ":hidden:", "", "impactdyn", *API_MODULES, "```", ""]
    return "\n".join(lines)


def generated_pages() -> dict[str, str]:
    pages = {"user-guide/case-files.md": case_reference(), "user-guide/cli.md": cli_reference(),
             "api/index.md": api_index(),
             "api/impactdyn.md": api_page("impactdyn", "The package: its errors, which every command maps to an "
                                                       "exit code.")}
    pages |= {f"api/{m}.md": api_page(f"impactdyn.{m}", s) for m, s in API_MODULES.items()}
    return pages


def write_pages(app: Any) -> None:
    for name, text in generated_pages().items():
        path = Path(app.srcdir) / name
        path.parent.mkdir(exist_ok=True)
        if not path.exists() or path.read_text(encoding="utf-8") != text:  # unchanged: no rebuild
            path.write_text(text, encoding="utf-8")


_CODE = re.compile(r"(``.+?``|:[\w:]+:`[^`]+`|`[^`]+`_?)")


def _escape(line: str) -> str:
    """``|`` and ``*`` outside literals and roles, as text (the docstrings' absolute values, products)."""
    bullet = re.match(r"\s*[*-] ", line)
    head, line = (bullet.group(0), line[bullet.end():]) if bullet else ("", line)
    parts = _CODE.split(line)
    return head + "".join(p if i % 2 else p.replace("|", "\\|").replace("*", "\\*") for i, p in enumerate(parts))


def as_rest(lines: list[str]) -> list[str]:
    """A docstring's lines as reStructuredText: maths escaped outside literal blocks, and each run of
    ``name : text`` entries (with their indented continuations) a definition list."""
    out: list[str] = []
    literal_indent = None  # the indentation of the paragraph that opened a literal block (``::``)
    in_entries = False
    for line in lines:
        indent = len(line) - len(line.lstrip())
        if literal_indent is not None and (not line.strip() or indent > literal_indent):
            out.append(line)
            continue
        literal_indent = None
        entry = SETTING_ENTRY.match(line)
        if entry:
            if not in_entries and out and out[-1].strip():
                out.append("")
            out += [", ".join(f"``{n}``" for n in entry.group(1).split(", ")), f"    {_escape(entry.group(2))}"]
            in_entries = True
        elif in_entries and line.startswith(" ") and line.strip():
            out.append(f"    {_escape(line.strip())}")
        else:
            if in_entries and line.strip():
                out.append("")
            in_entries = False
            out.append(_escape(line))
        if line.rstrip().endswith("::"):
            literal_indent = indent
    return out


def _without_metadata(annotation: Any) -> Any:
    """``annotation`` with every ``Annotated[T, ...]`` in it reduced to ``T``."""
    if typing.get_origin(annotation) is Annotated:
        return _without_metadata(typing.get_args(annotation)[0])
    args = typing.get_args(annotation)
    if _is_union(annotation):
        return Union[tuple(_without_metadata(a) for a in args)]  # noqa: UP007 (built from a tuple)
    if args and typing.get_origin(annotation) in (list, tuple, dict):
        return typing.get_origin(annotation)[tuple(_without_metadata(a) for a in args)]
    return annotation


def _for_people(annotation: Any) -> bool:
    """Whether ``annotation`` holds what :func:`annotation_for_people` words: pydantic's metadata or a ``Literal``."""
    return typing.get_origin(annotation) in (Annotated, Literal) or any(
        _for_people(a) for a in typing.get_args(annotation) if typing.get_origin(annotation) is not Literal)


def annotation_for_people(annotation: Any) -> str:
    """A type with pydantic's metadata as a reader wants it: the Python type, then its bounds as the case-file
    reference writes them (:func:`bounds_of`: ``float ≥ 0``, ``float > 0, ≤ 1``, ``float > 0 or None``),
    the names a registry accepts (:func:`registered_names`), or a ``Literal``'s choices (:func:`type_name`:
    ``one of "graded", "report"``)."""
    from sphinx.util.typing import stringify_annotation

    info = FieldInfo.from_annotation(annotation)
    registered = registered_names(info)
    if registered:
        return registered
    bare = _without_metadata(annotation)
    optional = _is_union(bare) and type(None) in typing.get_args(bare)
    if optional:
        bare = Union[tuple(a for a in typing.get_args(bare) if a is not type(None))]  # noqa: UP007
    typed = type_name(bare) if typing.get_origin(bare) is Literal else stringify_annotation(bare, "smart")
    words = " ".join(filter(None, [typed, bounds_of(info)]))
    return f"{words} or None" if optional else words


def _parameters(app: Any, obj: Any) -> list[inspect.Parameter]:
    """The parameters of ``obj`` with the annotations autodoc reads (Sphinx's own signature: the type hints
    evaluated, pydantic's ``Annotated`` kept)."""
    from sphinx.util.inspect import signature

    try:
        return list(signature(obj, type_aliases=app.config.autodoc_type_aliases).parameters.values())
    except (TypeError, ValueError):  # a builtin or an object without a signature: nothing to type
        return []


def _types_for_people(app: Any, what: str, name: str, obj: Any, options: Any, lines: list[str]) -> None:
    """A ``:type:`` field in users' words for each parameter typed with pydantic's metadata or a ``Literal``:
    autodoc adds the types it finds only where the docstring gives none."""
    typed = [f":type {p.name}: {annotation_for_people(p.annotation)}"
             for p in (_parameters(app, obj) if callable(obj) else []) if _for_people(p.annotation)]
    if typed:
        lines += ["", *typed]


def _rest_docstring(app: Any, what: str, name: str, obj: Any, options: Any, lines: list[str]) -> None:
    lines[:] = as_rest(lines)


def _skip_model_config(app: Any, what: str, name: str, obj: Any, skip: bool, options: Any) -> bool | None:
    """Leave out a pydantic model's ``model_config``: how pydantic validates, not what the model holds."""
    return True if name == "model_config" else None


def setup(app: Any) -> dict[str, Any]:
    app.connect("builder-inited", write_pages)
    app.connect("autodoc-process-docstring", _rest_docstring)
    app.connect("autodoc-process-docstring", _types_for_people)
    app.connect("autodoc-skip-member", _skip_model_config)
    return {"parallel_read_safe": True}
