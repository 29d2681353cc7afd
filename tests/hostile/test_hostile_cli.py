"""Bad input on the command line, each case in its own subprocess (``python -m it2track``) in
its own folder: exit status 1 or 2, no traceback, a message naming the option (or file) and
the value, no hang (every process has a timeout), and nothing in the folder written, changed
or deleted -- device nodes, FIFOs and symlinks included.

The subprocesses run two at a time from one fixture, so the suite's wall time stays small;
what click itself validates (ranges, choices) and what the in-process suites already cover
file by file is not repeated here.
"""

from __future__ import annotations

import os
import stat
import subprocess
import sys
import textwrap
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import pytest
from hostile_helpers import BINARY, make_device_link, make_fifo, snapshot

import it2track

TIMEOUT = 120  # seconds per case; a hang fails its case instead of the suite

SWEEP = """
[sweep]
seeds = 2
noise_std = 0.1
trajectories = "straight"

[simulation]
duration = 0.5

[[controllers]]
kind = "flc"
"""

OPTIMIZE = """
[optimize]
objective = "ISE"
train_seeds = 2
holdout_seeds = { start = 100, count = 2 }
noise_std = 0.05
trajectories = ["straight"]
"""


@dataclass(frozen=True)
class Case:
    args: tuple[str, ...]
    needles: tuple[str, ...]
    files: tuple[tuple[str, str], ...] = ()  # extra (name, text) written before the run


CASES: dict[str, Case] = {}


def case(name: str, args: str | list[str], *needles: str, **files: str) -> None:
    argv = args.split() if isinstance(args, str) else args
    CASES[name] = Case(tuple(argv), needles, tuple(files.items()))


def sweep_with(old: str, new: str) -> str:
    text = textwrap.dedent(SWEEP)
    return text.replace(old, new, 1) if old else text + "\n" + new + "\n"


SIM = ["simulate", "--duration", "0.5"]
# -- simulate -------------------------------------------------------------------------------
case("sim-ts-1e-7", "simulate --ts 1e-7", "--ts 1e-07", "memory")
case("sim-noise-negative", [*SIM, "--noise-std", "-1"], "--noise-std", "-1")
case("sim-noise-1e308", [*SIM, "--noise-std", "1e308"], "--noise-std", "1e+308", "largest")
case("sim-seed-22-digits", [*SIM, "--seed", "1234567890123456789012"], "--seed",
     "1234567890123456789012", "2**63 - 1")
case("sim-seed-negative", [*SIM, "--seed", "-1"], "--seed -1")
case("sim-base-seed-negative", [*SIM, "--base-seed", "-1"], "--base-seed -1", "seed=-1")
case("sim-fou-5", [*SIM, "--fou", "5"], "fou=5.0", "1.6")
case("sim-pd-negative-kp", [*SIM, "--controller", "pd", "--kp", "-1"], "kp=-1.0")
case("sim-pd-negative-kd", [*SIM, "--controller", "pd", "--kd", "-1"], "kd=-1.0")
case("sim-pd-with-fou", [*SIM, "--controller", "pd", "--fou", "0.3"], "--fou",
     "does not apply to --controller pd")
case("sim-ke-zero", [*SIM, "--ke", "0"], "ke=0.0", "> 0")
case("sim-ts-not-whole", [*SIM, "--ts", "0.003"], "--ts 0.003", "whole number")
case("sim-noise-rate-1e15", [*SIM, "--noise-rate", "1e15"], "--noise-rate", "noise samples")
case("sim-noise-power-huge", [*SIM, "--noise-power", "1e308"], "--noise-power", "1e+06")
case("sim-trace-empty", [*SIM, "--trace", ""], "--trace", "empty")
case("sim-trace-dev-full", [*SIM, "--trace", "/dev/full"], "--trace /dev/full",
     "character device")
case("sim-trace-folder", [*SIM, "--trace", "folder"], "--trace", "folder")
case("sim-trace-fifo", [*SIM, "--trace", "fifo.csv"], "--trace fifo.csv", "FIFO")
case("sim-trace-symlink", [*SIM, "--trace", "link.csv"], "--trace link.csv", "symbolic link")
case("sim-trace-no-folder", [*SIM, "--trace", "missing/run.csv"], "--trace", "missing",
     "does not exist")
case("sim-controller-file-fifo", [*SIM, "--controller-file", "fifo.t2fis"],
     "--controller-file fifo.t2fis", "FIFO")
