"""Which known mud a log (:func:`classify`) or a stream (:class:`StreamClassifier`)
resembles: every candidate set runs the full model on the data, and its residuals give a
Gaussian likelihood and, with equal priors, a probability (decision D47); and the checked
stream of samples that it and :class:`~mudrft.calibration.OnlineEstimator` read."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import (
    LENGTH_LIMITS,
    MudrftError,
    check_characteristic_length,
    check_choice,
    positive_number,
    warn_implausible,
)
from ..constitutive import channel_constants, channel_update, initial_state
from ..constitutive.contact import in_contact
from ..io import IntrusionDataset
from ..io._build import DIRECTIONS, PLAUSIBLE_DEPTH, PLAUSIBLE_PEAK_STRESS
from ..parameters.base import MudParameters
from ..parameters.registry import paper_parameters
from ..plate import DEFAULT_PLATE_LENGTH
from ._problem import ALL_PHASES, FIT_PARAMETERS, free_k_a, pack

__all__ = ["Classification", "StreamClassifier", "classify"]

#: Largest stress magnitude a streamed sample may have [Pa] (1e300 overflowed the filters).
MAX_STRESS = 1e12


class Sample(NamedTuple):
    """One checked sample: time [s], :math:`\\gamma=q/L_c` [-], stress [Pa], and the step
    from the previous sample, ``(dt [s], mean rate [1/s], previous time [s])`` (None for the
    first)."""

    time: float
    gamma: float
    stress: float
    step: tuple[float, float, float] | None


class SampleStream:
    """The last sample of a stream of plate length ``characteristic_length`` [m] (checked);
    checks each new one (finite, plausible, time increasing)."""

    def __init__(self, characteristic_length: float) -> None:
        self.L = float(characteristic_length)
        self.last: tuple[float, float] | None = None
        self.warned = False  # one plausibility warning a stream, not one a sample

    def reset(self) -> None:
        """Forget the previous sample."""
        self.last = None

    def push(self, time: float, depth: float, stress: float) -> Sample:
        """Check one sample (time [s], depth [m], stress [Pa]) and step to it."""
        t, q, s = _number("time", time), _number("depth", depth), _number("stress", stress)
        for what, given, v, limit, unit in (
            ("stress", stress, s, MAX_STRESS, "Pa"), ("depth", depth, q, LENGTH_LIMITS[1], "m")
        ):  # fmt: skip
            if abs(v) > limit:
                raise MudrftError(
                    f"update: {what} must be at most {limit:g} {unit} in magnitude (no mud "
                    f"test reaches it: a unit mistake?), got {given!r}"
                )
        big_depth = abs(q) > PLAUSIBLE_DEPTH[1]
        if not self.warned and (big_depth or abs(s) > PLAUSIBLE_PEAK_STRESS[1]):
            # a depth in mm or a stress in a wrong unit, as the log loader warns
            self.warned = warn_implausible(
                f"update: {'depth' if big_depth else 'stress'} of",
                abs(q) if big_depth else abs(s),
                PLAUSIBLE_DEPTH if big_depth else PLAUSIBLE_PEAK_STRESS,
                unit="m" if big_depth else "Pa",
                hint="stream SI values (depth in m, stress in Pa, time in s); "
                "this warning is shown once a stream",
            )
        previous, g = self.last, q / self.L
        if previous is not None and not t > previous[0]:
            raise MudrftError(
                f"update: time must increase between updates, got {t!r} [s] after "
                f"{previous[0]!r} [s]; a trial whose clock starts again: add the previous "
                "trial's last time to its times (the estimates carry on), or call reset() "
                "first (they start again from the prior)"
            )
        self.last = (t, g)
        if previous is None:
            return Sample(t, g, s, None)
        t0, g0 = previous
        return Sample(t, g, s, (t - t0, (g - g0) / (t - t0), t0))


def _number(name: str, value: Any) -> float:
    """``float(value)`` for a sample, or an error naming it (a string, None, a list, nan)."""
    if isinstance(value, str | bytes | bool) or value is None:
        raise MudrftError(f"update: {name} must be a number, got {value!r}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise MudrftError(
            f"update: {name} must be a number, got {type(value).__name__} {value!r}"
        ) from None
    if not math.isfinite(v):
        raise MudrftError(f"update: {name} must be finite, got {value!r}")
    return v


def _candidates(
    candidates: MudParameters | Sequence[MudParameters] | None,
    labels: Sequence[Any] | None,
    water_contents: ArrayLike | None,
    direction: str,
) -> tuple[list[MudParameters], list[Any]]:
    """The candidate sets and their labels (default: water contents [-] or sources), checked."""
    if candidates is not None and water_contents is not None:
        raise MudrftError("give either candidates or water_contents, not both")
    if candidates is None:
        ws = [0.25, 0.35, 0.45] if water_contents is None else list(np.atleast_1d(water_contents))
        cands = [paper_parameters(float(w), direction) for w in ws]
        default: list[Any] = [float(w) for w in ws]
    else:
        cands = [candidates] if isinstance(candidates, MudParameters) else list(candidates)
        for i, c in enumerate(cands):
            if not isinstance(c, MudParameters) or c.shape != ():
                raise MudrftError(f"candidates[{i}] must be a single MudParameters, got {c!r}")
        default = [c.source or f"set {i}" for i, c in enumerate(cands)]
    labs = default if labels is None else list(labels)
    if len(labs) != len(cands):
        raise MudrftError(
            f"labels must have one entry per candidate ({len(cands)}), got {len(labs)}"
        )
    if len(cands) < 1:
        raise MudrftError("candidates must hold at least one MudParameters")
    return cands, labs


def _softmax_loglik(
    sse: NDArray[np.float64], count: float, noise: float | None
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Gaussian log-likelihoods of the residual sums and the probabilities (equal priors),
    for a noise standard deviation ``noise`` (default the best candidate's RMS)."""
    var = max(float(np.min(sse)) / max(count, 1.0), 1e-300) if noise is None else noise**2
    ll = -0.5 * sse / var
    p = np.exp(ll - ll.max())
    return ll, p / p.sum()


