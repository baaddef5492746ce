r"""Mud under MuJoCo bodies: read the foot motion, step the mud once, write the wrench.

:func:`attach` puts mud under bodies of any MJCF model; each gets a mudrft foot, derived
from its geoms or given. Every physics step (inside ``mj_step``, as MuJoCo's passive
callback, :mod:`.callback`; ``backend="numpy"``: between ``mj_step1`` and ``mj_step2``) the
coupling clips each foot in its current pose by the mud surface (:mod:`.pose`), steps the
mud once, and writes into ``data.xfrc_applied`` the wrench the mud would exert at the end
of the step, linearised in the body twist (the linearly implicit step of its damping,
all feet of one robot together, D62-D62d) and bounded so that the mud never gives the
robot more energy than it took (D62c)::

    import mujoco, mudrft
    from mudrft.integrations.mujoco import attach
    coupling = attach(model, ["left_foot", "right_foot"], mudrft.paper_mud(0.25))
    coupling.reset(data)               # installs the mud in MuJoCo's step
    mujoco.mj_step(model, data, 1000)  # or coupling.step(data, 1000), checked per step

.. math:: w = (I - \Delta t\,K\,W)^{-1}\,(w_0 + \Delta t\,K\,a),

with :math:`W` the mobility :math:`J M^{-1} J^T`, :math:`K` the wrench's damping and
:math:`a` the twist acceleration from all other forces. The mud and feet with a surface
run as one compiled call per step for all feet of all robots (:mod:`.compiled`); any
other terrain runs on numpy arrays, the reference the tests compare with. Importing this
package does not import MuJoCo.
"""

from __future__ import annotations

from ._lazy import _mujoco as _mujoco  # for mudrft.integrations.walk
from .batch import MudBatch, MudContact
from .coupling import MudCoupling, attach, attach_batch
from .menagerie import menagerie_scene
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
    "menagerie_scene",
    "stability_limits",
]
