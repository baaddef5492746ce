r"""The passive morphing foot of Chen et al. (2026), Sec. III-B: mechanism and coupling with mud.

The foot (paper Fig. 6) has three parts: a two-stage telescoping **column** with a soft
and a hard spring in series, **eight pads** carried by the lower links of **eight
two-link linkages**. Compressing the column (deflection :math:`\delta`) pushes the
upper poles down; the couplers rotate the lower links and the pads spread from curled
up (pointing almost upward) to a nearly flat disk. The paper gives no dimensions; the
defaults here are a documented reconstruction (decision D30 in ``docs/model.md``) of the
same scale as the paper's fixed feet.

Frame: the foot frame has its origin at the tip (the bottom of the central base pad), z up,
pads at azimuths :math:`2\pi k/N`. Pad angle :math:`\theta` is measured from the horizontal
(0: spread flat, :math:`\pi/2`: pointing up).

One concept a module (decisions D30-D39):

* :mod:`.linkage` (D30): dimensions and the slider-crank :math:`\theta(\delta)` of each pad,
  a closed-form circle intersection, nearly linear (paper Fig. S3a);
* :mod:`.springs` (D31): the exact series law of the two-stage column, stiffness
  :math:`k_sk_h/(k_s+k_h)` until the soft stage bottoms out, then :math:`k_h` (Fig. S3b);
* :mod:`.pads` (D33, D38): submerged pad areas and the per-plate rule of eq. (6)-(7) with
  tilt :math:`\psi_1=\theta`, uniform channel stresses; horizontal forces on projected areas;
* :mod:`.equilibrium` (D32, D34, D35): the whole vertical mud force passes through the
  column, :math:`F_s(\delta)=F_z^{mud}(\delta)`, solved at every step by a grid bracket and
  SciPy's bracketing root finder, continued from the previous deflection (snap-through,
  hysteresis); the seal factor :math:`1-\tanh(g/g_s)` falls as the pad rims curl up;
* :mod:`.mechanism`: :class:`MorphingMechanism`, which composes them into the checked views
  of the mechanism (rigid ground, areas, balance, drawing); the modes ``"expanded"`` and
  ``"retracted"`` lock the column (D37);
* :mod:`.foot`: :class:`MorphingFoot`, the mechanism with the :class:`~mudrft.feet.base.Foot`
  interface of the mud terrain; :math:`L_c` is the square root of the spread footprint (D36);
* :mod:`.row`: the foot's numbers as one named tuple of floats
  (:class:`~.linkage.MorphingRow`), for compiled code.

The equations of the force are element-wise code over ``xp`` that reads its
numbers by attribute, from the dataclasses or from one :class:`~.linkage.MorphingRow` of floats:
numpy runs them on arrays, the compiled MuJoCo coupling on floats. The JAX backend
does not trace the foot: the column balance selects its root by a data-dependent scan.
"""

from __future__ import annotations

from .equilibrium import MorphingState
from .foot import MorphingFoot
from .linkage import Linkage, MorphingFootGeometry
from .mechanism import MODES, MorphingMechanism
from .springs import RigidGroundResponse, TwoStageSpring

__all__ = [
    "MODES",
    "Linkage",
    "MorphingFoot",
    "MorphingFootGeometry",
    "MorphingMechanism",
    "MorphingState",
    "RigidGroundResponse",
    "TwoStageSpring",
]