@dataclass(frozen=True)
class Classification:
    """Which candidate parameter set a dataset most resembles.

    Attributes
    ----------
    labels : tuple
        Candidate labels (water contents for the paper's rows).
    relative_rmse, log_likelihood, probabilities : ndarray
        Of each candidate over the fitted samples [-]: relative RMSE (decision D12),
        Gaussian log-likelihood, and probability with equal priors.
    best : object
        Label of the most likely candidate.
    """

    labels: tuple
    relative_rmse: NDArray[np.float64]
    log_likelihood: NDArray[np.float64]
    probabilities: NDArray[np.float64]
    best: Any


def classify(
    dataset: IntrusionDataset,
    candidates: Sequence[MudParameters] | None = None,
    *,
    labels: Sequence[Any] | None = None,
    water_contents: ArrayLike | None = None,
    direction: str | None = None,
    noise: float | None = None,
) -> Classification:
    """Which known parameter set (paper row or user list) an offline dataset resembles,
    from the residuals of each trial relative to its stress range.

    Parameters
    ----------
    dataset : IntrusionDataset
        The data.
    candidates : sequence of MudParameters, optional
        Candidate sets; default the paper's rows (W = 25, 35, 45 %) of the direction.
    labels : sequence, optional, keyword-only
        Label of each candidate (default: the water contents, or the sources).
    water_contents : array_like, optional, keyword-only
        Paper sets interpolated at these water contents [-] as candidates.
    direction : {"vertical", "horizontal"}, optional, keyword-only
        Default the dataset's.
    noise : float, optional, keyword-only
        Standard deviation of the residuals relative to each trial's range [-];
        default estimated from the best candidate.

    Examples
    --------
    >>> from mudrft.calibration import example_dataset
    >>> classify(example_dataset("vertical")).best
    0.25
    """
    if not isinstance(dataset, IntrusionDataset):
        raise MudrftError(f"dataset must be an IntrusionDataset, got {type(dataset).__name__}")
    d = check_choice("direction", dataset.direction if direction is None else direction, DIRECTIONS)
    cands, labs = _candidates(candidates, labels, water_contents, d)
    # residuals (m, K) relative to each trial's range, from one batched simulation, or one
    # per candidate when they differ in nu or k_a
    same = all(free_k_a(c) is None for c in cands) and len({float(c.nu) for c in cands}) == 1
    groups = [cands] if same else [[c] for c in cands]
    packs = [pack(dataset, g[0], acceleration=True, xi0=0.0) for g in groups]
    mask = packs[0].mask(ALL_PHASES)
    values = [{k: np.array([getattr(c, k) for c in g]) for k in FIT_PARAMETERS} for g in groups]
    R = np.concatenate([p.residuals(v, mask) for p, v in zip(packs, values, strict=True)], axis=1)
    sse = np.sum(R**2, axis=0)
    m = R.shape[0]
    ll, prob = _softmax_loglik(sse, m, None if noise is None else positive_number("noise", noise))
    return Classification(
        labels=tuple(labs),
        relative_rmse=np.sqrt(sse / m),
        log_likelihood=ll,
        probabilities=prob,
        best=labs[int(np.argmax(ll))],
    )


