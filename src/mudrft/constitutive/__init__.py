"""The mud constitutive model: pure laws (:mod:`~mudrft.constitutive.laws`), explicit state,
one time step (:mod:`~mudrft.constitutive.kernel`), exact solutions (eqs. 9-11)."""

from . import laws
from .dynamics import ChannelHistory, run, step
from .exact import suction_closed_form, thixotropic_approx, thixotropic_exact, xi_exact
from .kernel import ChannelConstants, channel_constants, channel_update
from .state import ChannelState, ChannelStress, initial_state

__all__ = [
    "ChannelConstants", "ChannelHistory", "ChannelState", "ChannelStress", "channel_constants",
    "channel_update", "initial_state", "laws", "run", "step", "suction_closed_form",
    "thixotropic_approx", "thixotropic_exact", "xi_exact",
]  # fmt: skip
