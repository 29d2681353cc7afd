"""The documentation site builds warning-free and holds what it promises.

The build is the one README gives (``python -m sphinx -W --keep-going -b html docs OUT``), run
on a scratch copy of ``docs/`` and the folders its pages include (``examples/``,
``src/it2track/configs/``, ``benchmarks/``), so that the generated pages (``docs/api/generated``,
``docs/auto_examples``) never land in the work tree. Executing the
gallery runs every example script once more.
"""

from __future__ import annotations

import ast
import importlib.util
import os
import pkgutil
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import it2track

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = sorted((ROOT / "examples").glob("*.py"))
GUIDE = sorted((ROOT / "docs" / "guide").glob("*.md"))

# Warnings whose cause is not obvious from Sphinx's message, and what to do about them.
HINTS = {
    "Inline literal start-string without end-string": (
        "in an '<autosummary>' line: Sphinx cuts a docstring's summary at the first '. ', even "
        "inside ``literal`` text (e.g. ``a ... b``); rephrase that first sentence"),
    "Undefined substitution referenced": "a bare |x| in a docstring is reST substitution "
                                         "syntax: write ``|x|``",
    "Inline emphasis start-string without end-string": "a bare * (e.g. *_meas, x*y) in a "
                                                       "docstring: put it in ``literal``",
    "doesn't have a title": "an example's docstring must start with a title line underlined "
                            "with '='",
    "isn't included in any toctree": "add the page to a toctree (docs/index.md); pages in "
                                     "docs/guide/ are picked up automatically",
}


def public_modules() -> list[str]:
    names = ["it2track"]
    for info in pkgutil.walk_packages(it2track.__path__, "it2track."):
        if not any(part.startswith("_") for part in info.name.split(".")):
            names.append(info.name)
    return names


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Build the site once (about 10-20 s) and return the HTML folder."""
    for package in ("sphinx", "numpydoc", "myst_parser", "sphinx_gallery"):
        if importlib.util.find_spec(package) is None:
            pytest.fail(f"{package} is not installed: the docs extra is part of the test "
                        "extra; run pip install -e '.[test]'", pytrace=False)
    work = tmp_path_factory.mktemp("docs-build")
    generated = shutil.ignore_patterns("_build", "generated", "auto_examples", "__pycache__",
                                       "sg_execution_times.rst", "*.pyc")
    for folder in ("docs", "examples", "src/it2track/configs", "benchmarks"):
        shutil.copytree(ROOT / folder, work / folder, ignore=generated)
    out = work / "html"
    env = {**os.environ, "MPLBACKEND": "Agg"}
    cmd = [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-j", "auto", "-q",
           "-b", "html", str(work / "docs"), str(out)]
    proc = subprocess.run(cmd, cwd=work, env=env, capture_output=True, text=True, timeout=900)
    if proc.returncode != 0:
        log = proc.stderr + proc.stdout
        hints = [f"- {key!r}: {hint}" for key, hint in HINTS.items() if key in log]
        pytest.fail(
            f"sphinx-build failed (exit {proc.returncode}); its warnings:\n{log[-8000:]}\n"
            + ("Hints:\n" + "\n".join(hints) if hints else ""),
            pytrace=False,
        )
    return out


def test_site_builds_with_an_api_page_for_every_public_module(site: Path) -> None:
    missing = []
    for name in public_modules():
        page = site / "api" / "generated" / f"{name}.html"
        # automodule's target: the page documents the module, not a namesake attribute
        # (it2track.tracking.simulate is a module and, re-exported, a function)
        if not page.is_file() or f'id="module-{name}"' not in page.read_text():
            missing.append(name)
    assert not missing, f"modules without their own API page: {missing}"


def test_api_pages_render_numpydoc_sections(site: Path) -> None:
    page = (site / "api" / "generated" / "it2track.tracking.simulate.html").read_text()
    for text in ("simulate_metrics", "LoopConfig", "Parameters", "Returns", "batch_size"):
        assert text in page, f"{text!r} missing from the simulate API page"


def test_every_guide_page_is_built_and_reachable(site: Path) -> None:
    assert GUIDE, "docs/guide/ holds no page"
    index = (site / "index.html").read_text()
    for page in GUIDE:
        assert (site / "guide" / f"{page.stem}.html").is_file(), f"{page.name} not built"
        assert f'href="guide/{page.stem}.html"' in index, f"{page.name} not in the index's toc"


@pytest.mark.parametrize("script", EXAMPLES, ids=lambda p: p.name)
def test_gallery_shows_each_example_with_its_output(site: Path, script: Path) -> None:
    page = site / "auto_examples" / f"{script.stem}.html"
    assert page.is_file(), f"no gallery page for {script.name}"
    html = page.read_text()
    assert "sphx-glr-script-out" in html, f"{script.name}: its printed output is not shown"


@pytest.mark.parametrize("script", EXAMPLES, ids=lambda p: p.name)
def test_example_docstring_starts_with_a_gallery_title(script: Path) -> None:
    doc = ast.get_docstring(ast.parse(script.read_text()), clean=True) or ""
    lines = doc.splitlines()
    assert len(lines) >= 2 and lines[0].strip() and re.fullmatch(r"=+", lines[1]) \
        and len(lines[1]) >= len(lines[0]), (
            f"{script.name}: the docstring must start with a title underlined by '=' (the "
            f"gallery's page title), e.g.\n\"\"\"\nMy example\n==========\n\nWhat it shows.\n"
            f"\"\"\"\nfound: {lines[:2]}")


def _commands(text: str, start: str) -> list[str]:
    return [line.strip() for line in text.splitlines() if line.strip().startswith(start)]


def test_install_guide_and_ci_give_readmes_commands() -> None:
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    guide = (ROOT / "docs" / "guide" / "install.md").read_text(encoding="utf-8")
    for start in ("python3 -m venv .venv && .venv/bin/pip install -e '.[test]'",
                  "python3 -m venv .venv && .venv/bin/pip install -e . &&"):
        ours, theirs = _commands(guide, start), _commands(readme, start)
        assert len(theirs) == 1 and ours == theirs, (
            f"docs/guide/install.md and README.md differ on the command starting {start!r}:\n"
            f"guide:  {ours}\nREADME: {theirs}")
    test_command = _commands(readme, "python3 -m venv .venv && .venv/bin/pip install -e '.[test]'")
    steps = [s.strip() for s in test_command[0].split("&&")][2:]  # after venv and install
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    ci_steps = [line.strip() for line in ci.split("keep in sync", 1)[1].splitlines()[1:]
                if line.strip() and not line.lstrip().startswith("#")]
    assert ci_steps == steps, f".ci/run runs {ci_steps}, README's test command {steps}"