case("sim-controller-file-binary", [*SIM, "--controller-file", "binary.toml"],
     "--controller-file binary.toml", "binary")
case("sim-controller-file-zero", [*SIM, "--controller-file", "zero.toml"], "zero.toml",
     "character device")
case("sim-trajectory-unknown", [*SIM, "--trajectory", "nope"], "--trajectory nope")
case("sim-trajectory-fifo", [*SIM, "--trajectory", "fifo.csv"], "--trajectory fifo.csv",
     "FIFO")
case("sim-trajectory-binary", [*SIM, "--trajectory", "binary.csv"], "binary.csv", "binary")
case("sim-plant-unknown", [*SIM, "--plant", "gazebo"], "--plant gazebo", "kinematic, mujoco")
case("sim-friction-kinematic", [*SIM, "--friction", "wet"], "--friction", "--plant mujoco")
case("sim-friction-word", [*SIM, "--plant", "mujoco", "--friction", "snowy"],
     "--friction 'snowy'", "dry, wet, icy")
case("sim-friction-1e400", [*SIM, "--plant", "mujoco", "--friction", "1e400"],
     "--friction 1e400", "finite")
case("sim-friction-negative", [*SIM, "--plant", "mujoco", "--friction", "-0.5"],
     "--friction -0.5", "(0, 1000]")
# -- sweep ----------------------------------------------------------------------------------
OUT = ["--out", "out", "--no-progress"]
case("sweep-config-binary", ["sweep", "--config", "binary.toml", *OUT], "binary.toml",
     "binary")
case("sweep-config-fifo", ["sweep", "--config", "fifo.toml", *OUT], "fifo.toml", "FIFO")
case("sweep-config-dev-zero", ["sweep", "--config", "zero.toml", *OUT], "zero.toml",
     "character device")
case("sweep-out-empty", ["sweep", "--config", "sweep.toml", "--out", ""], "--out", "empty")
case("sweep-out-is-a-file", ["sweep", "--config", "sweep.toml", "--out", "binary.csv"],
     "--out", "binary.csv")
case("sweep-scheduler-no-port", ["sweep", "--config", "sweep.toml", *OUT, "--scheduler",
                                 "foo"], "--scheduler", "'foo'", "port")
case("sweep-tls-without-tls", ["sweep", "--config", "sweep.toml", *OUT, "--scheduler",
                               "tcp://127.0.0.1:1", "--tls-cert", "sweep.toml"], "tls://")
case("sweep-duration-1e9", ["sweep", "--config", "bad.toml", *OUT], "bad.toml",
     "duration=1000000000.0", "GiB", bad=sweep_with("duration = 0.5", "duration = 1e9"))
case("sweep-noise-1e308", ["sweep", "--config", "bad.toml", *OUT], "noise_std", "1e+308",
     bad=sweep_with("noise_std = 0.1", "noise_std = [0.1, 1e308]"))
case("sweep-seed-22-digits", ["sweep", "--config", "bad.toml", *OUT], "seeds",
     "1234567890123456789012", bad=sweep_with("seeds = 2", "seeds = [1234567890123456789012]"))
case("sweep-pd-with-fou", ["sweep", "--config", "bad.toml", *OUT], "fou=0.2", "kind 'pd'",
     bad=sweep_with('kind = "flc"', 'kind = "pd"\nkp = 3.0\nfou = 0.2'))
case("sweep-pd-no-gains", ["sweep", "--config", "bad.toml", *OUT], "kind 'pd' needs",
     bad=sweep_with('kind = "flc"', 'kind = "pd"'))
case("sweep-file-with-fou", ["sweep", "--config", "bad.toml", *OUT], "fou=0.2", "kind 'file'",
     bad=sweep_with('kind = "flc"', 'kind = "file"\npath = "good.toml"\nfou = 0.2'))
case("sweep-file-fifo", ["sweep", "--config", "bad.toml", *OUT], "fifo.t2fis", "FIFO",
     bad=sweep_with('kind = "flc"', 'kind = "file"\npath = "fifo.t2fis"'))
# -- optimize -------------------------------------------------------------------------------
case("optimize-config-binary", ["optimize", "--config", "binary.toml", *OUT], "binary.toml",
     "binary")
case("optimize-out-empty", ["optimize", "--config", "opt.toml", "--out", ""], "--out", "empty",
     opt=textwrap.dedent(OPTIMIZE))
