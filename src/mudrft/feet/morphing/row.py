r"""The morphing foot as one :class:`~.linkage.MorphingRow` of floats, for compiled code."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from .equilibrium import linkage_row
from .linkage import MorphingRow

if TYPE_CHECKING:
    from .foot import MorphingFoot

__all__ = ["MorphingRow", "linkage_row", "morphing_row", "row_array"]


def morphing_row(foot: MorphingFoot) -> MorphingRow:
    """The :class:`~.linkage.MorphingRow` of a :class:`~.foot.MorphingFoot`."""
    lock = foot.locked_deflection()
    lock_row = -1.0 if lock is None else lock
    return linkage_row(foot.linkage, foot.spring, foot.seal_length, lock_row, foot.curl_delay)


def row_array(foot: MorphingFoot) -> NDArray[np.float64]:
    """:func:`morphing_row` as a float array (the compiled coupling's per-body row)."""
    return np.array(morphing_row(foot), dtype=float)
