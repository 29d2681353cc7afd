"""Imported by the figure workers' fork server only (its first preload, see :mod:`.render`):
when the server's last client has gone, end it at once.

The server's loop ends with ``SystemExit`` once no process holds its "alive" pipe (the command
and every worker it forked have exited); the interpreter would then tear down everything the
server imported -- matplotlib, numpy, scipy, the figures -- for about 0.3 s on a quiet machine
and 1-2 s on a busy one, holding the command's standard output and error open all along: a
pipeline or a ``subprocess.run(capture_output=True)`` reading them waited that long after the
command itself had finished. Nothing is left to do in the server then: the workers it forked
have exited (they end with ``os._exit`` and never run this), and it has nothing to write.
"""

from __future__ import annotations

import atexit
import os
import sys


def _exit_now() -> None:
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (AttributeError, OSError, ValueError):
            pass
    os._exit(0)


atexit.register(_exit_now)
