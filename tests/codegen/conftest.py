"""Shared pieces of the code-generation tests: random systems and cached host builds."""

from __future__ import annotations

import pytest
from codegen_helpers import skip_without

from it2track.codegen import RealType, generate_c
from it2track.codegen.host import HostLibrary, build_host_library


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
