r"""Mud under MuJoCo bodies: read the foot motion, step the mud once, write the wrench.

:func:`attach` puts mud under bodies of any MJCF model; each gets a mudrft foot, derived
from its geoms or given. Every physics step (inside ``mj_step``, from MuJoCo's passive
callback) the coupling writes into ``data.xfrc_applied`` the mud's wrench, linearly implicit in the body twist (D62-D62d) and bounded so that the mud
never gives the robot more energy than it took (D62c)::

    import mujoco, mudrft
    from mudrft.integrations.mujoco import attach
    coupling = attach(model, ["left_foot", "right_foot"], mudrft.paper_mud(0.25))
    coupling.reset(data)               # installs the mud in MuJoCo's step
    mujoco.mj_step(model, data, 1000)  # or coupling.step(data, 1000), checked per step

Importing this package does not import MuJoCo.
"""

from __future__ import annotations

from ._lazy import _mujoco as _mujoco  # for mudrft.integrations.walk
from .batch import MudBatch, MudContact
from .coupling import MudCoupling, attach, attach_batch
from .menagerie import menagerie_scene
from .placement import BodyFoot as BodyFoot
from .placement import body_foot
from .rigid import add_rigid_cells, set_rigid_cells
from .stability import stability_limits

__all__ = [
    "MudBatch",
    "MudContact",
    "MudCoupling",
    "add_rigid_cells",
    "attach",
    "attach_batch",
    "body_foot",
    "menagerie_scene",
    "set_rigid_cells",
    "stability_limits",
]
