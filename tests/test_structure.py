"""The package's import structure (docs/ARCHITECTURE.md): imports go one way.

Infrastructure → data model → ``io`` → solver packages → ``whipple`` → ``cli``
(:data:`LAYERS`): a module imports only its own layer and those below.  The load checks run
in a fresh interpreter, so what a module loads is what it alone needs.
"""

from __future__ import annotations

import ast
import json
import pathlib
import re
import subprocess
import sys

import pytest

SRC = pathlib.Path(__file__).resolve().parents[1] / "src" / "impactdyn"
SOLVERS = ("beam", "ble", "debris", "shield", "wall", "whipple", "cli")

#: The layers of docs/ARCHITECTURE.md, bottom first: the first names of ``impactdyn.<name>`` in each.
#: Root modules with a leading underscore are infrastructure.
LAYERS = (
    ("_*",),
    ("hydrogrid", "wallgrid", "materials", "constitutive", "units"),
    ("io",),
    ("beam", "shield", "debris", "wall", "ble"),
    ("whipple",),
    ("cli",),
)


def _page_layers() -> tuple[tuple[str, ...], ...]:
    """The layer drawing of docs/ARCHITECTURE.md, bottom first: the names that open each line."""
    page = (SRC.parents[1] / "docs" / "ARCHITECTURE.md").read_text(encoding="utf-8")
    drawing = page.split("## Layers", 1)[1].split("```", 2)[1]
    layers = []
    for line in drawing.splitlines():
        names = []
        for word in line.split():
            if not re.fullmatch(r"[A-Za-z_]\w*(/|\.py)", word):
                break
            names.append(word.removesuffix("/").removesuffix(".py"))
        if names:
            layers.append(tuple(names))
    return tuple(reversed(layers))


def test_layers_match_the_architecture_page():
    """LAYERS is the page's drawing: the same names in the same layers (infrastructure as ``_*``)."""
    page = _page_layers()
    assert all(name.startswith("_") for name in page[0]), page[0]
    assert (("_*",),) + page[1:] == LAYERS
    top = {p.stem if p.suffix else p.name for p in SRC.iterdir()
           if (p.suffix == ".py" or (p / "__init__.py").is_file()) and p.stem != "__init__"}
    assert sorted(n for n in top if not n.startswith("_")) == sorted(n for layer in LAYERS[1:] for n in layer)


def _loaded_after(statement: str) -> list[str]:
    code = f"import sys, json\n{statement}\nprint(json.dumps(sorted(m for m in sys.modules if m.startswith('impactdyn'))))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize("statement", [
    "import impactdyn.io", "import impactdyn.hydrogrid", "import impactdyn.wallgrid", "import impactdyn.materials",
    "import impactdyn.constitutive", "import impactdyn.units",
])
def test_data_model_and_io_load_no_solver(statement):
    loaded = _loaded_after(statement)
    solvers = [m for m in loaded if m.partition(".")[2].partition(".")[0] in SOLVERS]
    assert solvers == [], f"{statement} loads {solvers}"


def test_shield_loads_no_debris():
    loaded = _loaded_after("import impactdyn.shield")
    assert [m for m in loaded if m.startswith("impactdyn.debris")] == []


def _modules() -> dict[str, pathlib.Path]:
    mods = {}
    for path in SRC.rglob("*.py"):
        parts = path.relative_to(SRC.parent).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        mods[name] = path
    return mods


def _is_module(name: str) -> bool:
    return (SRC / name / "__init__.py").is_file() or (SRC / f"{name}.py").is_file()


