"""What a fit may free, within which bounds, and on which data (internal): the checks of
:func:`~mudrft.calibration.calibrate`'s options."""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Sequence
from dataclasses import replace
from typing import Any, cast

import numpy as np

from .._validation import MudrftError, check_finite, check_number
from ..io import IntrusionDataset, Trial, load_dataset
from ._problem import FIT_PARAMETERS

#: Parameter groups of the supplementary Sec. III-A; sigma_Y is fitted with the suction
#: group (decision D41).
GROUPS: dict[str, tuple[str, ...]] = {
    "b": ("alpha", "n"),
    "th": ("lam", "eta_m", "eta_inf", "gamma_dot_c"),
    "s": ("tau_build", "tau_leak", "epsilon", "sigma_y"),
}
_GROUP_ALIASES = {
    **dict.fromkeys(("b", "pi_b", "intrusion", "elastic"), "b"),
    **dict.fromkeys(("th", "pi_th", "relaxation", "thixotropic"), "th"),
    **dict.fromkeys(("s", "pi_s", "retraction", "suction"), "s"),
}

#: Default bounds of the fitted parameters, SI (wide: two to four decades around the
#: paper's tables); ``n`` is bounded by the model's (0, 1].
DEFAULT_BOUNDS: dict[str, tuple[float, float]] = {
    "alpha": (1.0, 1.0e8),
    "n": (0.02, 1.0),
    "lam": (0.01, 1.0e3),
    "eta_m": (1.0, 1.0e9),
    "eta_inf": (1.0e-2, 1.0e9),
    "gamma_dot_c": (1.0e-4, 1.0e2),
    "tau_build": (1.0e-3, 1.0e2),
    "tau_leak": (1.0e-3, 1.0e2),
    "epsilon": (1.0e-4, 1.0),
    "sigma_y": (1.0e-2, 1.0e8),
}


#: Samples per trial a fit thins longer logs to unless ``decimate`` is given (D104) [-].
FIT_SAMPLES = 2000


def auto_decimate(ds: IntrusionDataset) -> int:
    """The thinning factor that brings the longest trial to about :data:`FIT_SAMPLES` [-].

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0.0, 1.0, 10_001)
    >>> auto_decimate(IntrusionDataset((Trial(t, 0.01 * t, 100.0 * t),)))
    6
    """
    longest = max(len(t) for t in ds.trials)
    return max(1, math.ceil(longest / FIT_SAMPLES))


def _group_members(name: object) -> tuple[str, ...]:
    if not isinstance(name, str):
        raise MudrftError(f"groups must be names, got {name!r}")
    key = name.strip().lower()
    if key == "all":
        return FIT_PARAMETERS
    if key in _GROUP_ALIASES:
        return GROUPS[_GROUP_ALIASES[key]]
    if key in FIT_PARAMETERS:
        return (key,)
    raise MudrftError(
        f"groups must name parameter groups ('b', 'th', 's', 'all') or parameters "
        f"{list(FIT_PARAMETERS)}, got {name!r}"
    )


def resolve_groups(groups: str | Iterable[str] | None) -> tuple[str, ...]:
    """The parameters named by ``groups`` (``"all"``/None, group names, aliases or parameter
    names, as a sequence or a space- or comma-separated string), in fitting order."""
    if groups is None or groups == "all":
        names: Iterable[object] = ("b", "th", "s")
    elif isinstance(groups, str):
        names = [g for g in groups.replace(",", " ").split() if g]
    else:
        names = list(groups)
    free = {k for g in names for k in _group_members(g)}
    if not free:
        raise MudrftError("groups selects no parameter to fit")
    return tuple(k for k in FIT_PARAMETERS if k in free)


def _check_name(option: str, name: str) -> None:
    if name not in FIT_PARAMETERS:
        raise MudrftError(
            f"{option} has an unknown parameter {name!r}; expected {list(FIT_PARAMETERS)}"
        )


def resolve_bounds(bounds: dict[str, tuple[float, float]] | None) -> dict[str, tuple[float, float]]:
    """:data:`DEFAULT_BOUNDS` with the user's ``{name: (low, high)}`` [SI] applied."""
    out = dict(DEFAULT_BOUNDS)
    for k, v in (bounds or {}).items():
        _check_name("bounds", k)
        try:
            lo, hi = (float(v[0]), float(v[1]))
        except (TypeError, ValueError, IndexError):
            raise MudrftError(f"bounds[{k!r}] must be a pair (low, high), got {v!r}") from None
        if not (0 < lo < hi < math.inf):
            raise MudrftError(f"bounds[{k!r}] must satisfy 0 < low < high < inf, got {v!r}")
        if k == "n" and hi > 1.0:
            raise MudrftError(f"bounds['n'] must not exceed 1 (the model needs n <= 1), got {v!r}")
        out[k] = (lo, hi)
    return out


def resolve_fixed(fixed: dict[str, float] | None) -> dict[str, float]:
    """The user's ``{name: value}`` [SI] of parameters held fixed, names checked."""
    out = dict(fixed or {})
    for k in out:
        _check_name("fixed", k)
        out[k] = check_number(f"fixed[{k!r}]", check_finite(f"fixed[{k!r}]", out[k]))
    return out


def as_dataset(
    data: IntrusionDataset | Trial | str | os.PathLike[str] | Sequence[object], **load_options: Any
) -> IntrusionDataset:
    """The data of a fit as one dataset: datasets merged, trials joined, paths loaded with
    :func:`mudrft.io.load_dataset` and ``load_options`` (``area`` [m^2], ...)."""
    kinds: tuple[type | tuple[type, ...], ...] = (IntrusionDataset, Trial, (str, os.PathLike))
    one = isinstance(data, kinds) or not isinstance(data, Sequence)
    items = [data] if one else list(data)  # type: ignore[arg-type]
    found = {next((i for i, c in enumerate(kinds) if isinstance(x, c)), None) for x in items}
    if not items or len(found) != 1 or None in found:
        raise MudrftError(
            "dataset must be an IntrusionDataset, a Trial, a path or a list of them, "
            f"got {type(data).__name__}"
        )
    given = sorted(k for k, v in load_options.items() if v is not None)
    if given and found != {2}:  # they describe how to read a file; a dataset has them
        raise MudrftError(
            f"{' and '.join(given)} apply to a log read from a path; this dataset is already "
            "loaded (its trials carry their characteristic_length, and stress, not force): "
            "leave them out, or pass the file's path"
        )
    if isinstance(data, IntrusionDataset):
        return data
    if found == {2}:
        return load_dataset(data if one else items, **load_options)  # type: ignore[arg-type]
    if found == {1}:
        return IntrusionDataset(tuple(items))  # type: ignore[arg-type]
    datasets = cast(list[IntrusionDataset], items)
    return datasets[0].merge(*datasets[1:])


def thin_trials(ds: IntrusionDataset, k: int) -> IntrusionDataset:
    """Every ``k``-th sample of each trial, plus its deepest and last samples."""
    trials = []
    for tr in ds.trials:
        n = len(tr)
        keep = np.unique(np.r_[np.arange(0, n, k), int(np.argmax(tr.depth)), n - 1])
        meta = {**tr.meta, "decimated": k}
        trials.append(
            replace(tr, time=tr.time[keep], depth=tr.depth[keep], stress=tr.stress[keep], meta=meta)
        )
    return replace(ds, trials=tuple(trials))
