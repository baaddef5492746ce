r"""Mud under MuJoCo bodies: read the foot motion, step the mud once, write the wrench.

:func:`attach` puts mud under named bodies of any MJCF model. Each body gets a mudrft
foot, derived from its geoms or given explicitly. Every physics step the coupling

1. reads the pose and twist of each foot body, and clips the foot's triangles in their
   current pose by the mud surface (:mod:`.pose`): where each stress channel acts on the
   submerged part, and how much of it is submerged compared with the upright foot;
2. advances the mud state **once**, with the depth of the lowest point and each
   channel's velocity read where that channel acts (the foot's yaw frame);
3. assembles the wrench of the posed foot (:mod:`.wrench`), makes it safe for an explicit
   step (the linearly implicit treatment of its dissipative part in all six degrees of
   freedom of the body, below, all the feet of one robot together, D62d), bounds it so that
   the mud never gives the robot more energy than it has taken
   (:func:`.implicit.passive_wrench`, D62c), writes force and moment
   about the body's center of mass into ``data.xfrc_applied``, and raises if MuJoCo
   reports a diverged step.

It uses ``mj_step1`` / ``mj_step2``, so the forces come from the state at the start of
the step and held over it, and MuJoCo's own integrator does the rest::

    import mujoco, mudrft
    from mudrft.integrations.mujoco import attach
    coupling = attach(model, ["left_foot", "right_foot"], mudrft.paper_mud(0.25))
    coupling.reset(data)
    for _ in range(1000):
        coupling.step(data)            # mj_step1, mud, mj_step2

``attach(..., backend="numba")`` runs the whole coupling as one compiled call per physics
step for all feet of all robots (:mod:`.compiled`; closed-form and mesh feet on the mud),
equal to the numpy coupling to round-off (D68a).

Passivity (docs/model.md, decisions D60a-D63). The mud force has a part that acts like a
damper, :math:`c\approx\eta_\infty A/L_c` (1-2 kN s/m for the paper's feet), and the
suction switch :math:`H_\nu` makes the force jump by :math:`\sigma_s A` within a velocity
band :math:`\nu L_c` of a millimetre per second. An explicit step of a damper is stable
only for :math:`\Delta t<2m/c` (about 0.5 ms for a 0.3 kg foot), and a damper at a lever
arm of a light foot that can rotate is stiffer still. The coupling therefore applies the
wrench the mud would exert at the *end* of the step, linearised in the body twist
:math:`\xi`: with :math:`W` the body's 6x6 mobility (:math:`J M^{-1} J^T`, from MuJoCo),
:math:`K` the symmetric negative semi-definite damping of the wrench (each channel's
secant derivative acting where the channel acts, plus the same damping spread over the
submerged elements) and :math:`a` the twist acceleration from all other forces,

.. math:: w = (I - \Delta t\,K\,W)^{-1}\,(w_0 + \Delta t\,K\,a),

the linearly implicit Euler step of the dissipative part. It equals the explicit
:math:`w_0` at rest and for kinematic bodies (:math:`W=0`), never reverses a velocity
within one step, and so never injects energy through the damper, whatever the body's pose
or spin.

Modules, one concept each:

* :mod:`.placement`: a mudrft foot placed on a body (:func:`body_foot`, :class:`BodyFoot`),
  and the lowest point of each foot in its current pose;
* :mod:`.geoms`: the foot a geom stands for, and the lowest point of a geom;
* :mod:`.pose`: the foot's triangles, and the channel geometry of the posed foot;
* :mod:`.kinematics`: body frames, twists and the 6x6 mobility read from MuJoCo;
* :mod:`.wrench`: the wrench of the posed foot and its damping matrix;
* :mod:`.implicit`: the implicit treatment above (secant derivative, implicit wrench);
* :mod:`.stability`: explicit time-step limits (:func:`stability_limits`);
* :mod:`.batch`: the coupling of many robots (:class:`MudBatch`; :mod:`.contact`:
  :class:`MudContact`);
* :mod:`.compiled`, :mod:`.backend`, :mod:`.linalg`: the compiled coupling (numba);
* :mod:`.coupling`: one robot (:class:`MudCoupling`, :func:`attach`, :func:`attach_batch`).

Importing this package does not import MuJoCo; the coupling imports it when it is made.
"""

from __future__ import annotations

from ._lazy import _mujoco as _mujoco  # for mudrft.integrations.walk
from .batch import MudBatch, MudContact
from .coupling import MudCoupling, attach, attach_batch
from .placement import BodyFoot as BodyFoot
from .placement import body_foot
from .stability import stability_limits

__all__ = [
    "MudBatch",
    "MudContact",
    "MudCoupling",
    "attach",
    "attach_batch",
    "body_foot",
    "stability_limits",
]
