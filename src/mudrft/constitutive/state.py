"""Explicit, immutable state of one stress channel (x, y or z) or a batch of them."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._typing import ArrayLike, XpArray
from .._validation import check_in_range

__all__ = ["ChannelState", "ChannelStress", "initial_state"]


class ChannelState(NamedTuple):
    r"""State of a stress channel after a step.

    Attributes
    ----------
    gamma, gamma_w : array
        Dimensionless displacement, and the deepest of the current intrusion [-].
    xi : array
        Structure parameter in [0, 1] [-].
    s_th : array
        Lagged thixotropic stress [Pa]: :math:`\sigma_{th}=\kappa\eta_\infty\dot\gamma+s_{th}` (D6).
    sigma_s : array
        Suction state of eq. (5) [Pa].
    clock, clock_w : array
        Time since first contact, :math:`t` of eq. (9), and since the retraction began,
        :math:`t-t_w` of eq. (10) [s] (0 when not retracting).
    """

    gamma: XpArray
    gamma_w: XpArray
    xi: XpArray
    s_th: XpArray
    sigma_s: XpArray
    clock: XpArray = 0.0
    clock_w: XpArray = 0.0


class ChannelStress(NamedTuple):
    r"""Stresses of a channel at the end of a step [Pa]: the ``total`` of eq. (1), the
    ``elastic`` :math:`\sigma_b` times the bed contact, the ``thixotropic``
    :math:`\sigma_{th}` and the ``suction`` :math:`H_\nu\sigma_s`."""

    total: XpArray
    elastic: XpArray
    thixotropic: XpArray
    suction: XpArray


def initial_state(
    shape: tuple[int, ...] = (), *, xi0: float = 0.0, gamma: ArrayLike = 0.0
) -> ChannelState:
    """State of freshly prepared mud: no stress, structure ``xi0``.

    Parameters
    ----------
    shape : tuple of int
        Batch shape of the state arrays.
    xi0 : float, keyword-only
        Initial structure parameter in [0, 1] [-] (decision D3).
    gamma : float or array, keyword-only
        Initial dimensionless displacement [-].

    Examples
    --------
    >>> float(initial_state().xi), initial_state((2, 3)).sigma_s.shape
    (0.0, (2, 3))
    """
    check_in_range("xi0", xi0, 0.0, 1.0)
    z = np.zeros(shape)
    g = np.broadcast_to(np.asarray(gamma, dtype=float), shape).copy()
    return ChannelState(g, g.copy(), z + xi0, z.copy(), z.copy(), z.copy(), z.copy())
