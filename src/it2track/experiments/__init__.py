"""The paper's scenarios, Monte Carlo studies, sweeps and FoU optimisation. Returns data;
never plots (figures live in :mod:`it2track.report`)."""

from .specs import ConfigError, ControllerKind, ControllerSpec

__all__ = ["ConfigError", "ControllerKind", "ControllerSpec"]
