"""The options of ``attach``, checked once for both couplings (CPU and MJX).

Every mistake is a :class:`~mudrft.MudrftError` that names the option: a body name that is
not a string, the world body, a foot list of the wrong length, a flag that is not a bool
(``implicit="no"`` was read as True), ``bottom_stiffness`` without ``bottom`` (it was
ignored).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from ..._validation import (
    MudrftError,
    check_number,
    nonnegative_number,
    positive_number,
)

if TYPE_CHECKING:
    import mujoco

__all__ = ["AttachOptions", "check_attach_options", "check_count", "check_data"]

#: Defaults of the hard bottom's penalty (D67): stiffness [N/m], damping [N s/m].
BOTTOM_STIFFNESS, BOTTOM_DAMPING = 1e5, 2e3


class AttachOptions(NamedTuple):
    """The checked options: body names, one foot (or None) per body, and the rest in SI."""

    bodies: list[str]
    feet: list[Any]
    surface: float  # [m]
    bottom: float | None  # [m]
    bottom_stiffness: float  # [N/m]
    bottom_damping: float  # [N s/m]
    implicit: bool
    mobility: str
    resolution: int
    geoms: list[str | int | None]  # the foot's geom of each body, None: derived (D124)
    lookahead: bool = False  # read the other forces' acceleration ahead (D162)


def check_count(name: str, value: object) -> int:
    """An integer >= 1 (not a bool, not 2.5), or an error naming ``name``."""
    if type(value) is int and value >= 1:  # the common case, cheaply (a loop's nstep)
        return value
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise MudrftError(f"{name} must be an integer >= 1, got {value!r}")
    return int(value)


def check_attach_options(
    model: object,
    bodies: object,
    feet: object,
    *,
    surface: object,
    bottom: object,
    bottom_stiffness: object,
    bottom_damping: object,
    implicit: object,
    mobility: object,
    resolution: object,
    foot_geoms: object = None,
    lookahead: object = False,
) -> AttachOptions:
    """Check ``attach``'s arguments (see :class:`~mudrft.integrations.mujoco.MudBatch`),
    the model (a ``mujoco.MjModel``) first."""
    from ._lazy import _mujoco

    if not isinstance(model, _mujoco().MjModel):
        raise MudrftError(f"model must be a mujoco.MjModel, got {type(model).__name__}")
    names = [bodies] if isinstance(bodies, str) else bodies
    if not isinstance(names, Sequence) or not all(isinstance(b, str) for b in names):
        raise MudrftError(f"bodies must be a body name or a list of names, got {bodies!r}")
    names = list(names)
    if not names:
        raise MudrftError("bodies must name at least one body, got an empty list")
    if len(set(names)) != len(names):
        raise MudrftError(f"bodies must be distinct, got {names}")
    if "world" in names:
        raise MudrftError("bodies cannot include 'world': the mud acts on a body that moves")
    if feet is None or hasattr(feet, "contact_force"):
        feet_list = [feet] * len(names)
    else:
        if isinstance(feet, str) or not isinstance(feet, Sequence):
            raise MudrftError(
                f"feet must be a foot (mudrft.feet), one per body, or None (the geoms), got {feet!r}"
            )
        feet_list = list(feet)
        if len(feet_list) != len(names):
            raise MudrftError(
                f"feet must be one foot or one per body ({len(names)}), got {len(feet_list)}"
            )
    if not isinstance(implicit, (bool, np.bool_)):
        raise MudrftError(f"implicit must be True or False, got {implicit!r}")
    if not isinstance(lookahead, (bool, np.bool_)):
        raise MudrftError(
            "lookahead must be True (read the other forces' acceleration from a look-ahead "
            f"of MuJoCo's step) or False (estimate it from the last step), got {lookahead!r}"
        )
    if mobility not in ("chain", "body"):
        raise MudrftError(f"mobility must be 'chain' or 'body', got {mobility!r}")
    if bottom is None and (bottom_stiffness != BOTTOM_STIFFNESS or bottom_damping != BOTTOM_DAMPING):  # fmt: skip
        raise MudrftError(
            "bottom_stiffness and bottom_damping shape the hard bottom; give its depth with "
            "bottom= (without it they would be ignored)"
        )
    return AttachOptions(
        geoms=_foot_geoms(foot_geoms, names),
        bodies=names,
        feet=feet_list,
        surface=check_number("surface", surface, unit="m"),
        bottom=None if bottom is None else positive_number("bottom", bottom, unit="m"),
        bottom_stiffness=nonnegative_number("bottom_stiffness", bottom_stiffness, unit="N/m"),
        bottom_damping=nonnegative_number("bottom_damping", bottom_damping, unit="N s/m"),
        implicit=bool(implicit),
        mobility=str(mobility),
        resolution=check_count("resolution", resolution),
        lookahead=bool(lookahead),
    )


def _foot_geoms(foot_geoms: object, names: list[str]) -> list[str | int | None]:
    """``foot_geoms``, a mapping ``{body: geom name or id}``, as one entry per body."""
    if foot_geoms is None:
        return [None] * len(names)
    if not isinstance(foot_geoms, Mapping):
        raise MudrftError(
            "foot_geoms must be a mapping {body: geom name}, e.g. "
            f"foot_geoms={{{names[0]!r}: 'foot_geom'}}, got {foot_geoms!r}"
        )
    for body, geom in foot_geoms.items():
        if body not in names:
            raise MudrftError(
                f"foot_geoms names body {body!r}, which is not coupled; the bodies are {names}"
            )
        if isinstance(geom, bool) or not isinstance(geom, (str, int, np.integer)):
            raise MudrftError(f"foot_geoms[{body!r}] must be a geom's name (or id), got {geom!r}")
    return [foot_geoms.get(b) for b in names]


def check_data(model: mujoco.MjModel, data: object) -> None:
    """``data`` must be a ``mujoco.MjData`` of ``model``: one made for another model
    coupled the wrong bodies, or crashed inside MuJoCo (a segmentation fault)."""
    from ._lazy import _mujoco

    if not isinstance(data, _mujoco().MjData):
        raise MudrftError(f"data must be a mujoco.MjData, got {type(data).__name__}")
    got = (data.qpos.size, data.qvel.size, data.xpos.shape[0], data.ctrl.size)
    if got != (model.nq, model.nv, model.nbody, model.nu):
        raise MudrftError(
            f"data was made for another model (nq, nv, nbody, nu = {', '.join(map(str, got))}; "
            f"this model has {model.nq}, {model.nv}, {model.nbody}, {model.nu}): use "
            "mujoco.MjData(model)"
        )
