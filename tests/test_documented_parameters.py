"""Every parameter of the public API is mentioned in its docstring (python-control style)."""

import enum
import importlib
import inspect

import pytest

PACKAGES = ("it2track.fuzzy", "it2track.plant", "it2track.tracking", "it2track.experiments",
            "it2track.io", "it2track.paper", "it2track.codegen")


def public_callables():
    for package in PACKAGES:
        module = importlib.import_module(package)
        for name in module.__all__:
            obj = getattr(module, name)
            if inspect.isclass(obj) and issubclass(obj, enum.Enum):
                continue  # enum "parameters" are the Enum machinery's, not ours
            if inspect.isfunction(obj) or inspect.isclass(obj):
                yield f"{package}.{name}", obj


@pytest.mark.parametrize(("name", "obj"), list(public_callables()), ids=lambda v: str(v))
def test_parameters_are_documented(name, obj):
    try:
        signature = inspect.signature(obj)
    except (TypeError, ValueError):
        pytest.skip(f"{name} has no introspectable signature")
    doc = obj.__doc__ or ""
    missing = [
        p.name for p in signature.parameters.values()
        if p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD) and not p.name.startswith("_")
        and p.name not in ("self", "cls") and p.name not in doc
    ]
    assert not missing, f"{name}: parameters {missing} not mentioned in its docstring"