class StreamClassifier:
    """Which known parameter set a stream of samples most resembles, updated per sample.

    Parameters
    ----------
    candidates, labels, water_contents : optional
        As :func:`classify`; the paper's rows are those of ``direction``.
    direction : {"vertical", "horizontal"}, keyword-only
        Direction of the paper rows.
    characteristic_length : float, keyword-only
        Plate length [m].
    window : float, keyword-only
        Effective window length [samples] (> 1): each candidate's squared residuals are
        discounted by ``1 - 1/window`` per sample.
    noise : float, optional, keyword-only
        Stress noise standard deviation [Pa]; default the best candidate's windowed RMS.

    Examples
    --------
    >>> import mudrft
    >>> tr = mudrft.plate_intrusion(depth=0.03, speed=0.02, hold=0.5, dt=0.01)
    >>> res = mudrft.plate_response(tr, mudrft.paper_parameters(0.35))
    >>> clf = StreamClassifier()
    >>> for t, q, s in zip(tr.time, res.displacement, res.stress):
    ...     _ = clf.update(t, q, s)
    >>> clf.best
    0.35
    """

    def __init__(
        self,
        candidates: Sequence[MudParameters] | None = None,
        *,
        labels: Sequence[Any] | None = None,
        water_contents: ArrayLike | None = None,
        direction: str = "vertical",
        characteristic_length: float = DEFAULT_PLATE_LENGTH,
        window: float = 200.0,
        noise: float | None = None,
    ) -> None:
        check_choice("direction", direction, ("vertical", "horizontal"))
        self.candidates, self.labels = _candidates(candidates, labels, water_contents, direction)
        self.L = check_characteristic_length("StreamClassifier", characteristic_length)
        w = positive_number("window", window)
        if w <= 1.0:
            raise MudrftError(f"window must exceed 1 sample, got {window!r}")
        self.decay = 1.0 - 1.0 / w
        self.noise = None if noise is None else positive_number("noise", noise, unit="Pa")
        self.params = MudParameters.stack(self.candidates)
        self._consts = channel_constants(self.params)
        self._stream = SampleStream(self.L)
        self.reset()

    def reset(self) -> None:
        """Forget the stream."""
        K = len(self.candidates)
        self._state = initial_state((K,))
        self._sse = np.zeros(K)
        self._count = 0.0
        self._stream.reset()
        self._inside = False

    def update(self, time: float, depth: float, stress: float) -> Any:
        """Add one sample, its ``time`` [s] (increasing), ``depth`` [m] and ``stress`` [Pa];
        return the label of the most likely candidate."""
        x = self._stream.push(time, depth, stress)
        K = len(self.candidates)
        if x.step is None:  # the first sample: a starting point only
            self._state = initial_state((K,), gamma=x.gamma)
            return self.best
        dt, rate, _ = x.step
        if not in_contact(x.gamma):
            # above the surface: nothing to compare; the next intrusion starts afresh (D11)
            if self._inside:
                self._state = initial_state((K,), gamma=x.gamma)
                self._inside = False
            return self.best
        self._inside = True
        gv, gdv = np.full(K, x.gamma), np.full(K, rate)
        self._state, model = channel_update(self._consts, self._state, gv, gdv, dt)
        r = x.stress - np.asarray(model.total)
        self._sse = self.decay * self._sse + r * r
        self._count = self.decay * self._count + 1.0
        return self.best

    @property
    def log_likelihood(self) -> NDArray[np.float64]:
        """Gaussian log-likelihood of each candidate over the window [-]."""
        return _softmax_loglik(self._sse, self._count, self.noise)[0]

    @property
    def probabilities(self) -> NDArray[np.float64]:
        """Posterior probability of each candidate (equal priors) [-]."""
        return _softmax_loglik(self._sse, self._count, self.noise)[1]

    @property
    def rmse(self) -> NDArray[np.float64]:
        """Windowed RMS residual of each candidate [Pa]."""
        return np.sqrt(self._sse / max(self._count, 1e-300))

    @property
    def best(self) -> Any:
        """Label of the most likely candidate (the first one before any sample)."""
        return self.labels[int(np.argmin(self._sse))]

    def __repr__(self) -> str:
        return f"StreamClassifier(labels={self.labels!r}, best={self.best!r})"
