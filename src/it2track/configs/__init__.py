"""The example configuration files shipped inside the package.

Each ``*.toml`` file of this folder is a *packaged config*, named by its stem:

============== ==============================================================================
name           what it configures
============== ==============================================================================
paper          the study ``it2track reproduce`` runs by default (the defaults of
               :class:`it2track.experiments.study.StudyConfig`)
sweep          an example sweep for ``it2track sweep``
optimize       the FoU optimisation of ``it2track optimize``
sweep_dc_motor a sweep of the paper's controllers holding a DC motor's shaft angle (a
               ``[plant]`` table of ``kind = "lti"``; see the plants guide)
============== ==============================================================================

Every ``--config`` option of the command line takes a file or one of these names
(``it2track sweep --config sweep --out runs/sweep``), and ``it2track config show NAME
[--out FILE]`` prints one or writes a copy to edit. They ship with the package, so these
commands work from any folder after ``pip install``.

Examples
--------
>>> from it2track import configs
>>> configs.names()
('optimize', 'paper', 'sweep', 'sweep_dc_motor')
>>> configs.path("paper").name
'paper.toml'
"""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["names", "path", "resolve", "text"]

_HERE = Path(__file__).resolve().parent


def names() -> tuple[str, ...]:
    """The names of the packaged configs, sorted."""
    return tuple(sorted(p.stem for p in _HERE.glob("*.toml")))


def path(name: str) -> Path:
    """The installed file of the packaged config ``name``.

    Parameters
    ----------
    name : str
        One of :func:`names`.

    Returns
    -------
    pathlib.Path
        The file inside the installed package (read it, do not edit it: copy it with
        ``it2track config show NAME --out FILE``).

    Raises
    ------
    ValueError
        If ``name`` is not a packaged config; the message lists the names.
    """
    if not isinstance(name, str) or name not in names():
        raise ValueError(f"{name!r} is not a packaged config; the names are "
                         f"{', '.join(names())}")
    return _HERE / f"{name}.toml"


def text(name: str) -> str:
    """The text of the packaged config ``name`` (see :func:`path`).

    Parameters
    ----------
    name : str
        One of :func:`names`.

    Returns
    -------
    str

    Raises
    ------
    ValueError
        If ``name`` is not a packaged config.
    """
    return path(name).read_text(encoding="utf-8")


def resolve(value: str) -> Path:
    """What a ``--config`` value means: an existing file, else a packaged config's name.

    A file of that name wins (so a config file called ``paper`` in the current folder is
    read, not the packaged one); a value that is neither is an error naming both readings.

    Parameters
    ----------
    value : str
        A file path, or the name of a packaged config (``paper``, ``sweep``, ``optimize``).

    Returns
    -------
    pathlib.Path
        The file to read (the user's path as given, or the packaged file).

    Raises
    ------
    ValueError
        If ``value`` is empty, is a folder, or is neither an existing file nor a name.
    """
    if not isinstance(value, str) or not value:
        raise ValueError(f"{value!r} is empty: give a TOML file or one of the packaged "
                         f"configs {', '.join(names())}")
    given = Path(value)
    if os.path.lexists(given):
        if given.is_dir():
            raise ValueError(f"{value!r} is a folder, not a TOML file")
        return given
    if value in names():
        return path(value)
    raise ValueError(f"{value!r}: no such file, and not a packaged config (the names are "
                     f"{', '.join(names())}; `it2track config show NAME --out FILE` writes "
                     "one out to edit)")
