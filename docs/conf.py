"""Sphinx configuration of the it2track documentation site.

Build it from the repository root (the built site is not committed)::

    python -m sphinx -W --keep-going -j auto -b html docs docs/_build/html

``tests/test_docs.py`` runs the same build, warnings as errors, in a scratch copy.
"""

from __future__ import annotations

import ast
import importlib
import importlib.util
import inspect
import os
from pathlib import Path
from typing import ClassVar

import sphinx.ext.autosummary
from docutils import nodes
from docutils.statemachine import StringList
from sphinx.directives.other import TocTree
from sphinx.util.docutils import SphinxDirective

import it2track

HERE = Path(__file__).resolve().parent

project = "it2track"
author = "the it2track authors"
copyright = "the it2track authors, MIT licence"
release = version = it2track.__version__

extensions = [
    "myst_parser",
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
templates_path = ["_templates"]
exclude_patterns = ["_build", "**/*.png", "auto_examples/*.ipynb", "auto_examples/*.py",
                    "auto_examples/*.zip", "auto_examples/*.md5"]

# -- MyST (Markdown pages) -------------------------------------------------------------------
myst_enable_extensions = ["colon_fence", "dollarmath", "deflist"]
myst_heading_anchors = 3

# -- API reference: autosummary over the whole package, numpydoc for the docstrings ---------
autosummary_generate = True
autosummary_imported_members = False  # each object once, in the module that defines it
autodoc_default_options = {"member-order": "bysource"}
autodoc_typehints = "none"  # the numpydoc Parameters sections carry the types and shapes
numpydoc_show_class_members = False  # the class template lists members itself
numpydoc_class_members_toctree = False
numpydoc_attributes_as_param_list = True

# -- Examples gallery: every script in examples/ runs headless and its output is shown ------
os.environ.setdefault("MPLBACKEND", "Agg")
sphinx_gallery_conf = {
    "examples_dirs": str(HERE.parent / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r".*\.py$",  # execute every example, not only plot_*.py
    "download_all_examples": False,
    "remove_config_comments": True,
    "plot_gallery": "True",
    "abort_on_example_error": True,
    "within_subsection_order": "FileNameSortKey",
    "image_scrapers": ("matplotlib",),
    "reset_modules": ("matplotlib",),
    "show_memory": False,
    "write_computation_times": False,
    "capture_repr": (),
}

# -- HTML --------------------------------------------------------------------------------------
html_theme = "alabaster"
html_title = f"it2track {release}"
html_static_path: list[str] = []
html_theme_options = {
    "description": "Interval type-2 fuzzy control of a differential-drive robot",
    "fixed_sidebar": True,
    "show_relbars": True,
    "page_width": "1120px",
    "sidebar_width": "230px",
}
html_sidebars = {"**": ["about.html", "navigation.html", "relations.html", "searchbox.html"]}


def _prefer_submodules(import_by_name):
    """Make autosummary resolve a dotted name to the *module* when one exists.

    autosummary tries ``package.attribute`` before ``package.module``, so a submodule whose
    package re-exports a function of the same name (``it2track.tracking.simulate``, the module
    and the function) would get the function's page and lose its own. Names that are not
    modules resolve as before.
    """

    def resolve(name: str, *args, **kwargs):
        if name.split(".")[0] == "it2track":
            try:
                spec = importlib.util.find_spec(name)
            except (ImportError, ValueError):
                spec = None
            if spec is not None:
                return importlib.import_module(name), None, name
        return import_by_name(name, *args, **kwargs)

    return resolve


sphinx.ext.autosummary._import_by_name = _prefer_submodules(sphinx.ext.autosummary._import_by_name)


class GuideTocTree(TocTree):
    """A toctree of every page in one folder, in a preferred order.

    The entries are the preferred reading order; pages of ``:folder:`` that it does not name
    follow alphabetically, and named pages that do not exist (yet) are left out. So a guide
    page written later, by anyone, appears in the guide without editing the index.
    """

    option_spec: ClassVar = {**TocTree.option_spec,
                             "folder": lambda arg: arg.strip().strip("/")}

    def run(self):
        env = self.state.document.settings.env
        folder = self.options.pop("folder", None)
        wanted = [line.strip() for line in self.content if line.strip()]
        existing = [name for name in wanted if name in env.found_docs]
        if folder is not None:
            existing += sorted(
                name for name in env.found_docs
                if name.startswith(folder + "/") and name.count("/") == folder.count("/") + 1
                and name not in existing
            )
        self.content = StringList(existing, source="guide-toctree")
        return super().run()


class CliReference(SphinxDirective):
    """Every ``it2track`` command and subcommand, one section each, with its ``--help`` text
    as click renders it when the site is built (so a new command appears by itself)."""

    def run(self):
        import click

        from it2track.cli.main import main

        sections: list[nodes.Node] = []

        def walk(command: click.Command, path: list[str], parent: click.Context | None):
            ctx = click.Context(command, info_name=path[-1], parent=parent,
                                terminal_width=92, max_content_width=92)
            name = " ".join(path)
            text = command.get_help(ctx)
            section = nodes.section(ids=[nodes.make_id(name)],
                                    names=[nodes.fully_normalize_name(name)])
            section += nodes.title(name, name)
            section += nodes.literal_block(text, text, language="text")
            self.state.document.note_implicit_target(section)
            sections.append(section)
            if isinstance(command, click.Group):
                for sub in command.list_commands(ctx):
                    walk(command.get_command(ctx, sub), [*path, sub], ctx)

        walk(main, ["it2track"], None)
        return sections


class ScriptDocstrings(SphinxDirective):
    """One section per script of a repository folder (e.g. ``benchmarks``): its file name and
    its module docstring, parsed as reST (so a script added later appears by itself)."""

    required_arguments = 1

    def run(self):
        folder = HERE.parent / self.arguments[0]
        sections: list[nodes.Node] = []
        for script in sorted(folder.glob("*.py")):
            self.env.note_dependency(str(script))
            doc = ast.get_docstring(ast.parse(script.read_text(encoding="utf-8"))) or ""
            name = f"{self.arguments[0]}/{script.name}"
            section = nodes.section(ids=[nodes.make_id(name)],
                                    names=[nodes.fully_normalize_name(name)])
            section += nodes.title(name, "", nodes.literal(name, name))
            section += self.parse_text_to_nodes(f"```{{eval-rst}}\n{doc}\n```\n")
            self.state.document.note_implicit_target(section)
            sections.append(section)
        return sections


def _skip_foreign_inherited(app, what, name, obj, skip, options):
    """Leave out methods a class inherits from Python itself (``int.to_bytes`` of an IntEnum,
    ``Exception.add_note``): Python documents those, and their docstrings are not reST."""
    if inspect.isbuiltin(obj) or inspect.ismethoddescriptor(obj):
        return True  # implemented in C: not ours (it2track is pure Python)
    if callable(obj) and not isinstance(obj, type):
        owner = getattr(obj, "__objclass__", None)
        module = getattr(obj, "__module__", None) or getattr(owner, "__module__", None)
        if module is not None and module.split(".")[0] != "it2track":
            return True
    return None


def setup(app):
    app.add_directive("guide-toctree", GuideTocTree)
    app.add_directive("cli-reference", CliReference)
    app.add_directive("script-docstrings", ScriptDocstrings)
    app.connect("autodoc-skip-member", _skip_foreign_inherited)
