import os

from hypothesis import HealthCheck, settings

os.environ.setdefault("MPLBACKEND", "Agg")

# The machine running the tests is shared and noisy: no per-example deadlines (a slow example
# is not a failure); counterexamples are printed so a CI failure can be replayed.
settings.register_profile(
    "it2track", deadline=None, print_blob=True, suppress_health_check=[HealthCheck.too_slow]
)
settings.load_profile("it2track")


import pytest  # noqa: E402


@pytest.fixture(autouse=True)
def _no_physics_check_by_default(monkeypatch):
    """``it2track reproduce`` runs the MuJoCo physics check by default when MuJoCo is
    installed (minutes of simulation); tests that do not ask for it run without it
    (``tests/cli/test_reproduce_physics.py`` sets its own small check)."""
    import it2track.cli.reproduce as cli

    monkeypatch.setattr(cli, "_default_physics_check", lambda: None)