def _imports(path: pathlib.Path, module: str) -> list[tuple[str, int]]:
    """Every impactdyn module imported by ``path`` (at any depth: deferred imports count), with its line."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [(a.name, node.lineno) for a in node.names if a.name.startswith("impactdyn")]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                base = ".".join(package.split(".")[:len(package.split(".")) - node.level + 1] + ([base] if base else []))
            if base == "impactdyn":
                # ``from impactdyn import whipple`` imports the package impactdyn.whipple (a layer of its own);
                # ``from impactdyn import SimulationError`` only the root package
                found += [(f"{base}.{a.name}" if _is_module(a.name) else base, node.lineno) for a in node.names]
            elif base.startswith("impactdyn."):
                found += [(base, node.lineno)]
                # ``from impactdyn.pkg import _mod`` imports the private module impactdyn.pkg._mod
                found += [(f"{base}.{a.name}", node.lineno) for a in node.names if a.name.startswith("_")]
    return found


def _private_across(module: str, target: str) -> bool:
    """``target`` is a private module (a name after the package starts with ``_``) of a package other than
    ``module``'s: ``import impactdyn.pkg._mod``, ``from impactdyn.pkg._mod import x`` and
    ``from impactdyn.pkg import _mod`` all name it.  Root infrastructure (``impactdyn._errors``) is shared."""
    pkg = module.split(".")[1] if module.count(".") >= 1 else ""
    parts = target.split(".")
    return len(parts) >= 3 and parts[1] != pkg and any(p.startswith("_") for p in parts[2:])


def _layer(module: str) -> int:
    top = module.split(".")[1] if "." in module else ""
    for level, names in enumerate(LAYERS):
        if top in names or (names == ("_*",) and top.startswith("_")):
            return level
    raise AssertionError(f"{module}: in no layer of docs/ARCHITECTURE.md (add it to LAYERS)")


def test_imports_go_down_the_layers():
    """No module imports a layer above its own (deferred imports inside functions included)."""
    bad = []
    for module, path in _modules().items():
        if module == "impactdyn":
            continue
        for target, line in _imports(path, module):
            if target != "impactdyn" and _layer(target) > _layer(module):
                bad.append(f"{path.relative_to(SRC.parent)}:{line}: {target}")
    assert bad == []


def test_no_private_import_across_packages():
    bad = []
    for module, path in _modules().items():
        for target, line in _imports(path, module):
            if _private_across(module, target):
                bad.append(f"{path.relative_to(SRC.parent)}:{line}: {target}")
    assert bad == []


@pytest.mark.parametrize(("source", "module", "caught"), [
    ("from impactdyn.wall._solver import run", "impactdyn.debris._case", True),
    ("from impactdyn.wall import _solver", "impactdyn.debris._case", True),
    ("import impactdyn.wall._solver", "impactdyn.debris._case", True),
    ("import impactdyn.wall._solver as s", "impactdyn.debris._case", True),
    ("def f():\n    from impactdyn.wall import _solver", "impactdyn.debris._case", True),
    ("from .._errors import InputError\nfrom ..wall import _solver", "impactdyn.debris._case", True),
    ("from impactdyn.wall import run_wall", "impactdyn.debris._case", False),
    ("from impactdyn.wall import _solver", "impactdyn.wall._output", False),
    ("from . import _solver", "impactdyn.wall._output", False),
    ("from impactdyn._errors import InputError", "impactdyn.debris._case", False),
    ("from impactdyn import _errors", "impactdyn.debris._case", False),
])
def test_private_rule_catches_every_form(tmp_path, source, module, caught):
    path = tmp_path / "mod.py"
    path.write_text(source + "\n", encoding="utf-8")
    assert any(_private_across(module, target) for target, _ in _imports(path, module)) is caught


@pytest.mark.parametrize(("source", "module", "up"), [
    ("from impactdyn import whipple", "impactdyn.wall._output", True),
    ("from impactdyn import cli", "impactdyn.whipple._case", True),
    ("import impactdyn.ble", "impactdyn.io._lsdyna", True),
    ("from impactdyn.cli import app", "impactdyn.whipple._case", True),
    ("def f():\n    from impactdyn.whipple import run_whipple", "impactdyn.ble._jsc", True),
    ("from impactdyn import units", "impactdyn.wall._output", False),
    ("from impactdyn import SimulationError", "impactdyn.wall._output", False),
    ("from impactdyn.ble import jsc_verdict", "impactdyn.whipple._case", False),
    ("from impactdyn.wall import run_wall", "impactdyn.cli.whipple", False),
])
def test_layer_rule_catches_every_form(tmp_path, source, module, up):
    path = tmp_path / "mod.py"
    path.write_text(source + "\n", encoding="utf-8")
    assert any(_layer(t) > _layer(module) for t, _ in _imports(path, module) if t != "impactdyn") is up


def test_no_import_cycle():
    """No cycle in the graph of module-level imports (deferred imports inside functions included)."""
    modules = _modules()
    graph = {}
    for module, path in modules.items():
        deps = set()
        for target, _ in _imports(path, module):
            # ``from impactdyn.x import y`` may name a submodule y; the package x is the dependency either way
            while target not in modules and "." in target:
                target = target.rpartition(".")[0]
            if target != module and not module.startswith(target + "."):
                deps.add(target)
        graph[module] = deps
    state, stack, cycles = {}, [], []

    def visit(node):
        state[node] = 1
        stack.append(node)
        for dep in sorted(graph.get(node, ())):
            if dep.startswith(node + "."):  # a package's __init__ re-exporting its own submodules
                continue
            if state.get(dep) == 1:
                cycles.append(" -> ".join(stack[stack.index(dep):] + [dep]))
            elif dep not in state:
                visit(dep)
        stack.pop()
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            visit(node)
    assert cycles == []


def test_every_solver_failure_is_a_simulation_error():
    """The CLI's exit-1 contract ("simulation failed: …") covers every solver's breakdown type."""
    from impactdyn import SimulationError
    from impactdyn.beam import SimulationError as BeamFailure
    from impactdyn.shield import SPHError
    from impactdyn.wall import WallSolverError

    assert all(issubclass(kind, SimulationError) for kind in (BeamFailure, SPHError, WallSolverError))
