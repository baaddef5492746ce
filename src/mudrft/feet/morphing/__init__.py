r"""The passive morphing foot of Chen et al. (2026), Sec. III-B (docs/model.md, Sec. 7).

Foot frame: origin at the tip, z up, pads at azimuths :math:`2\pi k/N`; pad angle
:math:`\theta` from the horizontal (0 spread, :math:`\pi/2` up). The force is element-wise
code over ``xp`` reading its numbers by attribute, from the dataclasses or from one
:class:`~.linkage.MorphingRow` of floats (the compiled coupling).
"""

from __future__ import annotations

from .equilibrium import MorphingState
from .foot import MODES, MorphingFoot
from .linkage import Linkage, MorphingFootGeometry
from .springs import RigidGroundResponse, TwoStageSpring

__all__ = [
    "MODES", "Linkage", "MorphingFoot", "MorphingFootGeometry", "MorphingState",
    "RigidGroundResponse", "TwoStageSpring"
]  # fmt: skip
