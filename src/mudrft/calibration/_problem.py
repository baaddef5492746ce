"""The fitting problem of a calibration (internal): what a fit may free, within which
bounds, on which data (the checks of :func:`~mudrft.calibration.calibrate`'s options), and
the trials packed for batched simulation, arrays ``(n_max, T)`` padded at the end, run for
a batch of ``B`` parameter sets in one pass."""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import MudrftError, check_finite, check_number
from ..constitutive import channel_constants
from ..constitutive.contact import in_contact
from ..io import IntrusionDataset, Trial, load_dataset
from ..parameters.base import MudParameters
from ..plate import plate_history

#: Parameters a fit can free (nu and k_a are never fitted: decision D41).
FIT_PARAMETERS = tuple(
    "alpha n lam eta_m eta_inf gamma_dot_c tau_build tau_leak epsilon sigma_y".split()
)
#: Parameters the model is exactly linear in (each term of eq. 1 is proportional to one).
LINEAR_PARAMETERS = ("alpha", "eta_inf", "eta_m", "sigma_y")
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
    groups = "all" if groups is None else groups
    names = groups.replace(",", " ").split() if isinstance(groups, str) else list(groups)
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


#: Phase codes of :func:`segment`.
PHASES = {"intrusion": 0, "hold": 1, "retraction": 2, "out": 3}
#: Phases whose samples a fit reads (all but "out").
ALL_PHASES = (PHASES["intrusion"], PHASES["hold"], PHASES["retraction"])

#: Fraction of the deepest displacement within which the plate counts as at the bottom
#: (hold) or back at the surface (out), decision D42.
SEGMENT_TOLERANCE = 0.01


def segment(trial: Trial, *, tolerance: float = SEGMENT_TOLERANCE) -> np.ndarray:
    """Phase of every sample of a trial: 0 intrusion, 1 hold, 2 retraction, 3 out of the mud,
    cut at ``tolerance`` of its deepest displacement [-] (decision D42)."""
    q = np.asarray(trial.depth, dtype=float)
    qmax = float(np.max(q))
    if qmax <= 0:
        return np.zeros(q.size, dtype=np.int8)
    phase = np.full(q.size, 2, dtype=np.int8)
    band = tolerance * qmax
    at_bottom = q >= qmax - band
    i_reach = int(np.argmax(at_bottom))
    i_leave = int(q.size - 1 - np.argmax(at_bottom[::-1]))
    phase[: i_reach + 1] = 0
    phase[i_reach + 1 : i_leave + 1] = 1
    after = np.nonzero(q[i_leave + 1 :] <= band)[0]
    if after.size:
        phase[i_leave + 1 + after[0] :] = 3
    return phase


@dataclass
class Packed:
    """Trials padded into ``(n_max, T)`` arrays (:func:`pack`), with phase codes, the fitted
    samples (``valid``) and each trial's weight (1 / its stress range in the mud) [1/Pa]."""

    gamma: np.ndarray
    rate: np.ndarray
    dt: np.ndarray
    data: np.ndarray
    valid: np.ndarray
    phase: np.ndarray
    weight: np.ndarray
    nu: float
    k_a: float | None
    acceleration: bool
    xi0: float
    simulations: int = 0
    thixotropy: str = "ode"
    clock: str = "contact"
    contact: bool = True

    def mask(self, phases: tuple[int, ...]) -> np.ndarray:
        """Samples (n_max, T) of the given phases (and valid)."""
        return self.valid & np.isin(self.phase, phases)

    def parameters(self, values: Mapping[str, ArrayLike]) -> MudParameters:
        """A (batched) MudParameters from a dict of arrays of shape (B,)."""
        fields: dict[str, Any] = {
            k: np.asarray(values[k], dtype=float).reshape(-1, 1) for k in FIT_PARAMETERS
        }
        return MudParameters(**fields, nu=self.nu, k_a=self.k_a)

    def simulate(self, values: Mapping[str, ArrayLike], upto: int | None = None) -> np.ndarray:
        """Total stress, shape (upto, B, T) [Pa], for a batch of parameter values; a
        non-finite one (at absurd values) is +inf, for the caller to reject."""
        n = self.data.shape[0] if upto is None else int(upto)
        p = self.parameters(values)
        B = int(np.asarray(values["alpha"]).size)
        self.simulations += 1
        with np.errstate(over="ignore", invalid="ignore", divide="ignore", under="ignore"):
            qs, restart = self.thixotropy == "quasi-static", self.clock == "retraction"
            out = plate_history(
                channel_constants(p), self.gamma[:n], self.rate[: n - 1], self.dt[: n - 1],
                kappa=1.0 if self.acceleration and not qs else 0.0, quasi_static=qs,
                restart=restart, xi0=self.xi0, contact=self.contact, batch=B,
            )[..., 0]  # fmt: skip
        out[~np.isfinite(out)] = np.inf
        return out

    def residuals(self, values: Mapping[str, ArrayLike], mask: np.ndarray) -> np.ndarray:
        """Weighted residuals (model - data)/span of a batch of parameter values over the
        masked samples, shape (m, B), simulated up to the last of them."""
        rows = np.flatnonzero(mask.any(axis=1))
        n = int(rows[-1]) + 1 if rows.size else 1
        diff = (self.simulate(values, n) - self.data[:n, None, :]) * self.weight[None, None, :]
        return diff.transpose(0, 2, 1)[mask[:n]]  # (m, B)


