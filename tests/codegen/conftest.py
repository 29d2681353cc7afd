"""Shared pieces of the code-generation tests: random systems and cached host builds."""

from __future__ import annotations

import pytest

from it2track.codegen import RealType, generate_c
from it2track.codegen.host import HostLibrary, build_host_library
from it2track.codegen.tools import missing_tools


def skip_without(*tools: str) -> None:
    """Skip (never silently) when a tool is missing, naming its Debian package."""
    missing = missing_tools(tools)
    if missing:
        pytest.skip(f"needs {', '.join(tools)}: install the Debian package(s) "
                    f"{', '.join(missing)}")


@pytest.fixture(scope="session")
def build_dir(tmp_path_factory):
    return tmp_path_factory.mktemp("c-builds")


@pytest.fixture(scope="session")
def host_lib(build_dir):
    """``host_lib(system, real=..., prefix=...) -> HostLibrary`` (compiled once per code)."""
    skip_without("gcc")
    cache: dict[str, HostLibrary] = {}

    def make(system, real=RealType.DOUBLE, prefix="it2"):
        code = generate_c(system, real=real, prefix=prefix)
        key = code.digest()
        if key not in cache:
            cache[key] = HostLibrary(code, build_host_library(code, build_dir))
        return cache[key]

    return make