case("optimize-objective", ["optimize", "--config", "opt.toml", *OUT], "opt.toml", "ISEE",
     opt=textwrap.dedent(OPTIMIZE).replace('"ISE"', '"ISEE"'))
case("optimize-scheduler", ["optimize", "--config", "opt.toml", *OUT, "--scheduler", "h:x"],
     "--scheduler", "'h:x'", opt=textwrap.dedent(OPTIMIZE))
# -- reproduce ------------------------------------------------------------------------------
REP = ["reproduce", "--no-progress", "--out", "results"]
case("reproduce-config-binary", [*REP, "--config", "binary.toml"], "binary.toml", "binary")
case("reproduce-config-fifo", [*REP, "--config", "fifo.toml"], "fifo.toml", "FIFO")
case("reproduce-config-latin1", [*REP, "--config", "latin1.toml"], "latin1.toml", "UTF-8")
case("reproduce-out-empty", ["reproduce", "--quick", "--out", ""], "--out", "empty")
case("reproduce-out-under-a-file", ["reproduce", "--quick", "--out", "binary.csv/results"],
     "--out binary.csv/results", "cannot create")
case("reproduce-out-holds-a-folder", ["reproduce", "--quick", "--out", "prev"],
     "metrics.csv exists and is not a regular file", prev_note="")
case("reproduce-scheduler-no-port", [*REP, "--scheduler", "foo"], "--scheduler", "'foo'")
# --mcu-grid: at most the benchmark's 61 (its time grows with the square); only with a measurement
case("reproduce-mcu-grid-62", [*REP, "--mcu-grid", "62"], "--mcu-grid", "62", "2<=x<=61")
case("reproduce-mcu-grid-1", [*REP, "--mcu-grid", "1"], "--mcu-grid", "1 is not", "2<=x<=61")
case("reproduce-mcu-grid-negative", [*REP, "--mcu-grid", "-1"], "--mcu-grid", "-1", "2<=x<=61")
case("reproduce-mcu-grid-abc", [*REP, "--mcu-grid", "abc"], "--mcu-grid", "'abc'", "integer")
case("reproduce-mcu-grid-no-mcu", [*REP, "--mcu-grid", "21", "--no-mcu"], "--mcu-grid 21",
     "--no-mcu turns it off")
case("reproduce-mcu-grid-quick", [*REP, "--quick", "--mcu-grid", "21"], "--mcu-grid 21",
     "--quick turns it off", "add --mcu")
case("reproduce-mathtext-label", [*REP, "--config", "study.toml"], "study.toml",
     "\\\\undefinedmacro", "cannot be drawn",
     study='[[controllers]]\nkind = "flc"\nlabel = "$\\\\undefinedmacro{x}$"\n')
case("reproduce-mathtext-file-name", [*REP, "--config", "study.toml"], "cannot be drawn",
     study='[[controllers]]\nkind = "file"\npath = "$\\\\bad{x}$.toml"\n')
case("reproduce-same-csv-name", [*REP, "--config", "study.toml"], "a/p.csv", "b/p.csv",
     "would share", study='[study]\ntrajectories = ["a/p.csv", "b/p.csv"]\n')
case("reproduce-seeds-1e9", [*REP, "--config", "study.toml"], "seeds=1000000000", "memory",
     study="[study]\nseeds = 1000000000\n")
case("reproduce-noise-1e308", [*REP, "--config", "study.toml"], "noise_levels", "1e+308",
     study="[study]\nnoise_levels = [0.0, 1e308]\n")
case("reproduce-pd-with-fou", [*REP, "--config", "study.toml"], "fou=0.2", "kind 'pd'",
     study='[[controllers]]\nkind = "pd"\nkp = 2.0\nfou = 0.2\n')
# -- fuzzy-system files ---------------------------------------------------------------------
case("fis-show-fifo", "fis show fifo.t2fis", "fifo.t2fis", "FIFO")
case("fis-show-binary", "fis show binary.toml", "binary.toml", "binary")
case("fis-eval-fifo", "fis eval fifo.t2fis 0 0", "fifo.t2fis", "FIFO")
case("fis-convert-to-fifo", "fis convert good.toml fifo.fis", "fifo.fis", "FIFO")
case("fis-convert-to-symlink", "fis convert good.toml link.fis", "link.fis", "symbolic link")
case("surface-points", "surface good.toml --out s.png --points 100000", "points=100000",
     "GiB")
