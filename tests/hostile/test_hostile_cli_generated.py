"""Generated bad input: every option and argument of every command, each given each hostile
value of its kind -- empty, NaN, +-inf, 1e308, -1, 0, a word where a number goes; a binary
file, a FIFO, a folder, a dangling symlink or a device where an input file goes; a read-only
folder, a dangling symlink, a FIFO, a device or a file of the user's where an output goes.

The options are read from the commands themselves (click's parameters), so a new option is
fuzzed without a new line here; a new command needs its base invocation in :data:`BASE`
(:func:`test_every_command_is_fuzzed` says so). Each case runs in-process (``CliRunner``) in a
fresh folder, with a time limit, and the work a command would start (simulation, sweep,
optimisation, the study) replaced by a sentinel: a case that reaches it was accepted.

Verdicts: a value that can never be valid (empty, NaN, inf, 1e308, a word for a number, any
hostile file or folder) must be refused -- exit status 1 or 2, no traceback, the option (or
argument) and the value named, and the folder exactly as it was. ``-1`` and ``0`` may be
legitimate for some options: refused cleanly or accepted, never a traceback.
"""

from __future__ import annotations

import contextlib
import os
import signal
import textwrap
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import click
import pytest
from click.testing import CliRunner
from hostile_helpers import BINARY, make_device_link, make_fifo, snapshot, unwritable_folder

import it2track
from it2track.cli.main import main
from it2track.cli.options import RealRange

TIME_LIMIT = 60  # seconds per case: a hang fails its case

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

#: command path -> argv of a valid invocation; ``{name}`` marks where an argument goes, with
#: its valid value in :data:`ARGUMENTS`.
BASE: dict[str, list[str]] = {
    "simulate": ["simulate", "--duration", "0.1"],
    "reproduce": ["reproduce", "--quick", "--no-progress", "--out", "out"],
    "sweep": ["sweep", "--config", "sweep.toml", "--out", "out", "--no-progress"],
    "optimize": ["optimize", "--config", "opt.toml", "--out", "out", "--no-progress"],
    "fis show": ["fis", "show", "{file}"],
    "fis convert": ["fis", "convert", "{source}", "{target}"],
    "fis eval": ["fis", "eval", "{file}", "{values}", "0"],
    "surface": ["surface", "{file}", "--points", "5", "--out", "s.png"],
    "export c": ["export", "c", "--paper", "0.2", "--out", "C"],
    "config show": ["config", "show", "{name}"],
    "compile": ["compile"],  # (no parameter to fuzz: listed so a new one would be)
}
ARGUMENTS = {"file": "good.toml", "source": "good.toml", "target": "new.fis", "values": "0",
             "name": "paper"}
#: Output files a command writes into its folder: planted as the user's for "foreign".
FOREIGN = {"reproduce": "claims.md", "sweep": "results.csv", "optimize": "optimize.md",
           "export c": "it2.c"}

NUMBERS = {"empty": "", "nan": "nan", "inf": "inf", "-inf": "-inf", "huge": "1e308",
           "minus-one": "-1", "zero": "0", "word": "abc"}
STRINGS = {"empty": "", "nan": "nan", "huge": "1e308", "word": "abc"}
INPUTS = {"empty": "", "binary": "binary.toml", "fifo": "fifo.toml", "folder": "folder",
          "dangling": "dangling.toml", "device": "zero.toml"}
OUTPUT_FILES = {"empty": "", "fifo": "fifo{suffix}", "folder": "folder",
                "dangling": "dangling{suffix}", "read-only": "{ro}/x{suffix}",
                "foreign": "mine{suffix}", "device": "/dev/full"}
OUTPUT_FOLDERS = {"empty": "", "a-file": "binary.toml", "read-only": "{ro}/out",
                  "dangling": "dangling-folder", "foreign": "theirs"}
