"""Options shared by the batched and the single-foot fast paths (one place to validate them)."""

from __future__ import annotations

from typing import Any, NamedTuple

from .._validation import check_in_range, check_positive
from ..terrain import MudTerrain


class TerrainOptions(NamedTuple):
    """Validated options of a mud terrain, as :class:`~mudrft.MudTerrain` holds them."""

    characteristic_length: float  # [m]
    acceleration: bool
    reset_on_exit: bool
    xi0: float  # [-]
    heading_speed: float  # [m/s]


def terrain_options(
    mud: Any,
    foot: Any,
    *,
    characteristic_length: float | None,
    acceleration: bool,
    reset_on_exit: bool,
    xi0: float,
    heading_speed: float,
) -> tuple[Any, TerrainOptions]:
    """Take the options from a :class:`MudTerrain` (its own win) or the keywords; validate them.

    Returns the bare mud and the options; ``characteristic_length`` defaults to the foot's [m].
    """
    if isinstance(mud, MudTerrain):
        characteristic_length = mud.characteristic_length
        acceleration, reset_on_exit = mud.acceleration, mud.reset_on_exit
        xi0, heading_speed = mud.xi0, mud.heading_speed
        mud = mud.mud
    lc = characteristic_length if characteristic_length is not None else foot.characteristic_length
    return mud, TerrainOptions(
        characteristic_length=float(check_positive("characteristic_length", lc, unit="m")),
        acceleration=bool(acceleration),
        reset_on_exit=bool(reset_on_exit),
        xi0=float(check_in_range("xi0", xi0, 0.0, 1.0)),
        heading_speed=float(check_positive("heading_speed", heading_speed, unit="m/s")),
    )
