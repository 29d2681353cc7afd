"""What a wheel carries and what the install guide promises, checked without building one
(``.ci/check_wheel.py`` builds and installs a wheel and runs README's commands from another
folder).

- every non-Python file under ``src/it2track`` is matched by a ``package-data`` pattern, so it
  ships (a template or config left out works in a clone and fails after ``pip install .``);
- no wheel or other build artefact is committed;
- the install guide names every runtime dependency;
- the project metadata names its authors and carries classifiers.
"""

from __future__ import annotations

import fnmatch
import re
import subprocess
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
PACKAGE = ROOT / "src" / "it2track"


def _data_patterns() -> list[str]:
    return PYPROJECT["tool"]["setuptools"]["package-data"]["it2track"]


def test_every_data_file_of_the_package_ships():
    patterns = _data_patterns()
    unshipped = []
    for path in PACKAGE.rglob("*"):
        rel = path.relative_to(PACKAGE).as_posix()
        if (path.is_dir() or path.suffix in (".py", ".pyc", ".nbi", ".nbc")
                or "__pycache__" in path.parts):
            continue
        if not any(fnmatch.fnmatch(rel, p) and rel.count("/") == p.count("/")
                   for p in patterns):
            unshipped.append(rel)
    assert unshipped == [], f"not in [tool.setuptools.package-data]: {unshipped}"
    assert "configs/*.toml" in patterns


def test_the_packaged_configs_are_what_the_patterns_ship():
    shipped = sorted(p.name for p in (PACKAGE / "configs").glob("*.toml"))
    assert shipped == ["optimize.toml", "paper.toml", "sweep.toml", "sweep_dc_motor.toml"]
    assert not (ROOT / "configs").exists(), "the configs live in src/it2track/configs only"


def _tracked_files() -> list[str]:
    try:
        proc = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True,
                              timeout=60, check=False)
    except (OSError, subprocess.TimeoutExpired):
        proc = None
    if proc is None or proc.returncode != 0:
        pytest.skip("not a git checkout (or git is missing: apt-get install git)")
    return proc.stdout.splitlines()


def test_no_wheel_or_build_artefact_is_committed():
    artefacts = [f for f in _tracked_files()
                 if f.endswith((".whl", ".tar.gz", ".egg", ".so", ".pyc", ".nbi", ".nbc"))
                 or f.startswith(("build/", "dist/"))]
    assert artefacts == []


def test_the_install_guide_names_every_runtime_dependency():
    guide = (ROOT / "docs" / "guide" / "install.md").read_text(encoding="utf-8").lower()
    names = [re.match(r"[A-Za-z0-9_.-]+", d).group(0) for d in PYPROJECT["project"][
        "dependencies"]]
    assert len(names) >= 8
    missing = [n for n in names if n.lower() not in guide]
    assert missing == [], f"docs/guide/install.md does not name {missing}"


def test_metadata_has_authors_and_classifiers():
    project = PYPROJECT["project"]
    assert project["authors"] == [{"name": "it2track developers"}]
    classifiers = project["classifiers"]
    assert "Programming Language :: Python :: 3.11" in classifiers
    assert f"Programming Language :: Python :: {project['requires-python'][2:]}" in classifiers
    assert len(set(classifiers)) == len(classifiers) and classifiers == sorted(classifiers)
