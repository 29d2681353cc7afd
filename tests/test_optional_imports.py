"""Optional dependencies are imported only by the modules that need them (DESIGN.md sec. 1),
read from the source (every import statement, module level or inside a function)."""

from __future__ import annotations

import ast
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src" / "it2track"

#: Optional package -> the only modules (relative to src/it2track) that may import it, whether
#: by ``import pkg`` or through :func:`it2track._extras.require`.
ALLOWED = {"control": {"plant/control.py", "io/control.py"}}


def _imports(path: Path) -> set[str]:
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names.update(a.name.split(".")[0] for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names.add(node.module.split(".")[0])
        elif (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
              and node.func.id == "require" and node.args
              and isinstance(node.args[0], ast.Constant)):
            names.add(str(node.args[0].value))
    return names


def test_optional_packages_are_imported_only_where_needed() -> None:
    found: dict[str, set[str]] = {pkg: set() for pkg in ALLOWED}
    for path in SRC.rglob("*.py"):
        rel = path.relative_to(SRC).as_posix()
        for pkg in _imports(path) & set(ALLOWED):
            found[pkg].add(rel)
    for pkg, allowed in ALLOWED.items():
        assert found[pkg] == allowed, f"{pkg!r} imported by {sorted(found[pkg] - allowed)}"
