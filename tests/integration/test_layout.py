"""The package's layout holds: wings from bottom to top, each importing only wings below it, no import circle,
no module over 600 lines, and ``import cadartifact`` loading the standard library only (docs/design.md).

Every import counts, the ones inside functions too (a late import is still a dependency); imports under
``if TYPE_CHECKING:`` do not (a type named in an annotation, never imported at run time).
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

from cadartifact.testing.paths import ROOT

PACKAGE = ROOT / "cadartifact"

#: The wings, bottom to top: a module may import its own wing and the wings before it. The package's
#: ``__init__`` and ``__main__`` are its front door (the lazy public API), above every wing.
WINGS = (
    ("errors", "dependencies", "registry"),  # the error hierarchy, require(), live views: standard library only
    ("execution",),  # settings, executors, the child process, face sharing's rounds, the Dask connection
    ("numerics",),  # tensor products, exact B-spline bases, the operator cache, read-only arrays
    ("theory",),  # the paper: symbols, the scheme catalogue, spectral responses
    ("net",),  # the data model: ControlNet
    ("exchange",),  # files <-> nets, and the reader child
    ("analysis",),  # frames, intent, fields, the measured road, pieces, the budget, the run's settings
    ("advice",),  # the density search, its verification, the scheme comparison
    ("runs",),  # many faces and files: records, the documents, face sharing, repeated faces
    ("gate",),  # verdicts, policy, cache, cluster, reports, progress
    ("viz",),  # maps, heatmaps, the HTML report
    ("cq",),  # the CadQuery hook
    ("cli",),  # the command line
    ("testing",),  # test support for tests/ and benchmarks/: may import every wing, imported by none
)
RANK = {name: k for k, names in enumerate(WINGS) for name in names}
STDLIB_ONLY = ("errors", "dependencies", "registry")
FRONT_DOOR = ("__init__", "__main__")
MAX_LINES = 600


def _modules() -> dict[str, Path]:
    out = {}
    for path in PACKAGE.rglob("*.py"):
        parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def _type_checking_only(tree: ast.AST) -> set[int]:
    """ids of the import nodes inside ``if TYPE_CHECKING:`` blocks."""
    skip = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and getattr(node.test, "id", getattr(node.test, "attr", None)) == "TYPE_CHECKING":
            skip.update(id(n) for stmt in node.body for n in ast.walk(stmt))
    return skip


def imports(module: str, path: Path, known: set[str]) -> set[str]:
    """The package's modules that ``module`` imports (absolute names; a package's ``from . import x`` of a
    submodule counts as that submodule)."""
    tree = ast.parse(path.read_text())
    skip = _type_checking_only(tree)
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    found = set()
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if not target.startswith("cadartifact"):
                continue
            subs = [f"{target}.{a.name}" for a in node.names if f"{target}.{a.name}" in known]
            found.update(subs or [target])
        elif isinstance(node, ast.Import):
            found.update(a.name for a in node.names if a.name.startswith("cadartifact"))
    found.discard(module)
    return found


def wing(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


MODULES = _modules()
GRAPH = {m: imports(m, p, set(MODULES)) for m, p in MODULES.items()}


def test_every_module_is_in_a_wing():
    lost = sorted(m for m in MODULES if wing(m) not in RANK and m.split(".")[-1] not in FRONT_DOOR
                  and m != "cadartifact")
    assert not lost, f"modules outside every wing (add them to a wing folder or to WINGS): {lost}"


@pytest.mark.parametrize("module", sorted(m for m in MODULES if wing(m) in RANK))
def test_imports_go_down_only(module):
    here = RANK[wing(module)]
    up = sorted(t for t in GRAPH[module]
                if t != "cadartifact" and wing(t) in RANK and RANK[wing(t)] > here)
    assert not up, f"{module} (wing {wing(module)!r}) imports from a higher wing: {up}"
    front = sorted(t for t in GRAPH[module] if t.split(".")[-1] == "__main__")
    assert not front, f"{module} imports the command line's entry: {front}"


def _circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]
    sys.setrecursionlimit(max(10000, sys.getrecursionlimit()))

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in graph:
                continue
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in graph:
        if v not in index:
            visit(v)
    return out


def test_no_module_of_the_package_imports_its_test_support():
    """``cadartifact.testing`` sits above the command line and the front door: only tests and benchmarks use it."""
    users = sorted(m for m, targets in GRAPH.items() if wing(m) != "testing"
                   and any(t == "cadartifact.testing" or t.startswith("cadartifact.testing.") for t in targets))
    assert not users, f"modules of the package importing cadartifact.testing: {users}"


def test_no_import_circles():
    # the package's own __init__ files are left out: a package importing its submodules is no circle
    graph = {m: {t for t in ts if MODULES[t].name != "__init__.py"} for m, ts in GRAPH.items()
             if MODULES[m].name != "__init__.py"}
    assert _circles(graph) == []


def test_the_checker_sees_circles_and_climbs():
    """The two checks above, on a made-up graph: they would fail where they should."""
    assert _circles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert RANK["analysis"] > RANK["exchange"] > RANK["net"] > RANK["numerics"]
    assert RANK["testing"] == max(RANK.values())


@pytest.mark.parametrize("module", sorted(m for m in MODULES if wing(m) in STDLIB_ONLY))
def test_the_base_imports_the_standard_library_only(module):
    tree = ast.parse(MODULES[module].read_text())
    outside = set()
    for node in ast.walk(tree):
        names = [a.name for a in node.names] if isinstance(node, ast.Import) else \
            [node.module] if isinstance(node, ast.ImportFrom) and not node.level and node.module else []
        outside.update(n.split(".")[0] for n in names if n.split(".")[0] not in sys.stdlib_module_names)
    assert not outside, f"{module} imports {sorted(outside)}"


def _named_modules(path: Path) -> set[str]:
    """The package's modules named in ``path``'s string constants (``"cadartifact.x.y"``, ``"cadartifact.x:f"``),
    docstrings left out (a reference for the reader is no dependency)."""
    import re

    tree = ast.parse(path.read_text())
    docs = {id(node.body[0].value) for node in ast.walk(tree)
            if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body
            and isinstance(node.body[0], ast.Expr) and isinstance(node.body[0].value, ast.Constant)}
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docs:
            # a document's version ("cadartifact.gate/3") names no module
            found.update(re.findall(r"\bcadartifact(?:\.\w+)+(?![\w/])", node.value))
    return found


@pytest.mark.parametrize("module", sorted(m for m in MODULES if wing(m) in RANK))
def test_no_module_names_a_higher_wing_in_a_string(module):
    """A module imported by name (a child's ``"module:function"``, its idle imports) is a dependency the import
    check cannot see: the higher wing passes such names down instead."""
    here = RANK[wing(module)]
    up = sorted(n for n in _named_modules(MODULES[module]) if wing(n) in RANK and RANK[wing(n)] > here)
    assert not up, f"{module} (wing {wing(module)!r}) names a higher wing's module in a string: {up}"


def test_the_string_check_sees_a_name(tmp_path):
    """The check above, on a made-up module: it finds a name in a string, not in a docstring."""
    f = tmp_path / "m.py"
    f.write_text('"""See cadartifact.gate.run."""\nX = ("cadartifact.runs.face_sharing", "cadartifact.gate.run:f", "cadartifact.gate/3")\n')
    assert _named_modules(f) == {"cadartifact.runs.face_sharing", "cadartifact.gate.run"}


def test_no_module_over_600_lines():
    long = {str(p.relative_to(PACKAGE.parent)): n for p in MODULES.values()
            if (n := len(p.read_text().splitlines())) > MAX_LINES}
    assert not long, f"modules over {MAX_LINES} lines: {long}"


def test_import_cadartifact_loads_the_standard_library_only():
    code = ("import sys, cadartifact, cadartifact.exchange, cadartifact.cli, cadartifact.cli.prestart, "
            "cadartifact.testing.paths; "
            "print(' '.join(sorted(m for m in sys.modules if m.split('.')[0] in "
            "('numpy', 'OCP', 'cadquery', 'pyvista', 'vtk', 'matplotlib', 'trimesh', 'typer', 'rich'))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert out == "", f"importing the front door, the exchange wing, the CLI's start or the test paths loaded: {out}"
