"""Optional dependencies: import them where needed, and say which extra installs them.

Standard library only. ``control`` (python-control) comes with ``pip install
'it2track[control]'``, ``mujoco`` with ``'it2track[mujoco]'``, ``dask.distributed`` with
``'it2track[dask]'``.
"""

from __future__ import annotations

import importlib
from types import ModuleType

__all__ = ["MissingExtraError", "require"]


class MissingExtraError(ImportError):
    """An optional package a feature needs is not installed; the message names the extra."""


def require(module: str, extra: str, feature: str) -> ModuleType:
    """Import ``module`` or raise :class:`MissingExtraError` naming ``extra``.

    Parameters
    ----------
    module : str
        The package to import (``"control"``).
    extra : str
        The it2track extra that installs it (``"control"``).
    feature : str
        What needs it, for the message (``"a python-control plant"``).

    Returns
    -------
    module
        The imported package.

    Raises
    ------
    MissingExtraError
        If the import fails (an ``ImportError``).
    """
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise MissingExtraError(
            f"{feature} needs the optional package {module!r}, which is not installed: "
            f"pip install 'it2track[{extra}]'"
        ) from exc
