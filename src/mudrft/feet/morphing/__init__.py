r"""The passive morphing foot of Chen et al. (2026), Sec. III-B: mechanism and coupling with mud.

A two-stage telescoping column (a soft and a hard spring in series) carries eight pads on
eight two-link linkages (paper Fig. 6): compressing the column spreads the pads from curled
up to a nearly flat disk. The paper gives no dimensions; the defaults are a documented
reconstruction (D30). Foot frame: origin at the tip, z up, pads at azimuths
:math:`2\pi k/N`; pad angle :math:`\theta` from the horizontal (0 spread, :math:`\pi/2` up).

* :mod:`.linkage`: dimensions and the slider-crank :math:`\theta(\delta)` (D30);
* :mod:`.springs`: the series law of the two-stage column (D31);
* :mod:`.pads`: submerged pad areas and the plate rule of eqs. (6)-(7) (D33, D38);
* :mod:`.equilibrium`: the column balance :math:`F_s(\delta)=F_z^{mud}(\delta)` and its
  root selection (D32, D34), the seal broken by curling pads (D35);
* :mod:`.foot`: :class:`MorphingFoot`, the checked mechanism with the Foot interface;
* :mod:`.row`: the foot's numbers as one named tuple of floats, for compiled code.

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
