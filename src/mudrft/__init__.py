"""mudrft: the 3D force mud exerts on a robot foot (Chen et al. 2026's resistive force
model, integrated over the surface of any foot). SI units throughout.

>>> import mudrft
>>> mud = mudrft.paper_mud(water_content=0.25)
>>> mud.vertical.sigma_y
7100.0
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # at run time every name loads on first use: `mudrft --help` stays light
    from . import constitutive, parameters, units
    from ._validation import MudrftError
    from .data import data_path
    from .parameters import Mud, MudParameters, paper_mud, paper_parameters
    from .plate import PlateResult, plate_response
    from .simulation import LoadControl, Result, simulate, static_sinking
    from .terrains import MudTerrain, Terrain, TerrainOutput
    from .terrains.field import MudField
    from .trajectories import GAIT_SPEEDS, Trajectory, gait, plate_intrusion

# the function mudrft.citations() shares its name with the module mudrft.citations, which
# would replace a lazy attribute once imported: the function is bound here (stdlib only)
from .citations import citations

__version__ = "0.3.0.dev0"

_LAZY = {  # submodules; mudrft.sweep is also callable: mudrft.sweep(spec, ...)
    name: f"mudrft.{name}"
    for name in ("constitutive", "parameters", "units", "feet", "terrains", "baselines",
                 "calibration", "integrations", "backends", "metrics", "io", "plotting", "sweep")
}  # fmt: skip
#: Names loaded on first use, by module.
_FROM = {
    "mudrft._validation": ("MudrftError",),
    "mudrft.backends": ("BatchedMud",),
    "mudrft.calibration": ("calibrate", "load_parameters"),
    "mudrft.data": ("data_path",),
    "mudrft.parameters": ("Mud", "MudParameters", "paper_mud", "paper_parameters"),
    "mudrft.plate": ("PlateResult", "plate_response"),
    "mudrft.simulation": ("LoadControl", "Result", "simulate", "static_sinking"),
    "mudrft.terrains": ("MudTerrain", "Terrain", "TerrainOutput"),
    "mudrft.terrains.field": ("MudField",),
    "mudrft.trajectories": ("GAIT_SPEEDS", "Trajectory", "gait", "plate_intrusion"),
}
_LAZY_ATTRS = {name: (module, name) for module, names in _FROM.items() for name in names}

__all__ = [  # the lazy names below, spelled out for readers and linters
    "GAIT_SPEEDS", "BatchedMud", "LoadControl", "Mud", "MudField", "MudParameters", "MudTerrain",
    "MudrftError", "PlateResult", "Result", "Terrain", "TerrainOutput", "Trajectory",
    "__version__", "backends", "baselines", "calibrate", "calibration", "citations",
    "constitutive", "data_path", "feet", "gait", "integrations", "io", "load_parameters",
    "metrics", "paper_mud", "paper_parameters", "parameters", "plate_intrusion",
    "plate_response", "plotting", "simulate", "static_sinking", "sweep", "terrains", "units",
]  # fmt: skip


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return importlib.import_module(_LAZY[name])
    if name in _LAZY_ATTRS:
        mod, attr = _LAZY_ATTRS[name]
        return getattr(importlib.import_module(mod), attr)
    raise AttributeError(f"module 'mudrft' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
