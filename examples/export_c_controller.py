"""
Export the controller as C for a microcontroller
=================================================

Export the paper's IT2FLC as C, compile it on this machine and check it against Python: the
same as ``it2track export c --paper 0.2 --out DIR``, through the Python API; then the generated
code is compiled with the host's C compiler (when ``gcc`` is installed) and evaluated through
ctypes on a grid of inputs, inside and outside the universe [-1, 1]^2.

Run: ``python examples/export_c_controller.py``
"""

import tempfile

import numpy as np

import it2track
from it2track.codegen import RealType, generate_c, write_c
from it2track.codegen.tools import missing_tools

fls = it2track.heading_fls(0.2)
with tempfile.TemporaryDirectory() as tmp:
    for real in (RealType.DOUBLE, RealType.FLOAT):
        code = generate_c(fls, real=real, prefix=f"ctrl_{real.value}")
        paths = write_c(code, tmp)
        print(f"{real.value}: wrote {', '.join(p.name for p in paths)} "
              f"({len(code.source.splitlines())} lines of C)")
        if missing_tools(["gcc"]):
            print("  gcc is not installed (Debian package gcc): not compiled")
            continue
        from it2track.codegen.host import HostLibrary, build_host_library

        lib = HostLibrary(code, build_host_library(code, tmp))
        axis = np.linspace(-1.5, 1.5, 61)
        x = np.stack(np.meshgrid(axis, axis), axis=-1).reshape(-1, 2)
        x = x.astype(lib.dtype).astype(np.float64)
        u, yl, yr, status = lib.evaluate(x)
        err = np.max(np.abs(u - fls(x[:, 0], x[:, 1])))
        print(f"  compiled; {len(x)} inputs, all OK: {bool(np.all(status == 0))}, "
              f"max |u_C - u_Python| = {err:.2g} V")
