"""Which evaluations of the mud the couplings are known to keep passive (decision D62b).

The MuJoCo and MJX couplings treat the mud's instantaneous damping implicitly (D62, D62a);
the stresses with memory stay explicit. With the default evaluation (``thixotropy="ode"``
with the acceleration term) the instantaneous viscous stress dominates, and no released
free foot has gained energy in the tests or in 19,137 random releases. Without it
(``acceleration=False``) or with the paper's quasi-static evaluation, a foot that tilts,
spins about a horizontal axis and slides can gain energy from the mud: the coupling warns.
"""

from __future__ import annotations

import warnings
from typing import Any

from .._validation import _caller_level
from ..terrains import MudTerrain

__all__ = ["PassivityWarning", "warn_if_not_passive"]


class PassivityWarning(UserWarning):
    """A coupling was given an evaluation of the mud that is not known to stay passive."""


def warn_if_not_passive(terrain: Any) -> bool:
    """Warn (:class:`PassivityWarning`) when ``terrain`` is a :class:`~mudrft.MudTerrain`
    whose evaluation the couplings do not keep passive (D62b); return whether it warned."""
    if not isinstance(terrain, MudTerrain):
        return False
    if terrain.acceleration and not terrain.quasi_static:
        return False
    how = (
        f"thixotropy={terrain.thixotropy!r}"
        if terrain.quasi_static
        else "thixotropy='ode' without the acceleration term"
    )
    warnings.warn(
        f"the coupling keeps the mud passive for the default evaluation (thixotropy='ode' "
        f"with the acceleration term); with {how} a foot that tilts, spins about a "
        "horizontal axis and slides can gain energy from the mud (measured: up to 4 times "
        "its starting energy in 0.2 s; docs/model.md D62b). For physics simulation use "
        "MudTerrain(mud), or watch the energy of your model",
        PassivityWarning,
        stacklevel=_caller_level(),
    )
    return True
