"""Fitted parameters on disk: read a fit JSON (:meth:`~mudrft.calibration.FitResult.to_json`)
or a plain JSON object of SI fields."""

from __future__ import annotations

import difflib
import json
import os
from pathlib import Path
from typing import Any

from .._validation import MudrftError
from ..parameters.base import PARAMETER_UNITS, MudParameters

__all__ = ["load_parameters", "parameters_from_json", "read_json"]


def read_json(p: Path) -> dict[str, Any]:
    """The JSON object in file ``p``; an error names what is wrong (line and column)."""
    try:
        text = p.read_text(encoding="utf-8-sig")  # a byte-order mark, as CSV logs allow
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


#: What a fit file (:meth:`FitResult.to_dict`) calls itself, and the newest version read.
FIT_FORMAT, FIT_VERSION = "mudrft-fit", 1
#: Keys a plain parameter object may hold beside the fields.
_PLAIN_META = ("direction", "source", "units", "format", "version")


def parameters_from_json(data: dict[str, Any], *, where: str) -> MudParameters:
    """The parameter set of a fit dict (its ``"parameters"``) or of a plain dict of SI
    fields, read from ``where`` (named in errors); refused, naming the key: another
    format, a newer version, a unit that is not SI, an unknown field, or not one number."""
    fmt, version = data.get("format", FIT_FORMAT), data.get("version", FIT_VERSION)
    if fmt != FIT_FORMAT:
        raise MudrftError(f"{where}: format {fmt!r} is not a mudrft parameter or fit file")
    if isinstance(version, bool) or not isinstance(version, int) or version < 1:
        raise MudrftError(f"{where}: version must be a positive integer, got {version!r}")
    if version > FIT_VERSION:
        raise MudrftError(
            f"{where}: version {version} was written by a newer mudrft; this one reads "
            f"version {FIT_VERSION}: upgrade mudrft"
        )
    if "parameters" in data:
        fields = data["parameters"]
        if not isinstance(fields, dict):
            raise MudrftError(f"{where}: 'parameters' must be an object of SI values")
    else:
        fields = {k: v for k, v in data.items() if k not in _PLAIN_META}
    unknown = [k for k in fields if k not in PARAMETER_UNITS]
    if unknown:
        hints = [
            f"{k!r} (did you mean {close[0]!r}?)" if close else repr(k)
            for k in unknown
            for close in [difflib.get_close_matches(k.lower(), PARAMETER_UNITS, n=1)]
        ]
        raise MudrftError(
            f"{where}: unknown parameter {', '.join(hints)}; the fields are "
            f"{', '.join(PARAMETER_UNITS)}"
        )
    units = data.get("units", {})
    if not isinstance(units, dict):
        raise MudrftError(f"{where}: 'units' must be an object {{field: unit}}, got {units!r}")
    for k, unit in units.items():
        si = PARAMETER_UNITS.get(k)
        if si is not None and " ".join(str(unit).split()) != si:
            raise MudrftError(
                f"{where}: {k} is given in {unit!r}; mudrft reads its files in SI ({si!r}): "
                f'convert the value to {si} and write "{k}": "{si}"'
            )
    for k, v in fields.items():
        if isinstance(v, bool) or not isinstance(v, int | float):
            raise MudrftError(f"{where}: {k} must be one number [{PARAMETER_UNITS[k]}], got {v!r}")
    direction = data.get("direction", "")
    if direction not in ("", "vertical", "horizontal"):
        raise MudrftError(
            f"{where}: direction must be 'vertical' or 'horizontal', got {direction!r}"
        )
    try:
        return MudParameters.from_dict(fields, source=f"fit: {where}", direction=direction)
    except MudrftError as exc:
        raise MudrftError(f"{where}: {exc}") from None


def load_parameters(path: str | os.PathLike[str]) -> MudParameters:
    """Read a parameter set from the JSON file ``path``: a fit (:meth:`FitResult.to_json`)
    or a plain object of the SI fields of :class:`~mudrft.MudParameters` (``alpha``, ``n``,
    ``lam``, ...; ``nu`` and ``k_a`` optional)."""
    p = Path(os.fspath(path))
    return parameters_from_json(read_json(p), where=str(p))
