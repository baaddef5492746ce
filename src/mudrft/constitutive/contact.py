"""Contact with the mud: when a channel feels the mud, and from which state (decision D11)."""

from __future__ import annotations

import numpy as np

from .._typing import Namespace, XpArray
from .state import ChannelState

__all__ = ["contact_rate", "enter", "in_contact"]


def in_contact(depth: XpArray) -> XpArray:
    """Whether a tip at ``depth`` [m] (or ``depth / L_c`` [-]) touches the mud: depth > 0.

    Examples
    --------
    >>> in_contact(np.array([-0.005, 0.0, 0.001])).tolist()
    [False, False, True]
    """
    return depth > 0.0


def enter(state: ChannelState, fresh: XpArray, xi0: XpArray, xp: Namespace = np) -> ChannelState:
    """``state``, with undisturbed mud (structure ``xi0`` [-]) where ``fresh`` (bool)."""
    return ChannelState(
        gamma=xp.where(fresh, 0.0, state.gamma),
        gamma_w=xp.where(fresh, 0.0, state.gamma_w),
        xi=xp.where(fresh, xi0, state.xi),
        s_th=xp.where(fresh, 0.0, state.s_th),
        sigma_s=xp.where(fresh, 0.0, state.sigma_s),
        clock=xp.where(fresh, 0.0, state.clock),
        clock_w=xp.where(fresh, 0.0, state.clock_w),
    )


def contact_rate(rate: XpArray, was_in: XpArray, now_in: XpArray, xp: Namespace = np) -> XpArray:
    """The rate [1/s] the mud sees over a step: ``rate``, or 0 when the tip was out of the
    mud at both ends of the step (``was_in``, ``now_in``: :func:`in_contact` there)."""
    return xp.where(was_in | now_in, rate, 0.0)
