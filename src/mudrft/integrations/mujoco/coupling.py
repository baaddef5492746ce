"""Mud under bodies of one MuJoCo model: :func:`attach`, :func:`attach_batch`."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from ..._validation import MudrftError
from .batch import MudBatch

if TYPE_CHECKING:
    import mujoco

    from ...parameters import Mud
    from ...terrains import MudTerrain
    from ...terrains.field import MudField

__all__ = ["MudCoupling", "attach", "attach_batch"]


class MudCoupling(MudBatch):
    """:class:`MudBatch` of one MjData; its methods take the MjData, and outputs in
    :attr:`last` have shape ``(nbody, ...)``."""

    def __init__(
        self,
        model: mujoco.MjModel,
        bodies: str | int | Sequence[str | int],
        mud: Mud | MudTerrain | MudField,
        **kw: Any,
    ) -> None:
        if "n" in kw:
            raise MudrftError("MudCoupling couples one MjData; use MudBatch(n=...) for many")
        super().__init__(model, bodies, mud, n=1, **kw)
        self._single = True


def attach(
    model: mujoco.MjModel,
    bodies: str | int | Sequence[str | int],
    mud: Mud | MudTerrain | MudField,
    **kw: Any,
) -> MudCoupling:
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
    model: mujoco.MjModel,
    bodies: str | int | Sequence[str | int],
    mud: Mud | MudTerrain | MudField,
    *,
    n: int,
    **kw: Any,
) -> MudBatch:
    """Attach mud to named bodies of ``n`` robots of one model; see :class:`MudBatch`."""
    return MudBatch(model, bodies, mud, n=n, **kw)
