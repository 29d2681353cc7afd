"""it2track: interval type-2 fuzzy logic control for differential-drive trajectory tracking."""

from . import fuzzy
from .io import load, save
from .paper import dead_zone_matched_fls, heading_fls

__version__ = "0.1.0"
__all__ = ["__version__", "dead_zone_matched_fls", "fuzzy", "heading_fls", "load", "save"]
