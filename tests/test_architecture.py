"""The package's shape: no import cycles between its modules, and imports flow down the layers.

Both checks read the source (the AST of every module under ``src/it2track``), not what a test
run happens to import, so an import inside a function counts as much as one at the top.

An **import cycle** is a cycle in the graph whose edges are the import statements that can run:
at module level, inside functions and methods (a lazy import only postpones the cycle to the
first call), under ``try``. Imports under ``if TYPE_CHECKING:`` are left out of this graph:
they never run, they only let an annotation name a collaborator's class. An import names the
module it imports and, for ``from pkg import name``, the package ``pkg`` too (its
``__init__`` runs first); a module's own ancestor packages are left out (they are always
initialised before it, and ``from . import sibling`` is how a package reaches its parts).

The **layers** (DESIGN.md sec. 1) count every import, ``TYPE_CHECKING`` ones too: a type-only
import of a higher layer is still knowledge of it.
"""

from __future__ import annotations

import ast
import itertools
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src"
PACKAGE = "it2track"

#: Which packages each layer must never import (DESIGN.md sec. 1: cli/report -> experiments ->
#: tracking -> fuzzy | plant, and fuzzy and plant know nothing of each other).
FORBIDDEN = {
    "it2track.fuzzy": ("it2track.plant", "it2track.tracking", "it2track.experiments",
                       "it2track.report", "it2track.cli"),
    "it2track.plant": ("it2track.fuzzy", "it2track.tracking", "it2track.experiments",
                       "it2track.report", "it2track.cli"),
    "it2track.tracking": ("it2track.experiments", "it2track.report", "it2track.cli"),
    "it2track.experiments": ("it2track.report", "it2track.cli"),
}
#: Only these packages may import matplotlib.
PLOTTING = ("it2track.report", "it2track.cli")


@dataclass(frozen=True)
class Import:
    """One module named by one import statement."""

    module: str  # the importing module
    target: str  # the module it names (dotted; outside the package: as written)
    path: str  # the importing file, relative to src/
    line: int
    statement: str
    type_only: bool  # under ``if TYPE_CHECKING:``

    def __str__(self) -> str:
        kind = " (under TYPE_CHECKING)" if self.type_only else ""
        return f"{self.path}:{self.line}: {self.statement!r}{kind}"


def _within(name: str, package: str) -> bool:
    return name == package or name.startswith(package + ".")


def _type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def imports_of(module: str, source: str, *, is_package: bool, known: Iterable[str],
               path: str = "") -> list[Import]:
    """Every module of ``known`` (and every outside module) that ``source`` imports."""
    known = set(known)
    base = module.split(".") if is_package else module.split(".")[:-1]
    out: list[Import] = []

    def add(target: str, node: ast.stmt, type_only: bool) -> None:
        if target in known and (target == module or _within(module, target)):
            return  # itself, or one of its own ancestor packages
        out.append(Import(module, target, path, node.lineno, ast.unparse(node), type_only))

    def visit(node: ast.AST, type_only: bool) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.If) and _type_checking(child.test):
                for stmt in child.body:
                    visit_stmt(stmt, True)
                for stmt in child.orelse:
                    visit_stmt(stmt, type_only)
                continue
            visit_stmt(child, type_only)

    def visit_stmt(node: ast.AST, type_only: bool) -> None:
        if isinstance(node, ast.Import):
            for alias in node.names:
                parts = alias.name.split(".")
                names = [".".join(parts[:k]) for k in range(1, len(parts) + 1)]
                for name in names if names[0] == PACKAGE else names[-1:]:
                    add(name, node, type_only)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                anchor = base[: len(base) - (node.level - 1)]
                target = ".".join([*anchor, *([node.module] if node.module else [])])
            else:
                target = node.module or ""
            add(target, node, type_only)
            for alias in node.names:
                if f"{target}.{alias.name}" in known:
                    add(f"{target}.{alias.name}", node, type_only)
        else:
            visit(node, type_only)

    visit(ast.parse(source), False)
    return out


