import os
import time

import pytest
from hypothesis import HealthCheck, settings

os.environ.setdefault("MPLBACKEND", "Agg")
# A command run by a test compiles the kernels in its own process when the cache is cold (no
# background process outliving the test); tests/cli/test_first_run.py turns it back on.
os.environ.setdefault("IT2TRACK_BACKGROUND_COMPILE", "0")

# The machine running the tests is shared and noisy: no per-example deadlines (a slow example
# is not a failure); counterexamples are printed so a CI failure can be replayed.
settings.register_profile(
    "it2track", deadline=None, print_blob=True, suppress_health_check=[HealthCheck.too_slow]
)
settings.load_profile("it2track")


# -- collection: say what happens (pytest -q hides its "collecting N items" line) -----------
_COLLECT: dict = {}


def pytest_collection(session):
    """Collecting imports the package and its dependencies for the doctests: seconds with
    nothing on screen under ``-q``. A stage line, and a count while it runs on a terminal."""
    reporter = session.config.pluginmanager.get_plugin("terminalreporter")
    if reporter is None or session.config.option.verbose >= 0:
        return
    now = time.monotonic()
    _COLLECT.update(reporter=reporter, start=now, last=now, files=set())
    reporter.write("collecting the tests (imports numpy, scipy, matplotlib, numba) ...",
                   flush=True)


def pytest_collectreport(report):
    reporter = _COLLECT.get("reporter")
    if reporter is None:
        return
    if report.nodeid.endswith((".py", ".md")):
        _COLLECT["files"].add(report.nodeid)
    now = time.monotonic()
    if reporter.isatty() and now - _COLLECT["last"] >= 0.5:
        _COLLECT["last"] = now
        reporter.rewrite(f"collecting the tests: {len(_COLLECT['files'])} files, "
                         f"{now - _COLLECT['start']:.0f} s", erase=True, flush=True)


def pytest_collection_finish(session):
    reporter = _COLLECT.pop("reporter", None)
    if reporter is None:
        return
    line = (f"collected {len(session.items)} tests from {len(_COLLECT['files'])} files in "
            f"{time.monotonic() - _COLLECT['start']:.1f} s")
    if reporter.isatty():
        reporter.rewrite(line, erase=True)
        reporter.write("\n")
    else:
        reporter.write(" " + line + "\n", flush=True)


@pytest.fixture(autouse=True, scope="session")
def _no_physics_check_by_default():
    """``it2track reproduce`` runs the MuJoCo physics check by default when MuJoCo is
    installed, and the verdicts on the chip when the AVR toolchain is (minutes each); tests
    that do not ask for them run without them (``tests/cli/test_reproduce_physics.py`` sets
    its own small check, ``tests/cli/test_reproduce_chip.py`` passes ``--chip``). Session
    scope: module-scoped fixtures that run ``reproduce`` are set up before any
    function-scoped one."""
    import it2track.cli.reproduce as cli

    patch = pytest.MonkeyPatch()
    patch.setattr(cli, "_default_physics_check", lambda: None)
    patch.setattr(cli, "_default_chip", lambda: False)
    yield
    patch.undo()
