"""The trials of a dataset packed for batched simulation (internal): arrays ``(n_max, T)``
padded at the end, run for a batch of ``B`` parameter sets in one pass."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import MudrftError
from ..constitutive import channel_constants
from ..constitutive.contact import in_contact
from ..io import IntrusionDataset, Trial
from ..parameters.base import MudParameters
from ..plate import plate_history

#: Parameters a fit can free (nu and k_a are never fitted: decision D41).
FIT_PARAMETERS = tuple(
    "alpha n lam eta_m eta_inf gamma_dot_c tau_build tau_leak epsilon sigma_y".split()
)
#: Parameters the model is exactly linear in (each term of eq. 1 is proportional to one).
LINEAR_PARAMETERS = ("alpha", "eta_inf", "eta_m", "sigma_y")
#: Phase codes of :func:`segment`.
PHASES = {"intrusion": 0, "hold": 1, "retraction": 2, "out": 3}
#: Phases whose samples a fit reads (all but "out").
ALL_PHASES = (PHASES["intrusion"], PHASES["hold"], PHASES["retraction"])

#: Fraction of the deepest displacement within which the plate counts as at the bottom
#: (hold) or back at the surface (out), decision D42.
SEGMENT_TOLERANCE = 0.01


def segment(trial: Trial, *, tolerance: float = SEGMENT_TOLERANCE) -> np.ndarray:
    """Phase of every sample of a trial: 0 intrusion, 1 hold, 2 retraction, 3 out of the mud.

    Intrusion runs until the depth first comes within ``tolerance`` of its deepest, the
    hold until it last leaves that band, the retraction until the depth is back within the
    band around the surface; later samples are "out" (decision D42).
    """
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