def pack(
    ds: IntrusionDataset,
    p: MudParameters,
    *,
    acceleration: bool,
    xi0: float,
    thixotropy: str = "ode",
    clock: str = "contact",
    exclude: Sequence[NDArray[np.bool_]] | None = None,
    direction: str | None = None,
) -> Packed:
    """The trials of ``ds`` packed for parameter sets that share ``p``'s ``nu`` [1/s] and
    ``k_a`` [1/s] (:func:`free_k_a`); ``exclude`` marks, per trial, samples left out of the
    fit; a vertical plate's samples above the surface, and the first after each entry, are
    simulated but not fitted. The other options are :func:`~mudrft.calibration.calibrate`'s.
    """
    trials = ds.trials
    contact = (direction or ds.direction) == "vertical"
    T, n_max = len(trials), max(len(t) for t in trials)
    time, gamma, data = np.zeros((n_max, T)), np.zeros((n_max, T)), np.zeros((n_max, T))
    valid = np.zeros((n_max, T), dtype=bool)
    phase = np.full((n_max, T), -1, dtype=np.int8)
    weight = np.zeros(T)
    for j, tr in enumerate(trials):
        n = len(tr)
        ph = segment(tr)
        t = tr.time - tr.time[0]
        time[:n, j] = t
        time[n:, j] = t[-1] + (t[-1] - t[-2]) * np.arange(1, n_max - n + 1)
        gamma[:n, j] = tr.gamma
        gamma[n:, j] = tr.gamma[-1]
        data[:n, j] = tr.stress
        phase[:n, j] = ph
        valid[:n, j] = ph != PHASES["out"]
        if contact:  # above the surface: no mud stress, nothing to fit; nor on entry
            inside = in_contact(tr.depth)
            valid[:n, j] &= inside & np.r_[False, inside[:-1]]
        if exclude is not None:
            valid[:n, j] &= ~np.asarray(exclude[j], dtype=bool)
        if not np.any(ph == PHASES["intrusion"]) or float(np.max(tr.depth)) <= 0:
            raise MudrftError(
                f"trial {tr.name!r} has no intrusion (depth never increases); "
                "a calibration trial must intrude into the mud"
            )
        fitted = tr.stress[valid[:n, j]]
        span = float(np.ptp(fitted)) if fitted.size else 0.0
        if not span > 0:
            raise MudrftError(
                f"trial {tr.name!r}: the stress is the same ({float(tr.stress[0]):.4g} Pa) "
                f"at every sample in the mud ({fitted.size} samples); the model has "
                "nothing to fit: is this the stress column of an intrusion log?"
            )
        weight[j] = 1.0 / span
    dt = np.diff(time, axis=0)
    return Packed(
        gamma=gamma,
        rate=np.diff(gamma, axis=0) / dt,
        dt=dt,
        data=data,
        valid=valid,
        phase=phase,
        weight=weight,
        nu=float(p.nu),
        k_a=free_k_a(p),
        acceleration=acceleration,
        xi0=xi0,
        thixotropy=thixotropy,
        clock=clock,
        contact=contact,
    )


def free_k_a(p: MudParameters) -> float | None:
    """``p.k_a`` [1/s], or None where it is the default ``1/lam`` (it then follows ``lam``)."""
    return None if np.isclose(float(p.k_a), 1.0 / float(p.lam)) else float(p.k_a)


def basis(vals: Mapping[str, ArrayLike], lin: Sequence[str]) -> dict[str, Any]:
    """Each column of ``vals`` expanded into ``1 + len(lin)`` columns: the ``lin``
    parameters all 1, then each in turn 2 (the regressors of the linear parameters)."""
    P = int(np.asarray(vals["alpha"]).size)
    out = {k: np.repeat(np.asarray(v, dtype=float), 1 + len(lin)) for k, v in vals.items()}
    for j, k in enumerate(lin):
        v = np.ones((P, 1 + len(lin)))
        v[:, 1 + j] = 2.0
        out[k] = v.ravel()
    return out


def values_of(p: MudParameters, *, batch: int) -> dict[str, NDArray[np.float64]]:
    """The fitted fields of a single set ``p`` [SI], each repeated ``batch`` times."""
    return {k: np.full(batch, float(getattr(p, k))) for k in FIT_PARAMETERS}
