r"""Mud under MuJoCo bodies: read the foot motion, step the mud once, write the wrench.

:func:`attach` puts mud under named bodies of any MJCF model. Each body gets a mudrft
foot, derived from its geoms or given explicitly. Every physics step the coupling

1. reads the pose and velocity of the foot *tip* (the point of the foot that is lowest in
   the model's reference pose, fixed in the body) and the depth of the lowest point of
   the foot geom in its current pose;
2. rotates the motion into the foot frame (the foot's yaw; the foot is treated as upright,
   see the tilt approximation below) and advances the mud state **once**;
3. makes the force safe for an explicit step (the semi-implicit treatment of the
   velocity-dependent part, below) and writes force and moment about the body's
   center of mass into ``data.xfrc_applied``.

It uses ``mj_step1`` / ``mj_step2``, so the forces come from the state at the start of
the step and held over it, and MuJoCo's own integrator does the rest::

    import mujoco, mudrft
    from mudrft.integrations.mujoco import attach
    coupling = attach(model, ["left_foot", "right_foot"], mudrft.paper_mud(0.25))
    coupling.reset(data)
    for _ in range(1000):
        coupling.step(data)            # mj_step1, mud, mj_step2

Stability (docs/model.md, decisions D61-D64). The mud force has a part that
acts like a damper, :math:`c\approx\eta_\infty A/L_c` (1-2 kN s/m for the paper's feet),
and the suction switch :math:`H_\nu` makes the force jump by :math:`\sigma_s A` within a
velocity band :math:`\nu L_c` of a millimetre per second. An explicit step of a damper is
stable only for :math:`\Delta t<2m/c` (about 0.5 ms for a 0.3 kg foot). The coupling
therefore applies the force the mud would exert at the *end* of the step, linearised in
the velocity: with :math:`W` the tip's mobility (:math:`J M^{-1} J^T`, from MuJoCo),
:math:`D\le0` the diagonal velocity derivative of the mud force (secant differences,
one batched mud call) and :math:`a` the acceleration from all other forces (from the
previous step),

.. math:: F = (I - \Delta t\,D\,W)^{-1}\,(F_0 + \Delta t\,D\,a),

the linearly implicit Euler step of the dissipative part. It equals the explicit
:math:`F_0` at rest and for kinematic bodies (:math:`W=0`), never reverses the velocity
within one step, and so never injects energy through the damper.

Modules, one concept each:

* :mod:`.placement`: a mudrft foot placed on a body (:func:`body_foot`, :class:`BodyFoot`),
  and the lowest point of each foot in its current pose;
* :mod:`.geoms`: the foot a geom stands for, and the lowest point of a geom;
* :mod:`.kinematics`: body frames, velocities and tip mobility read from MuJoCo;
* :mod:`.implicit`: the semi-implicit treatment above (secant derivative, implicit force);
* :mod:`.stability`: explicit time-step limits (:func:`stability_limits`);
* :mod:`.batch`: the coupling of many robots (:class:`MudBatch`, :class:`MudContact`);
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
