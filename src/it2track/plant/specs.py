"""Plants named in configuration: ``[plant]`` tables and plant files, never code.

A ``[plant]`` table picks a family by ``kind`` and gives that family's keys:

=============  ======================================================================  ========
kind           plant                                                                   extra
=============  ======================================================================  ========
``kinematic``  the paper's robot (the default; no other keys: the robot's parameters
               come from the configuration's ``[robot]``/simulation settings)
``lti``        a linear plant: ``A, B, C[, D]`` or ``num, den``, optional ``dt``,
               ``x0``, ``input_limits``, names (:class:`~.linear.LinearSpec`)
``mujoco``     the robot in the MuJoCo physics engine (:mod:`.mujoco_plant`)             mujoco
=============  ======================================================================  ========

A nonlinear python-control system cannot be written in a file (it is code): give it from Python,
``LoopConfig(plant=it2track.plant.control.from_control(sys))``.
"""

from __future__ import annotations

import importlib
import os
import tomllib
from collections.abc import Mapping
from typing import Any

from .._files import read_text
from .base import PlantSpec

__all__ = ["PLANT_KINDS", "load_plant", "plant_from_dict"]

#: ``kind`` -> (module, class with ``from_dict(table, *, where)``, pip extra or None).
#: ``kinematic`` has no spec: it is ``LoopConfig.plant = None``.
PLANT_KINDS: dict[str, tuple[str, str, str | None] | None] = {
    "kinematic": None,
    "lti": ("it2track.plant.linear", "LinearSpec", None),
    "mujoco": ("it2track.plant.mujoco_plant", "MujocoSpec", "mujoco"),
}


def plant_from_dict(table: object, *, where: str = "[plant]") -> PlantSpec | None:
    """The plant a ``[plant]`` table describes.

    Parameters
    ----------
    table : dict
        With ``kind`` (one of :data:`PLANT_KINDS`) and that family's keys.
    where : str
        How error messages name the table (file and key).

    Returns
    -------
    PlantSpec or None
        ``None`` for ``kind = "kinematic"`` (the paper's robot).

    Raises
    ------
    ValueError
        For a missing or unknown ``kind``, keys the family does not know, or bad values
        (naming ``where``, the key and the value); for a family whose optional dependency is
        missing, naming the extra to install.
    """
    if not isinstance(table, Mapping):
        raise ValueError(f"{where} must be a table, got {table!r}")
    kind = table.get("kind")
    if kind == "nlsys":
        raise ValueError(f"{where}: kind = 'nlsys' (a nonlinear python-control system) is code "
                         "and cannot be read from a file; give it from Python: "
                         "LoopConfig(plant=it2track.plant.control.from_control(sys))")
    if not isinstance(kind, str) or kind not in PLANT_KINDS:
        raise ValueError(f"{where}: kind={kind!r} must be one of {sorted(PLANT_KINDS)}")
    entry = PLANT_KINDS[kind]
    if entry is None:
        extra = sorted(set(table) - {"kind"})
        if extra:
            raise ValueError(f"{where}: kind = 'kinematic' takes no other keys, got {extra} "
                             "(the robot's parameters are set in the simulation settings)")
        return None
    module_name, class_name, pip_extra = entry
    try:
        module = importlib.import_module(module_name)
    except ModuleNotFoundError as exc:
        if pip_extra is not None and exc.name is not None and not exc.name.startswith("it2track"):
            raise ValueError(f"{where}: kind = {kind!r} needs the optional package {exc.name!r}: "
                             f"pip install 'it2track[{pip_extra}]'") from None
        raise ValueError(f"{where}: kind = {kind!r} is not available in this version of "
                         "it2track") from None
    spec = getattr(module, class_name).from_dict(dict(table), where=where)
    if not isinstance(spec, PlantSpec):  # pragma: no cover - a family's own bug
        raise TypeError(f"{class_name}.from_dict returned {spec!r}, not a PlantSpec")
    return spec


def load_plant(path: str | os.PathLike[str]) -> PlantSpec | None:
    """The plant described by a TOML file: its ``[plant]`` table, or the whole file if it has
    none (a file holding just ``kind = ...`` and the family's keys).

    Parameters
    ----------
    path : str or os.PathLike
        A TOML file (regular, bounded in size, UTF-8).

    Returns
    -------
    PlantSpec or None
        As :func:`plant_from_dict`.

    Raises
    ------
    ValueError
        If the file is not a readable TOML file, has keys besides ``[plant]`` when it has that
        table, or describes no valid plant (the message names the file).
    OSError
        If the file cannot be opened.
    """
    text = read_text(path, what="plant file")
    try:
        data: dict[str, Any] = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{os.fspath(path)}: not valid TOML: {exc}") from None
    if "plant" in data:
        others = sorted(set(data) - {"plant"})
        if others:
            raise ValueError(f"{os.fspath(path)}: unknown key(s) {others} beside [plant]")
        return plant_from_dict(data["plant"], where=f"{os.fspath(path)} [plant]")
    return plant_from_dict(data, where=os.fspath(path))