#: (command, parameter, value label) accepted by design, and why.
LEGITIMATE = {
    ("fis eval", "VALUES", "huge"): "an input outside its universe is clipped to it "
                                    "(DESIGN.md sec. 2): 1e308 is the universe's top",
}


class WorkStarted(Exception):
    """The sentinel: the command got past its checks and started its work."""


@dataclass(frozen=True)
class Case:
    command: str
    param: str  # the option (--out) or argument (FILE) as messages name it
    kind: str
    label: str
    value: str
    argv: tuple[str, ...]
    must_refuse: bool


def _walk(cmd: click.Command, path: tuple[str, ...] = ()) -> Iterator[tuple[str, click.Command]]:
    if isinstance(cmd, click.Group):
        for name, sub in sorted(cmd.commands.items()):
            yield from _walk(sub, (*path, name))
    else:
        yield " ".join(path), cmd


def _kind(command: str, param: click.Parameter) -> str:
    t = param.type
    if isinstance(t, click.Path):
        if getattr(t, "exists", False) or param.name == "system":
            return "input"
        if not t.file_okay or (command == "export c" and param.name == "out_text"):
            return "output-folder"
        return "output-file"
    if isinstance(t, RealRange | click.types.FloatParamType | click.types.IntParamType
                  | click.FloatRange | click.IntRange):
        return "number"
    if isinstance(t, click.Choice):
        return "choice"
    if param.name == "values":
        return "number"
    return "string"


def _name(param: click.Parameter) -> str:
    if isinstance(param, click.Option):
        return param.opts[0]
    return (param.name or "").upper()


def _argv(command: str, param: click.Parameter, value: str) -> list[str]:
    base = list(BASE[command])
    if isinstance(param, click.Argument):
        if command == "export c":  # SYSTEM replaces --paper
            return ["export", "c", value, "--out", "C"]
        slot = "{" + (param.name or "") + "}"
        base = [value if a == slot else a for a in base]
    else:
        base += [param.opts[0], value]
    return [ARGUMENTS.get(a[1:-1], a) if a.startswith("{") and a.endswith("}") else a
            for a in base]


def _suffix(command: str, param: click.Parameter) -> str:
    return {"surface": ".png", "fis convert": ".fis"}.get(command, ".csv")


def _cases() -> list[Case]:
    out = []
    for command, cmd in _walk(main):
        if command not in BASE:
            continue
        for param in cmd.params:
            if isinstance(param, click.Option) and param.is_flag:
                continue
            kind = _kind(command, param)
            values = {"number": NUMBERS, "string": STRINGS, "choice": STRINGS,
                      "input": INPUTS, "output-file": OUTPUT_FILES,
                      "output-folder": OUTPUT_FOLDERS}[kind]
            for label, value in values.items():
                value = value.replace("{suffix}", _suffix(command, param))
                must = kind != "string" and label not in ("minus-one", "zero")
                must = must or label == "empty"
                if kind == "choice":
                    must = value not in (param.type.choices if isinstance(
                        param.type, click.Choice) else ())
                if (command, _name(param), label) in LEGITIMATE:
                    must = False
                out.append(Case(command, _name(param), kind, label, value,
                                tuple(_argv(command, param, value)), must))
    return out


CASES = _cases()


def _prepare(folder: Path, case: Case, ro: Path) -> None:
    folder.mkdir()
    (folder / "sweep.toml").write_text(textwrap.dedent(SWEEP))
    (folder / "opt.toml").write_text(textwrap.dedent(OPTIMIZE))
    it2track.save(it2track.heading_fls(0.2), folder / "good.toml")
    (folder / "binary.toml").write_bytes(BINARY)
    (folder / "folder").mkdir()
    make_fifo(folder / "fifo.toml")
    make_device_link(folder / "zero.toml")
    for name in ("dangling.toml", "dangling-folder", *(f"dangling{s}" for s in
                                                       (".csv", ".png", ".fis"))):
        (folder / name).symlink_to(folder / "no-such-target")
    for suffix in (".csv", ".png", ".fis"):
        make_fifo(folder / f"fifo{suffix}")
        (folder / f"mine{suffix}").write_bytes(b"the user's own file\n")
    theirs = folder / "theirs"
    theirs.mkdir()
    (theirs / FOREIGN.get(case.command, "results.csv")).write_text("the user's own file\n")


