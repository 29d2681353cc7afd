"""The command line leaves without the interpreter's final garbage collections."""

from __future__ import annotations

import subprocess
import sys

_PROBE = """
import atexit, gc, sys
atexit.register(lambda: print("freeze count at exit:", gc.get_freeze_count() > 0))
from it2track.cli.main import main
try:
    main(sys.argv[1:], prog_name="it2track")
except SystemExit as exc:
    print("exit code:", exc.code)
"""


def _probe(*args: str) -> list[str]:
    proc = subprocess.run([sys.executable, "-c", _PROBE, *args], capture_output=True,
                          text=True, check=True, timeout=120)
    return [line for line in proc.stdout.splitlines() if line.startswith(("freeze", "exit"))]


def test_a_command_freezes_the_collector_at_exit():
    """Every command registers gc.freeze at exit (0.5 s of a 7 s ``reproduce --quick`` went
    to collecting a finished process's objects); the command's own exit code stands."""
    assert _probe("config", "show", "paper") == ["exit code: 0", "freeze count at exit: True"]
    assert _probe("config", "show", "nonsense") == ["exit code: 2",  # click's usage error
                                                     "freeze count at exit: True"]


def test_the_hook_is_registered_once_per_process():
    from it2track.cli import main as cli

    before = list(cli._EXIT_HOOK)
    cli._skip_final_collection()
    cli._skip_final_collection()
    assert cli._EXIT_HOOK == [True]
    assert before in ([], [True])
