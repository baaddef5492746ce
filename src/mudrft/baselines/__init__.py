"""Baseline terrain models to compare the mud model with (supplementary Sec. III-D).

Every model is a :class:`mudrft.terrains.Terrain`:

* :class:`GranularRFT` -- granular RFT (Li et al. 2013) in 3D (Treers et al. 2021);
* :class:`~mudrft.terrains.GranularRFT3D` -- the 3D-RFT of Agarwal et al. (2023);
* :class:`LinearStiffness` -- linear mud stiffness (Godon et al. 2022, Liu et al. 2023);
* :class:`MaxwellMud` -- a *reconstruction* of the Maxwell-type mud of Chen et al. (AIM 2024);
* :class:`RigidGround` -- penalty contact with regularised Coulomb friction.

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
