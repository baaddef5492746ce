r"""Contact with the mud: when a channel feels the mud, and from which state (decision D11).

One rule, used by :func:`mudrft.simulate` (through :func:`mudrft.terrains.mud.mud_step`), by
:func:`mudrft.plate_response` and by the forward model of :func:`mudrft.calibrate`:

* a tip touches the mud when its depth is positive (:func:`in_contact`); at or above the
  surface it feels no stress;
* the mud's memory starts at first contact: a channel that was out of the mud before a step
  starts that step from undisturbed mud (:func:`enter`), whatever it did in the air;
* the mud sees the motion of a step that starts or ends in it (:func:`contact_rate`).

The functions are element-wise (:mod:`mudrft._xp`): numpy, JAX and numba run them alike.
"""

from __future__ import annotations

import numpy as np

from .._typing import Namespace, XpArray
from .state import ChannelState

__all__ = ["contact_rate", "enter", "in_contact"]


def in_contact(depth: XpArray) -> XpArray:
    """Whether a tip at ``depth`` touches the mud: depth > 0 (positive into the mud).

    Parameters
    ----------
    depth : array_like
        Depth below the surface [m], or the dimensionless displacement ``depth / L_c`` [-].

    Examples
    --------
    >>> in_contact(np.array([-0.005, 0.0, 0.001])).tolist()
    [False, False, True]
    """
    return depth > 0.0


def enter(state: ChannelState, fresh: XpArray, xi0: XpArray, xp: Namespace = np) -> ChannelState:
    """The channel state, undisturbed mud where ``fresh`` (the tip was out of the mud).

    Parameters
    ----------
    state : ChannelState
        State at the start of the step.
    fresh : array_like of bool
        Where the tip was out of the mud before the step.
    xi0 : float
        Structure of undisturbed mud [-] (decision D3).
    xp : module
        Element-wise namespace (:mod:`mudrft._xp`).
    """
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
