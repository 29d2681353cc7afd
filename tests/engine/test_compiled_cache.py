"""The compiled kernels' disk cache works from a wheel install (non-editable) in a fresh venv.

Builds a wheel of this checkout, installs it (no dependencies) into a new virtual environment
whose dependencies come from this environment's site-packages (on PYTHONPATH), and runs a
small simulation twice, each time in a fresh process with ``NUMBA_CACHE_DIR`` unset: the first
compiles and writes numba's cache next to the installed modules, the second loads it (cache
hits, no misses) and gets the same numbers.
"""

import json
import os
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

CHILD = """
import json
import numpy as np
import it2track
from it2track.paper import heading_fls
from it2track.tracking import FuzzyHeadingController, LoopConfig, RunTable, simulate_metrics
from it2track.tracking import straight
from it2track.tracking import _jit
m = simulate_metrics([FuzzyHeadingController(fls=heading_fls(0.2))], [straight()],
                     RunTable(0, 0, 0.1, np.arange(3)), LoopConfig(duration=0.5))
stats = _jit.loop.stats
print(json.dumps({"file": it2track.__file__, "ISE": m["ISE"].tolist(),
                  "hits": sum(stats.cache_hits.values()),
                  "misses": sum(stats.cache_misses.values())}))
"""


@pytest.mark.slow
def test_cache_from_a_wheel_install_in_a_fresh_venv(tmp_path):
    wheels = tmp_path / "wheels"
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation",
                    "-q", "-w", str(wheels), str(ROOT)], check=True, capture_output=True)
    (wheel,) = wheels.glob("it2track-*.whl")
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    python = venv / "bin" / "python"
    subprocess.run([sys.executable, "-m", "pip", "--python", str(python), "install", "-q",
                    "--no-deps", str(wheel)], check=True, capture_output=True)
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
    env["PYTHONPATH"] = sysconfig.get_paths()["purelib"]  # numpy, numba, scipy ... from here
    runs = []
    for _ in range(2):
        out = subprocess.run([str(python), "-c", CHILD], env=env, check=True,
                             capture_output=True, text=True, cwd=tmp_path)  # fmt: skip
        runs.append(json.loads(out.stdout.strip().splitlines()[-1]))
    first, second = runs
    assert Path(first["file"]).is_relative_to(venv), first["file"]  # the wheel's copy
    assert first["misses"] > 0 and first["hits"] == 0, first
    assert second["hits"] > 0 and second["misses"] == 0, second
    assert second["ISE"] == first["ISE"]
    installed = Path(first["file"]).parent
    assert list(installed.rglob("_jit*.nbi")), "no numba cache index next to the modules"
