"""Mud under named bodies of one MuJoCo model: :func:`attach` and :class:`MudCoupling`.

:class:`MudCoupling` is :class:`~mudrft.integrations.mujoco.MudBatch` for one ``MjData``,
with outputs of shape ``(nbody, ...)``; :func:`attach_batch` makes a batch of ``n``
robots.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from ..._validation import MudrftError
from .batch import MudBatch, MudContact

if TYPE_CHECKING:
    import mujoco

    from ...parameters import Mud
    from ...terrains import Terrain

__all__ = ["MudCoupling", "attach", "attach_batch"]


class MudCoupling(MudBatch):
    """Mud under named bodies of one MuJoCo model and one MjData (see :class:`MudBatch`).

    Outputs in :attr:`last` have shape ``(nbody, ...)``.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        bodies: str | int | Sequence[str | int],
        mud: Mud | Terrain,
        **kw: Any,
    ) -> None:
        if "n" in kw:
            raise MudrftError("MudCoupling couples one MjData; use MudBatch(n=...) for many")
        super().__init__(model, bodies, mud, n=1, **kw)
        self._single = True

    def reset(self, data: mujoco.MjData) -> None:  # type: ignore[override]
        """Start with undisturbed mud under the feet in their current pose."""
        super().reset([data])

    def apply(self, data: mujoco.MjData) -> MudContact:  # type: ignore[override]
        """Advance the mud once and write ``data.xfrc_applied`` (after ``mj_step1``)."""
        self.last = MudContact(*(a[0] for a in self._apply(self._check(data))))
        return self.last

    def step(self, data: mujoco.MjData, nstep: int = 1) -> MudContact:  # type: ignore[override]
        """``nstep`` physics steps, the mud advanced once per step."""
        if self._loop is not None and data is self._compiled.datas[0]:  # type: ignore[union-attr]
            self._loop(self._nstep(nstep))  # the compiled loop
            out = self.last
            assert out is not None
            return out
        out = self._step(self._check(data), self._nstep(nstep))
        if out.depth.ndim == 2:  # (1, nbody): the batch's shape; the compiled path gives (nbody,)
            out = MudContact(*(a[0] for a in out))
        self.last = out
        return out

    def advance(self, data: mujoco.MjData, nstep: int = 1) -> None:  # type: ignore[override]
        """``nstep`` physics steps without returning the contact (:attr:`last` has it)."""
        if self._loop is not None and data is self._compiled.datas[0]:  # type: ignore[union-attr]
            self._loop(self._nstep(nstep))  # the compiled loop
        else:
            self.step(data, nstep)


def attach(
    model: mujoco.MjModel, bodies: str | int | Sequence[str | int], mud: Mud | Terrain, **kw: Any
) -> MudCoupling:
    """Attach mud to named bodies of a MuJoCo model; see :class:`MudBatch` for options.

    References
    ----------
    .. [1] X. Chen, L. Wang, X. Huang, J. Shan, Y. Shen and J. Yi, "A Foot Resistive Force
       Model for Legged Locomotion on Muddy Terrains", 2026 (preprint with supplementary
       materials), eqs. (1)-(7).
    .. [2] mudrft's model chapter (docs/model.md), Sec. 10, decisions D60-D68.

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
    mud: Mud | Terrain,
    *,
    n: int,
    **kw: Any,
) -> MudBatch:
    """Attach mud to named bodies of ``n`` robots of one model; see :class:`MudBatch`."""
    return MudBatch(model, bodies, mud, n=n, **kw)
