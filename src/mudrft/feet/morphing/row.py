r"""The morphing foot as one row of floats, for code compiled on floats (D68d).

:class:`MorphingRow` holds every number the foot's force needs: the dimensions of
:class:`~.linkage.MorphingFootGeometry` (same names), the resolved :class:`~.linkage.Linkage`
(``pole_top``, ``stroke``, ``branch``), the :class:`~.springs.TwoStageSpring`'s derived
constants (same names as its properties), the seal length and the locked deflection. The
element-wise functions of :mod:`.linkage`, :mod:`.springs`, :mod:`.pads` and
:mod:`.equilibrium` read their numbers by attribute, so they run unchanged on a geometry
dataclass (numpy) or on this named tuple (numba compiles named tuples of floats; it cannot
compile the dataclasses).
"""

from __future__ import annotations

import dataclasses
import functools
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from .foot import MorphingFoot
    from .linkage import Linkage
    from .springs import TwoStageSpring

__all__ = ["MorphingRow", "linkage_row", "morphing_row", "row_array"]


class MorphingRow(NamedTuple):
    """Every number of a :class:`~.foot.MorphingFoot`'s force, as floats [m, rad, N/m, N].

    ``lock`` is the locked deflection of the modes ``"expanded"`` and ``"retracted"``
    [m], or -1 for the free ``"morphing"`` mode (D37).
    """

    base_radius: float
    pivot_height: float
    column_radius: float
    height: float
    pad_length: float
    pad_inner_width: float
    pad_outer_width: float
    n_pads: float
    crank_length: float
    crank_offset: float
    coupler_length: float
    pole_radius: float
    retracted_angle: float
    expanded_angle: float
    pole_top: float
    stroke: float
    branch: float
    series_stiffness: float
    hard_stiffness: float
    knee_deflection: float
    knee_force: float
    seal_length: float
    lock: float


@functools.lru_cache(maxsize=64)
def linkage_row(
    linkage: Linkage, spring: TwoStageSpring, seal_length: float = 1.0, lock: float = -1.0
) -> MorphingRow:
    """The :class:`MorphingRow` of a :class:`~.linkage.Linkage` and a
    :class:`~.springs.TwoStageSpring` (seal length [m], locked deflection [m] or -1);
    cached, for :func:`~.equilibrium.balanced_deflection` on floats."""
    g = linkage.geometry
    # every field of the geometry (a field the row lacks fails below, instead of vanishing)
    values = {f.name: getattr(g, f.name) for f in dataclasses.fields(g)}
    values.update(
        pole_top=linkage.pole_top,
        stroke=linkage.stroke,
        branch=linkage.branch,
        series_stiffness=spring.series_stiffness,
        hard_stiffness=spring.hard_stiffness,
        knee_deflection=spring.knee_deflection,
        knee_force=spring.knee_force,
        seal_length=seal_length,
        lock=lock,
    )
    return MorphingRow(**{k: float(v) for k, v in values.items()})


def morphing_row(foot: MorphingFoot) -> MorphingRow:
    """The :class:`MorphingRow` of a :class:`~.foot.MorphingFoot`."""
    lock = foot.locked_deflection()
    return linkage_row(foot.linkage, foot.spring, foot.seal_length, -1.0 if lock is None else lock)


def row_array(foot: MorphingFoot) -> NDArray[np.float64]:
    """:func:`morphing_row` as a float array (the compiled coupling's per-body row)."""
    return np.array(morphing_row(foot), dtype=float)
