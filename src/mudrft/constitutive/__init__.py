"""The mud constitutive model: pure laws, explicit state, one time step, exact solutions.

* :mod:`~mudrft.constitutive.laws`: the pure stress laws of eqs. (1)-(5), (7);
* :mod:`~mudrft.constitutive.kernel`: :func:`channel_update`, the one definition of the
  time step every path runs (numpy, Python floats, JAX, numba);
* :mod:`~mudrft.constitutive.dynamics`: the validated :func:`step` and :func:`run`;
* :mod:`~mudrft.constitutive.exact`: the paper's closed-form solutions (eqs. 9-11).
"""

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
