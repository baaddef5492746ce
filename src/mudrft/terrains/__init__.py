"""All terrain models behind one interface (:class:`Terrain`), each constructible with no
arguments and accepted by :func:`mudrft.simulate` in place of the mud.

>>> from mudrft import terrains
>>> [t.name for t in (terrains.Mud(), terrains.GranularRFT(), terrains.RigidGround())]
['mud', 'granular-rft', 'rigid']
"""

from __future__ import annotations

from typing import Any

from .._validation import MudrftError
from ..parameters.base import Mud as MudParameterSets
from ..parameters.registry import paper_mud
from .base import Terrain, TerrainOutput, check_motion
from .granular_rft import GranularRFT
from .granular_rft3d import GranularRFT3D
from .linear import LinearStiffness
from .maxwell import MaxwellMud
from .mud import MudState, MudTerrain, channel_parameters, mud_step
from .rigid import RigidGround

__all__ = [
    "GranularRFT", "GranularRFT3D", "LinearStiffness", "MaxwellMud", "Mud", "MudState",
    "MudTerrain", "RigidGround", "Terrain", "TerrainOutput", "as_terrain", "channel_parameters",
    "check_motion", "mud_step"
]  # fmt: skip


def Mud(water_content: float | MudParameterSets = 0.25, **kw: Any) -> MudTerrain:
    """The mud model as a terrain: ``MudTerrain(paper_mud(water_content), **kw)``.

    Parameters
    ----------
    water_content : float or mudrft.Mud
        Water content [-] of the paper's mud (0.25-0.45), or a parameter set.
    **kw
        Keyword options of :class:`MudTerrain` (``characteristic_length`` [m], ...).

    Examples
    --------
    >>> Mud(0.35).mud.water_content
    0.35
    """
    mud = water_content if isinstance(water_content, MudParameterSets) else paper_mud(water_content)
    return MudTerrain(mud, **kw)


def as_terrain(terrain: MudParameterSets | Terrain) -> Terrain:
    """Accept a :class:`~mudrft.Mud` (wrapped in :class:`~mudrft.MudTerrain`) or any terrain."""
    if isinstance(terrain, MudParameterSets):
        return MudTerrain(terrain)
    if isinstance(terrain, Terrain) and not isinstance(terrain, type):
        return terrain
    if isinstance(terrain, str):
        raise MudrftError(
            "mud must be a Mud (mudrft.paper_mud) or a terrain object, got the string "
            f"{terrain!r}: write the terrain, e.g. mudrft.terrains.GranularRFT() "
            "(mudrft.baselines.compare takes names)"
        )
    if isinstance(terrain, type):
        raise MudrftError(
            f"mud must be a Mud or a terrain object, got the class {terrain.__name__} "
            f"(write {terrain.__name__}() with its options)"
        )
    raise MudrftError(
        "mud must be a Mud (mudrft.paper_mud) or a terrain with initial_state() and step() "
        f"(mudrft.terrains), got {type(terrain).__name__}"
    )