def package_imports(src: Path = SRC) -> tuple[set[str], list[Import]]:
    """The modules of the package and every import statement in them."""
    files: dict[str, tuple[Path, bool]] = {}
    for file in sorted((src / PACKAGE).rglob("*.py")):
        parts = list(file.relative_to(src).with_suffix("").parts)
        is_package = parts[-1] == "__init__"
        files[".".join(parts[:-1] if is_package else parts)] = (file, is_package)
    imports: list[Import] = []
    for name, (file, is_package) in files.items():
        imports += imports_of(name, file.read_text(encoding="utf-8"), is_package=is_package,
                              known=files, path=str(file.relative_to(src)))
    return set(files), imports


def cycles(modules: Iterable[str], imports: Iterable[Import]) -> list[list[Import]]:
    """One cycle (as its import statements) per strongly connected group of modules, among
    the imports that can run (``TYPE_CHECKING`` ones left out)."""
    modules = set(modules)
    edges: dict[str, dict[str, Import]] = {m: {} for m in modules}
    for imp in imports:
        if not imp.type_only and imp.target in modules:
            edges[imp.module].setdefault(imp.target, imp)
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    groups: list[set[str]] = []

    def connect(v: str) -> None:  # Tarjan (the package is small: recursion is fine)
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in edges[v]:
            if w not in index:
                connect(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            group = set()
            while True:
                w = stack.pop()
                on_stack.discard(w)
                group.add(w)
                if w == v:
                    break
            if len(group) > 1:
                groups.append(group)

    for v in sorted(modules):
        if v not in index:
            connect(v)
    out = []
    for group in groups:  # a shortest way back to the first module, within the group
        start = min(group)
        paths = {start: [start]}
        queue = [start]
        while queue:
            v = queue.pop(0)
            for w in sorted(edges[v]):
                if w == start:
                    path = [*paths[v], start]
                    out.append([edges[a][b] for a, b in itertools.pairwise(path)])
                    queue = []
                    break
                if w in group and w not in paths:
                    paths[w] = [*paths[v], w]
                    queue.append(w)
    return out


def layer_violations(imports: Iterable[Import], forbidden: Mapping[str, Sequence[str]],
                     plotting: Sequence[str]) -> list[str]:
    """One sentence per import that goes up a layer, or to matplotlib from below the plots."""
    out = []
    for imp in imports:
        for layer, above in forbidden.items():
            hit = next((p for p in above if _within(imp.module, layer)
                        and _within(imp.target, p)), None)
            if hit is not None:
                out.append(f"{imp}: {layer} must not import {hit} (it imports {imp.target})")
        if _within(imp.target, "matplotlib") and not any(_within(imp.module, p)
                                                          for p in plotting):
            out.append(f"{imp}: only {' and '.join(plotting)} may import matplotlib "
                       f"({imp.module} does)")
    return out


@pytest.fixture(scope="module")
def package() -> tuple[set[str], list[Import]]:
    return package_imports()


def test_no_import_cycle_between_modules(package: tuple[set[str], list[Import]]) -> None:
    modules, imports = package
    found = cycles(modules, imports)
    assert not found, "import cycles (each import statement of the cycle, in order):\n" + \
        "\n".join(" -> ".join(i.module for i in c) + f" -> {c[0].module}\n  "
                  + "\n  ".join(map(str, c)) for c in found)


def test_imports_flow_down_the_layers(package: tuple[set[str], list[Import]]) -> None:
    _, imports = package
    bad = layer_violations(imports, FORBIDDEN, PLOTTING)
    assert not bad, "imports against the layering (DESIGN.md sec. 1):\n" + "\n".join(bad)


def test_the_graph_sees_the_package_as_it_is(package: tuple[set[str], list[Import]]) -> None:
    """The checks above would pass on an empty graph: the graph must hold known imports."""
    modules, imports = package
    assert {"it2track.fuzzy.system", "it2track.experiments.study.runner"} <= modules
    edges = {(i.module, i.target) for i in imports}
    assert ("it2track.tracking.simulate", "it2track.tracking.compiled") in edges  # from . import
    assert ("it2track.fuzzy.sugeno", "it2track.fuzzy.system") in edges  # from .system import
    # inside a function: the CLI imports the study lazily
    assert ("it2track.cli.reproduce", "it2track.experiments.study") in edges
    assert any(i.target == "matplotlib" or i.target.startswith("matplotlib.") for i in imports
               if i.module.startswith("it2track.report"))
    # the package's own ancestors are not edges (every module would be in a cycle with them)
    assert ("it2track.fuzzy.system", "it2track.fuzzy") not in edges
    assert ("it2track.experiments.sweep.plan", "it2track") not in edges


# -- the checks themselves, on made-up packages -----------------------------------------------

FAKE = {"p": ("", True), "p.a": ("from . import b\n", False), "p.q": ("", True)}


def fake_imports(sources: Mapping[str, tuple[str, bool]]) -> tuple[set[str], list[Import]]:
    imports = []
    for name, (text, is_package) in sources.items():
        imports += imports_of(name, text, is_package=is_package, known=sources, path=name)
    return set(sources), imports


@pytest.mark.parametrize(("back", "line"), [
    ("from .a import x\n", 1),  # at module level
    ("def f():\n    from .a import x\n", 2),  # lazily, inside a function
    ("class C:\n    def m(self):\n        import p.a\n", 3),  # in a method, absolute
    ("try:\n    from . import a\nexcept ImportError:\n    pass\n", 2),
    ("from .q import y\nif TYPE_CHECKING:\n    pass\nelse:\n    from .a import x\n", 5),
])
def test_a_cycle_is_found_however_the_import_is_written(back: str, line: int) -> None:
    modules, imports = fake_imports({**FAKE, "p.b": (back, False)})
    found = cycles(modules, imports)
    assert [[(i.module, i.target) for i in c] for c in found] == [[("p.a", "p.b"),
                                                                  ("p.b", "p.a")]]
    assert (found[0][1].path, found[0][1].line) == ("p.b", line)


def test_a_cycle_through_a_package_init_is_found() -> None:
    # p.a imports a name of package p.q, whose __init__ imports p.q.c, which imports p.a
    modules, imports = fake_imports({
        "p": ("", True), "p.a": ("from .q import thing\n", False),
        "p.q": ("from . import c\nthing = 1\n", True), "p.q.c": ("from .. import a\n", False),
    })
    assert [[(i.module, i.target) for i in c] for c in cycles(modules, imports)] == [
        [("p.a", "p.q"), ("p.q", "p.q.c"), ("p.q.c", "p.a")]]


def test_type_checking_imports_make_no_cycle_but_break_the_layers() -> None:
    modules, imports = fake_imports({
        **FAKE, "p.b": ("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n"
                        "    from .a import x\n", False)})
    assert cycles(modules, imports) == []
    bad = layer_violations(imports, {"p.b": ("p.a",)}, ("p.q",))
    assert bad == ["p.b:3: 'from .a import x' (under TYPE_CHECKING): p.b must not import p.a "
                   "(it imports p.a)"]


def test_layer_messages_name_the_offending_import() -> None:
    _, imports = fake_imports({
        "p": ("", True), "p.low": ("import numpy\n\ndef f():\n    import matplotlib.pyplot\n",
                                   False),
        "p.high": ("", True), "p.high.x": ("from ...p import low\n", False),
        "p.lower": ("from .high import x\n", False), "p.q": ("import matplotlib\n", False),
    })
    bad = layer_violations(imports, {"p.low": ("p.high",), "p.lower": ("p.high",)}, ("p.q",))
    assert bad == [
        "p.low:4: 'import matplotlib.pyplot': only p.q may import matplotlib (p.low does)",
        "p.lower:1: 'from .high import x': p.lower must not import p.high (it imports p.high)",
        "p.lower:1: 'from .high import x': p.lower must not import p.high (it imports "
        "p.high.x)",
    ]
    # a layer's name is a package, not a prefix: p.lower (which imports p.high) is not in p.low
    assert layer_violations(imports, {"p.low": ("p.high",)}, ("p",)) == []


#: A module a contributor can hold in their head: above this many lines, split it by concept
#: (issue 18). The largest today is fuzzy/reducers.py.
MAX_MODULE_LINES = 610


def test_no_module_is_too_long_to_hold_in_ones_head() -> None:
    lengths = {p.relative_to(SRC).as_posix(): len(p.read_text(encoding="utf-8").splitlines())
               for p in (SRC / PACKAGE).rglob("*.py")}
    assert len(lengths) > 150  # the walk sees the package (not an empty folder)
    too_long = {name: n for name, n in lengths.items() if n > MAX_MODULE_LINES}
    assert not too_long, f"split these by concept (> {MAX_MODULE_LINES} lines): {too_long}"
