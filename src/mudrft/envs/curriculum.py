"""A curriculum of mud fields: how hard each is to walk in, and the fields in that order."""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from .._validation import MudrftError, positive_number
from ..feet.base import Foot
from ..simulation import static_sinking
from ..terrains.field import MudField

__all__ = ["by_difficulty", "difficulty"]


def difficulty(field: MudField, *, load: float = 50.0, foot: Foot | None = None) -> float:
    """The mean over the field's cells of the static sinking [m] of ``foot`` (the paper's
    flat foot) under ``load`` [N] (rigid ground: 0): wetter and softer mud sinks deeper.

    >>> import mudrft
    >>> firm, wet = (mudrft.MudField({"m": w}, ["m"]) for w in (0.25, 0.45))
    >>> difficulty(firm) < difficulty(wet)
    True
    """
    from ..feet import Flat

    if not isinstance(field, MudField):
        raise MudrftError(f"field must be a MudField, got {type(field).__name__}")
    w = positive_number("load", load, unit="N")
    f = Flat() if foot is None else foot
    depth = [0.0 if t is None else static_sinking(f, t.mud, w) for t in field.terrains]
    return float(np.mean(np.asarray(depth)[field.cells]))


def by_difficulty(fields: Iterable[MudField], **options: object) -> list[MudField]:
    """``fields`` from the easiest to the hardest (:func:`difficulty`, its ``options``):
    give them in turn to ``env.reset(options={"field": f})``."""
    return sorted(fields, key=lambda f: difficulty(f, **options))  # type: ignore[arg-type]
