r"""The passive morphing foot of Chen et al. (2026), Sec. III-B: mechanism and coupling with mud.

A two-stage telescoping column (a soft and a hard spring in series) carries eight pads on
eight two-link linkages (paper Fig. 6): compressing the column spreads the pads from curled
up to a nearly flat disk. The paper gives no dimensions; the defaults are a documented
reconstruction (D30). Foot frame: origin at the tip, z up, pads at azimuths
:math:`2\pi k/N`; pad angle :math:`\theta` from the horizontal (0 spread, :math:`\pi/2` up).
The force is element-wise code over ``xp`` reading its numbers by attribute, from the
dataclasses or from one :class:`~.linkage.MorphingRow` of floats (the compiled coupling).
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