@contextlib.contextmanager
def _time_limit(seconds: int) -> Iterator[None]:
    def expire(signum: int, frame: Any) -> None:
        raise TimeoutError(f"no answer within {seconds} s")

    old = signal.signal(signal.SIGALRM, expire)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


@pytest.fixture
def no_work(monkeypatch: pytest.MonkeyPatch) -> None:
    """Replace the work every long-running command starts by the sentinel."""
    import it2track.experiments.optimize as optimize
    import it2track.experiments.sweep as sweep
    import it2track.report.render as render
    import it2track.tracking as tracking

    def started(*args: object, **kwargs: object) -> None:
        raise WorkStarted

    for module, name in ((tracking, "simulate"), (sweep, "run_sweep"),
                         (optimize, "run_optimization"), (render, "FigureRenderer")):
        monkeypatch.setattr(module, name, started)
    monkeypatch.setenv("MPLBACKEND", "Agg")


@pytest.mark.parametrize("case", CASES, ids=[f"{c.command}-{c.param}-{c.label}"
                                             for c in CASES])
def test_generated_bad_input(case: Case, tmp_path: Path, no_work: None,
                             monkeypatch: pytest.MonkeyPatch) -> None:
    ro = unwritable_folder(tmp_path)
    if ro is None and "{ro}" in case.value:
        pytest.skip("no folder here refuses writes to this user")
    argv = [a.replace("{ro}", str(ro)) for a in case.argv]
    value = case.value.replace("{ro}", str(ro))
    folder = tmp_path / "case"
    _prepare(folder, case, ro or tmp_path)
    monkeypatch.chdir(folder)
    before = snapshot(folder)
    with _time_limit(TIME_LIMIT):
        result = CliRunner().invoke(main, argv)
    shown = f"{' '.join(argv)}\nexit {result.exit_code}\n{result.output}"
    exc = result.exception
    assert not isinstance(exc, TimeoutError), f"hang\n{shown}"
    accepted = isinstance(exc, WorkStarted) or result.exit_code == 0
    if not accepted and exc is not None and not isinstance(exc, SystemExit):
        import traceback

        trace = "".join(traceback.format_exception(exc))
        pytest.fail(f"traceback for the user\n{shown}\n{trace}")
    if accepted:
        assert not case.must_refuse, f"accepted a value it must refuse\n{shown}"
        return
    assert result.exit_code in (1, 2), shown
    message = " ".join(result.output.split())
    if case.kind in ("input", "output-file", "output-folder") and value:
        assert value in message, f"the value {value!r} is not named\n{shown}"
    else:
        assert case.param in message, f"{case.param} is not named\n{shown}"
        inapplicable = "does not apply" in message or "applies only" in message
        if value and not inapplicable:  # (an option refused as such needs no value)
            assert any(v in message for v in _spellings(value)), (
                f"the value {value!r} is not named\n{shown}")
    assert snapshot(folder) == before, f"files changed\n{shown}"


def _spellings(value: str) -> set[str]:
    """``value`` as typed, or the same number as Python prints it (``1e308`` -> ``1e+308``)."""
    out = {value}
    with contextlib.suppress(ValueError):
        number = float(value)
        out |= {repr(number), f"{number:g}"}
    return out


def test_every_command_is_fuzzed() -> None:
    """A command without a base invocation here would escape the generator."""
    missing = sorted(name for name, _ in _walk(main) if name not in BASE)
    assert not missing, f"add a base invocation to BASE for: {missing}"
    assert len(CASES) > 300 and os.path.basename(__file__).startswith("test_hostile")
