import os

from hypothesis import HealthCheck, settings

os.environ.setdefault("MPLBACKEND", "Agg")

# The machine running the tests is shared and noisy: no per-example deadlines (a slow example
# is not a failure); counterexamples are printed so a CI failure can be replayed.
settings.register_profile(
    "it2track", deadline=None, print_blob=True, suppress_health_check=[HealthCheck.too_slow]
)
settings.load_profile("it2track")
