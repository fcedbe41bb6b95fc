"""The package's import structure (docs/ARCHITECTURE.md): imports go one way.

Infrastructure → data model → ``io`` → solver packages → ``whipple`` → ``cli``
(:data:`LAYERS`): a module imports only its own layer and those below.  The load checks run
in a fresh interpreter, so what a module loads is what it alone needs.
"""

from __future__ import annotations

import ast
import json
import pathlib
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
            if base.startswith("impactdyn"):
                found += [(base, node.lineno)]
                # ``from impactdyn.pkg import _mod`` imports the private module impactdyn.pkg._mod
                found += [(f"{base}.{a.name}", node.lineno) for a in node.names if a.name.startswith("_")]
    return found


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
        pkg = module.split(".")[1] if module.count(".") >= 1 else ""
        for target, line in _imports(path, module):
            parts = target.split(".")
            if len(parts) >= 3 and parts[2].startswith("_") and parts[1] != pkg:
                bad.append(f"{path.relative_to(SRC.parent)}:{line}: {target}")
    assert bad == []


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
