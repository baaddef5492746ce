"""Fitted parameters on disk: read a fit JSON, or a plain JSON object of SI fields.

Writing is :meth:`~mudrft.calibration.FitResult.to_json` (atomic, never replacing a
file without ``overwrite=True``); reading a parameter set for use anywhere in the
library is :func:`load_parameters`.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

from .._validation import MudrftError
from ..parameters.base import PARAMETER_UNITS, MudParameters

__all__ = ["load_parameters", "parameters_from_json", "read_json"]


def read_json(p: Path) -> dict[str, Any]:
    """The JSON object in file ``p``; a precise error for a missing, unreadable or
    malformed file (line and column) or for JSON that is not an object."""
    try:
        text = p.read_text(encoding="utf-8")
    except FileNotFoundError as exc:
        raise MudrftError(f"{p}: no such file") from exc
    except (OSError, UnicodeDecodeError) as exc:
        raise MudrftError(f"{p}: cannot be read ({exc})") from exc
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise MudrftError(
            f"{p}: line {exc.lineno}, column {exc.colno}: invalid JSON ({exc.msg})"
        ) from None
    if not isinstance(data, dict):
        raise MudrftError(f"{p}: expected a JSON object, got {type(data).__name__}")
    return data


def parameters_from_json(data: dict[str, Any], *, where: str) -> MudParameters:
    """The parameter set of a fit dict (its ``"parameters"``) or of a plain dict of SI fields.

    Parameters
    ----------
    data : dict
        Parsed JSON.
    where : str, keyword-only
        Where the data come from (a path), named in errors and in the set's ``source``.
    """
    fields = data.get("parameters", data)
    if not isinstance(fields, dict):
        raise MudrftError(f"{where}: 'parameters' must be an object of SI values")
    fields = {k: v for k, v in fields.items() if k in PARAMETER_UNITS}
    direction = data.get("direction", "")
    if direction not in ("", "vertical", "horizontal"):
        raise MudrftError(
            f"{where}: direction must be 'vertical' or 'horizontal', got {direction!r}"
        )
    try:
        return MudParameters.from_dict(fields, source=f"fit: {where}", direction=direction)
    except MudrftError as exc:
        raise MudrftError(f"{where}: {exc}") from None
    except TypeError as exc:
        raise MudrftError(f"{where}: bad parameter values ({exc})") from None


def load_parameters(path: str | os.PathLike[str]) -> MudParameters:
    """Read a parameter set from a fit JSON (:meth:`FitResult.to_json`) or a plain JSON object.

    A plain object holds the SI fields of :class:`~mudrft.MudParameters`
    (``alpha``, ``n``, ``lam``, ...; ``nu`` and ``k_a`` optional).

    Parameters
    ----------
    path : str or path-like
        The JSON file.

    Returns
    -------
    MudParameters
    """
    p = Path(os.fspath(path))
    return parameters_from_json(read_json(p), where=str(p))
