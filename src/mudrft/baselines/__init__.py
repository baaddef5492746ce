"""Baseline terrain models to compare the mud model with (supplementary Sec. III-D), each a
:class:`mudrft.terrains.Terrain` (docs/model.md, section 8, tabulates them and their sources).

>>> import mudrft
>>> from mudrft.baselines import compare
>>> out = compare(mudrft.feet.Flat(), mudrft.gait(speed=0.26))
>>> sorted(out)
['granular-rft', 'granular-rft3d', 'linear', 'maxwell', 'mud', 'rigid']
"""

from ..terrains.granular_rft import (
    FourierCoefficients,
    GranularRFT,
    li2013_alpha,
    rft_forces,
    treers_weights,
)
from ..terrains.linear import DEFAULT_STIFFNESS, LinearStiffness, fit_stiffness
from ..terrains.maxwell import MaxwellFit, MaxwellMud, fit_maxwell
from ..terrains.rigid import RigidGround
from .compare import (
    CSV_COLUMNS,
    History,
    compare,
    default_terrains,
    normalized_loop,
    run_terrain,
    summarize,
    write_csv,
)

__all__ = [
    "CSV_COLUMNS", "DEFAULT_STIFFNESS", "FourierCoefficients", "GranularRFT", "History",
    "LinearStiffness", "MaxwellFit", "MaxwellMud", "RigidGround", "compare", "default_terrains",
    "fit_maxwell", "fit_stiffness", "li2013_alpha", "normalized_loop", "rft_forces", "run_terrain",
    "summarize", "treers_weights", "write_csv"
]  # fmt: skip
