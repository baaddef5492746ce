"""The mud constitutive model: pure laws, explicit state, exact time stepping."""

from . import laws
from .dynamics import (
    ChannelHistory,
    run,
    step,
    suction_closed_form,
    thixotropic_approx,
    thixotropic_exact,
    xi_exact,
)
from .state import ChannelState, ChannelStress, initial_state

__all__ = [
    "ChannelHistory",
    "ChannelState",
    "ChannelStress",
    "initial_state",
    "laws",
    "run",
    "step",
    "suction_closed_form",
    "thixotropic_approx",
    "thixotropic_exact",
    "xi_exact",
]
