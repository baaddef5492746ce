"""mudrft: the 3D force mud exerts on a robot foot.

An implementation of the foot-mud resistive force model of Chen et al. (2026):
nonlinear elastic resistance, thixotropic viscoelastic stress with a structure
parameter, and suction with build-up, leak and sealing, integrated over the
surface of any foot. SI units throughout.

>>> import mudrft
>>> mud = mudrft.paper_mud(water_content=0.25)
>>> mud.vertical.sigma_y
7100.0
"""

from __future__ import annotations

import importlib
from typing import Any

from . import constitutive, parameters, units
from ._validation import MudrftError
from .citations import citations
from .parameters import Mud, MudParameters, paper_mud, paper_parameters
from .plate import PlateResult, plate_response
from .simulation import LoadControl, Result, simulate, static_sinking
from .terrains import MudTerrain, Terrain, TerrainOutput
from .trajectories import GAIT_SPEEDS, Trajectory, gait, plate_intrusion

__version__ = "0.1.0"

_LAZY = {
    "feet": "mudrft.feet",
    "terrains": "mudrft.terrains",
    "baselines": "mudrft.baselines",
    "calibration": "mudrft.calibration",
    "integrations": "mudrft.integrations",
    "backends": "mudrft.backends",
    "metrics": "mudrft.metrics",
    "io": "mudrft.io",
    "plotting": "mudrft.plotting",
    "sweep": "mudrft.sweep",  # callable: mudrft.sweep(spec, ...) runs a design sweep
}
_LAZY_ATTRS = {
    "calibrate": ("mudrft.calibration", "calibrate"),
    "load_parameters": ("mudrft.calibration", "load_parameters"),
    "BatchedMud": ("mudrft.backends", "BatchedMud"),
}

__all__ = [
    "GAIT_SPEEDS",
    "Mud",
    "MudParameters",
    "MudTerrain",
    "MudrftError",
    "LoadControl",
    "PlateResult",
    "Result",
    "Terrain",
    "TerrainOutput",
    "Trajectory",
    "__version__",
    "citations",
    "constitutive",
    "gait",
    "paper_mud",
    "paper_parameters",
    "parameters",
    "plate_intrusion",
    "plate_response",
    "simulate",
    "static_sinking",
    "units",
    *sorted(_LAZY),
    *sorted(_LAZY_ATTRS),
]


def __getattr__(name: str) -> Any:
    # submodules and heavier entry points load on first use, keeping `import mudrft` light
    if name in _LAZY:
        return importlib.import_module(_LAZY[name])
    if name in _LAZY_ATTRS:
        mod, attr = _LAZY_ATTRS[name]
        return getattr(importlib.import_module(mod), attr)
    raise AttributeError(f"module 'mudrft' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
