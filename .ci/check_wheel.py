"""Build a wheel, install it into a fresh virtual environment, and run README's commands from a
folder outside the repository: what a user gets from ``pip install .``.

Run from the repository root (a few minutes: the environment installs the dependencies, and
the first simulating command compiles the kernels)::

    python3 .ci/check_wheel.py [--keep] [--full]

Checks that the installed package carries its data (the packaged configs, the report and C
templates) and that every command of README's "Newcomer commands" and "Command line" sections
and its Python examples run with nothing of the clone on the path: the working folder is a
new temporary one, and ``PYTHONPATH`` is unset. ``--full`` runs the default ``reproduce``
(tens of seconds) instead of ``--quick``; ``--keep`` keeps the folder and prints it.
Exit status 0 when every command succeeded.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: README's commands, in the order a newcomer would try them (optional parts left out).
COMMANDS = [
    "it2track --version",
    "python -m it2track --help",
    "it2track compile",
    "it2track simulate --trajectory curved --controller it2 --fou 0.3 --noise-std 0.1 "
    "--seed 4",
    "it2track simulate --json --trace run.csv",
    "it2track config show paper",
    "it2track config show sweep --out my_sweep.toml",
    "it2track sweep --config sweep --out runs/sweep",
    "it2track sweep --config my_sweep.toml --out runs/sweep --resume",
    "it2track optimize --config optimize --out runs/optimize",
    "it2track export c --paper 0.2 --out ctrl/",
    "it2track fis show heading.t2fis",
    "it2track fis convert heading.t2fis heading.toml",
    "it2track fis eval heading.toml 0.3 -0.1",
    "it2track surface heading.t2fis --out heading.png",
    "it2track export c heading.t2fis --out ctrl/ --real float --reducer eiasc --prefix heading",
]


def readme_python_blocks() -> list[str]:
    """README's Python examples that need no file of their own (the "Library" section's)."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    section = text[text.index("## Library in ten lines"):text.index("## Command line")]
    return re.findall(r"```python\n(.*?)```", section, flags=re.S)


def run(cmd: str, *, cwd: Path, env: dict[str, str]) -> tuple[bool, float, str]:
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, shell=True, cwd=cwd, env=env, capture_output=True, text=True,
                          check=False)
    return proc.returncode == 0, time.perf_counter() - t0, proc.stdout + proc.stderr


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--keep", action="store_true", help="keep the temporary folder")
    parser.add_argument("--full", action="store_true", help="the default reproduce, not --quick")
    args = parser.parse_args()
    work = Path(tempfile.mkdtemp(prefix="it2track-wheel-"))
    failures = 0
    try:
        dist = work / "dist"
        subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w",
                        str(dist), str(ROOT)], check=True)
        wheel = next(dist.glob("it2track-*.whl"))
        print(f"built {wheel.name}")
        venv = work / "venv"
        subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
        subprocess.run([str(venv / "bin" / "python"), "-m", "pip", "install", "-q",
                        str(wheel)], check=True)
        env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
        env["PATH"] = f"{venv / 'bin'}{os.pathsep}{env.get('PATH', '')}"
        env["MPLBACKEND"] = "Agg"
        cwd = work / "elsewhere"
        cwd.mkdir()
        heading = ("import it2track; it2track.save(it2track.heading_fls(0.2), "
                   "'heading.t2fis')")
        reproduce = ("it2track reproduce --out results" if args.full
                     else "it2track reproduce --quick --out results")
        steps = [f'python -c "{heading}"', reproduce, *COMMANDS]
        for k, block in enumerate(readme_python_blocks()):
            script = cwd / f"readme_example_{k}.py"
            script.write_text(block)
            steps.append(f"python {script.name}")
        for cmd in steps:
            ok, seconds, output = run(cmd, cwd=cwd, env=env)
            print(f"{'ok  ' if ok else 'FAIL'} {seconds:6.1f} s  {cmd}", flush=True)
            if not ok:
                failures += 1
                print("     " + output[-2000:].replace("\n", "\n     "))
        for name in ("results/report.html", "results/claims.md", "runs/sweep/results.csv",
                     "runs/optimize/optimize.md", "ctrl/it2.h", "ctrl/heading.c",
                     "my_sweep.toml", "heading.png"):
            if not (cwd / name).is_file():
                failures += 1
                print(f"FAIL missing {name}")
    finally:
        if args.keep:
            print(f"kept {work}")
        else:
            shutil.rmtree(work, ignore_errors=True)
    print("every README command works from a wheel install" if failures == 0
          else f"{failures} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