case("surface-out-empty", ["surface", "good.toml", "--out", ""], "empty")
case("surface-fifo", "surface fifo.t2fis --out s.png", "fifo.t2fis", "FIFO")


def _prepare(folder: Path, c: Case) -> None:
    folder.mkdir()
    (folder / "binary.toml").write_bytes(BINARY)
    (folder / "binary.csv").write_bytes(BINARY)
    (folder / "latin1.toml").write_bytes(b"# caf\xe9\n" + textwrap.dedent(SWEEP).encode())
    (folder / "sweep.toml").write_text(textwrap.dedent(SWEEP))
    (folder / "victim.txt").write_text("precious")
    (folder / "link.csv").symlink_to("victim.txt")
    (folder / "link.fis").symlink_to("victim.txt")
    (folder / "folder").mkdir()
    for name in ("fifo.toml", "fifo.t2fis", "fifo.csv", "fifo.fis"):
        make_fifo(folder / name)
    make_device_link(folder / "zero.toml")
    it2track.save(it2track.heading_fls(0.2), folder / "good.toml")
    it2track.save(it2track.heading_fls(0.2), folder / "$\\bad{x}$.toml")
    for sub, direction in (("a", "1,1,0\n2,2,0\n3,3,0\n"), ("b", "1,0,1\n2,0,2\n3,0,3\n")):
        (folder / sub).mkdir()
        (folder / sub / "p.csv").write_text("t,x,y\n0,0,0\n" + direction)
    (folder / "prev" / "metrics.csv").mkdir(parents=True)  # a folder where a result goes
    (folder / "prev" / "metrics.csv" / "mine.txt").write_text("the user's")
    for name, text in c.files:
        suffix = ".txt" if name.endswith("note") else ".toml"
        (folder / (name + suffix)).write_text(text)


@dataclass(frozen=True)
class Outcome:
    returncode: int | None
    stdout: str
    stderr: str
    before: dict[str, tuple[str, bytes | None]]
    after: dict[str, tuple[str, bytes | None]]


def _run(folder: Path, c: Case) -> Outcome:
    before = snapshot(folder)
    env = {**os.environ, "IT2TRACK_MEMORY_LIMIT": "4G", "MPLBACKEND": "Agg",
           "COLUMNS": "200"}
    try:
        proc = subprocess.run(
            [sys.executable, "-m", "it2track", *c.args], cwd=folder, env=env,
            capture_output=True, text=True, timeout=TIMEOUT, stdin=subprocess.DEVNULL,
        )  # fmt: skip
        code, out, err = proc.returncode, proc.stdout, proc.stderr
    except subprocess.TimeoutExpired as exc:  # a hang: fails the case
        code, out, err = None, str(exc.stdout or ""), str(exc.stderr or "")
    return Outcome(code, out, err, before, snapshot(folder))


@pytest.fixture(scope="module")
def outcomes(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Outcome]:
    root = tmp_path_factory.mktemp("hostile-cli")
    folders = {}
    for name, c in CASES.items():
        folders[name] = root / name
        _prepare(folders[name], c)
    with ThreadPoolExecutor(max_workers=2) as pool:
        futures = {name: pool.submit(_run, folders[name], c) for name, c in CASES.items()}
        return {name: f.result() for name, f in futures.items()}


@pytest.mark.parametrize("name", list(CASES))
def test_bad_command_line_is_a_clear_error(outcomes: dict[str, Outcome], name: str) -> None:
    c, o = CASES[name], outcomes[name]
    shown = f"exit {o.returncode}\nstdout: {o.stdout}\nstderr: {o.stderr}"
    assert o.returncode is not None, f"hang (killed after {TIMEOUT} s)\n{shown}"
    assert o.returncode in (1, 2), shown
    assert "Traceback" not in o.stderr + o.stdout, shown
    message = " ".join(o.stderr.split())
    for needle in c.needles:
        assert needle in message, f"{needle!r} missing\n{shown}"
    assert o.after == o.before, f"files changed: {set(o.after) ^ set(o.before)}\n{shown}"


def test_device_nodes_survive() -> None:
    """(Run after the cases above) ``--trace /dev/full`` must not have replaced the device."""
    if os.path.exists("/dev/full"):
        assert stat.S_ISCHR(os.stat("/dev/full").st_mode)
