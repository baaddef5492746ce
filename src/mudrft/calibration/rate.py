r"""The rate of a logged depth, read to survive the sensor's noise (which biases every
rate-dependent constant towards zero by :math:`x^2/(1+x^2)`, :math:`x` the rate noise over
the speed): :func:`smooth_trial` fits the depth as constant-speed segments, or smooths it
with a local-linear kernel; samples whose step spans a change of speed are not fitted.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import replace
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from .._validation import MudrftError
from ..io import IntrusionDataset, Trial

#: The smoothing window is chosen for a rate noise of at most this fraction of the trial's
#: speed [-]; the bias it leaves on the rate-dependent constants is about its square.
RATE_NOISE = 0.01
#: A change of slope across a sample larger than this many of its standard errors (and than
#: :data:`RATE_NOISE` of the speed) is a change of speed [-].
KINK_Z = 5.0
#: Warn when the rate's noise biases the rate-dependent constants by more than this [-].
BIAS_WARNING = 0.01
#: The window is at most this fraction of the trial's samples in the mud [-].
_MAX_WINDOW_FRACTION = 0.1
#: Segments describe a depth whose residual's mean square is at most this times the noise's.
_NOISE_RATIO = 1.3


class Smoothing(NamedTuple):
    """How the depth of trial ``name`` was read: ``method`` (``"as logged"``,
    ``"segments"`` or ``"kernel"``), the ``window`` of the slopes or kernel [samples], the
    median step ``dt`` [s], the depth's noise [m], the rate's noise [m/s], the trial's
    ``speed`` [m/s], and the time spans [s] in which the speed ``changes``."""

    name: str
    method: str
    window: int
    dt: float
    depth_noise: float
    rate_noise: float
    speed: float
    changes: tuple[tuple[float, float], ...]

    @property
    def bias(self) -> float:
        """Relative bias [-] of the rate-dependent constants from the rate's noise, the
        attenuation of errors in the variables (in the module's docstring)."""
        x2 = (self.rate_noise / self.speed) ** 2 if self.speed > 0 else 0.0
        return x2 / (1.0 + x2)

    def excluded(self, time: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Samples at ``time`` [s] whose step, or the step before it, spans a change of speed."""
        t = np.asarray(time, dtype=float)
        out = np.zeros(t.size, dtype=bool)
        for a, b in self.changes:
            spans = np.flatnonzero((t[:-1] < b) & (t[1:] >= a)) + 1
            out[spans] = True
            out[np.minimum(spans + 1, t.size - 1)] = True
        return out

    def note(self) -> str:
        """One line: how the depth was read, its noise and the rate's."""
        what = {
            "as logged": "as logged",
            "segments": f"fitted as {len(self.changes) + 1} constant-speed segments",
            "kernel": f"smoothed over {self.window} samples ({1e3 * self.window * self.dt:.3g} ms)",
        }[self.method]
        share = f" ({100 * self.rate_noise / self.speed:.2g} % of the speed)" if self.speed else ""
        return (
            f"{self.name}: depth noise {1e3 * self.depth_noise:.3g} mm, {what}, rate noise "
            f"{1e3 * self.rate_noise:.3g} mm/s{share}, {len(self.changes)} changes of speed"
        )


#: Samples [-] below which :func:`depth_noise` cannot tell noise from motion.
NOISE_MIN_SAMPLES = 16


def depth_noise(depth: NDArray[np.float64]) -> float:
    r"""Standard deviation of a logged depth's noise [m],
    :math:`1.4826\,\mathrm{median}|\Delta^2 q|/\sqrt6` (a change of speed is an outlier
    the median ignores); 0 for fewer than :data:`NOISE_MIN_SAMPLES` samples.

    Examples
    --------
    >>> q = np.random.default_rng(0).normal(0.0, 2e-5, 5000) + 0.01 * np.linspace(0, 1, 5000)
    >>> round(depth_noise(q) / 2e-5, 1)
    1.0
    """
    d2 = np.diff(np.asarray(depth, dtype=float), 2)
    if d2.size + 2 < NOISE_MIN_SAMPLES:
        return 0.0
    return 1.4826 * float(np.median(np.abs(d2))) / math.sqrt(6.0)


def slope_noise(sigma: float, samples: int, dt: float) -> float:
    """Noise [m/s] of the least-squares slope of ``samples`` [-] depths of noise ``sigma``
    [m], ``dt`` [s] apart: :math:`\\sigma\\sqrt{12/(m(m^2-1))}/\\Delta t`."""
    m = max(int(samples), 2)
    return sigma * math.sqrt(12.0 / (m * (m * m - 1))) / dt


def _kernel_smooth(depth: NDArray[np.float64], half_width: int) -> NDArray[np.float64]:
    """The depth [m] averaged with parabolic weights over ``2h+1`` samples, so that the
    difference of two neighbours is the least-squares slope of the ``2h+2`` samples around
    them; the ends are extended by odd reflection (a constant speed stays exact)."""
    i = np.arange(-half_width, half_width + 1, dtype=float)
    w = (half_width + 0.5) ** 2 - i * i
    padded = np.pad(depth, half_width, mode="reflect", reflect_type="odd")
    return np.convolve(padded, w / w.sum(), mode="valid")


def speed_changes(
    time: NDArray[np.float64],
    depth: NDArray[np.float64],
    half_width: int,
    sigma: float,
    speed: float,
) -> list[int]:
    """The samples where the speed changes: where the least-squares slopes of the
    ``half_width + 1`` samples before and after differ by more than :data:`KINK_Z` standard
    errors (depth noise ``sigma`` [m]) and :data:`RATE_NOISE` of ``speed`` [m/s]."""
    n = depth.size
    k = max(half_width, 1) + 1
    if n < 2 * k + 1:
        return []
    dt = float(np.median(np.diff(time)))
    j = np.arange(k, dtype=float) - (k - 1) / 2.0
    slope = np.convolve(depth, (j / float(j @ j) / dt)[::-1], mode="valid")  # of depth[i:i+k]
    jump = np.zeros(n)
    jump[k - 1 : n - k + 1] = slope[k - 1 :] - slope[: n - 2 * k + 2]
    se = math.sqrt(2.0) * slope_noise(sigma, k, dt)
    big = np.abs(jump) > max(KINK_Z * se, RATE_NOISE * speed)
    groups, count = ndimage.label(ndimage.binary_closing(big, np.ones(k, dtype=bool)) | big)
    at = ndimage.maximum_position(np.abs(jump), groups, range(1, count + 1))
    return [int(a[0]) for a in at]


def _segments(
    time: NDArray[np.float64], depth: NDArray[np.float64], at: list[int], margin: int, sigma: float
) -> tuple[NDArray[np.float64], NDArray[np.float64], float] | None:
    """The depth [m] fitted as continuous constant-speed segments between the changes
    ``at`` (sample indices), each placed where the lines of its two segments meet, a
    segment within :data:`KINK_Z` standard errors of still held exactly still; returns the
    change times [s], the fitted depth [m] and the largest standard error of a moving
    segment's speed [m/s]; None if a segment is too short to fit."""
    bounds = [0, *at, depth.size - 1]
    lines = []
    for a, b in itertools.pairwise(bounds):
        lo, hi = (a + margin, b - margin) if b - a > 4 * margin else (a, b)
        if hi - lo < 2:
            return None
        lines.append(np.polyfit(time[lo : hi + 1], depth[lo : hi + 1], 1))
    knots = []
    for i, (l1, l2) in enumerate(itertools.pairwise(lines)):
        dv = l1[0] - l2[0]
        t_meet = (l2[1] - l1[1]) / dv if dv != 0 else np.inf
        near = time[max(at[i] - margin - 1, 0)], time[min(at[i] + margin + 1, time.size - 1)]
        knots.append(t_meet if near[0] <= t_meet <= near[1] else time[at[i]])
    nodes = np.r_[time[0], np.sort(knots), time[-1]]
    if np.any(np.diff(nodes) <= 0):
        return None
    hats = np.stack([np.interp(time, nodes, e) for e in np.eye(nodes.size)], axis=1)
    inv = np.linalg.pinv(hats.T @ hats)
    c = inv @ hats.T @ depth
    # the speed of each segment and its standard error
    D = (np.eye(nodes.size, k=1) - np.eye(nodes.size))[:-1] / np.diff(nodes)[:, None]
    speed = D @ c
    se = sigma * np.sqrt(np.einsum("ij,jk,ik->i", D, inv, D))
    still = np.abs(speed) <= KINK_Z * se
    group = np.r_[0, np.cumsum(~still)]  # nodes joined by a still segment share a depth
    merged = hats @ np.eye(group[-1] + 1)[group]
    fitted = merged @ np.linalg.lstsq(merged, depth, rcond=None)[0]
    moving = se[~still]
    return np.asarray(knots), fitted, float(moving.max()) if moving.size else 0.0


def smooth_trial(trial: Trial, *, window: int | str = "auto") -> tuple[Trial, Smoothing]:
    """The ``trial`` with the depth [m] the model reads, for a rate that survives the
    sensor's noise, and what was done (:class:`Smoothing`). ``window``: ``"auto"``
    constant-speed segments when they describe the depth, else the kernel over the fewest
    samples whose rate noise is :data:`RATE_NOISE` of the trial's speed (at most a tenth of
    its samples in the mud), and the depth as logged when it has no noise to speak of;
    ``"raw"`` the depth as logged; an odd int the kernel over that many samples.

    Examples
    --------
    >>> t = np.arange(0.0, 4.0, 0.002)
    >>> q = 0.01 * np.clip(t - 0.5, 0.0, 3.0) + np.random.default_rng(1).normal(0, 2e-5, t.size)
    >>> tr, how = smooth_trial(Trial(t, q, 1e5 * np.clip(q, 0, None)))
    >>> how.method, [round(a, 2) for a, _ in how.changes]
    ('segments', [0.5, 3.5])
    """
    t = trial.time
    q = np.asarray(trial.depth, dtype=float)
    dt = float(np.median(np.diff(t)))
    sigma = depth_noise(q)
    speed = trial.speed
    if window == "auto":
        h_max = int(_MAX_WINDOW_FRACTION * np.count_nonzero(q > 0)) // 2
        h = 0
        while h < h_max and slope_noise(sigma, 2 * h + 2, dt) > RATE_NOISE * speed:
            h += 1
    else:
        h = 0 if window == "raw" else (int(window) - 1) // 2
    at = speed_changes(t, q, h, sigma, speed)
    method, depth, rate = ("as logged", q, slope_noise(sigma, 2, dt))
    changes = tuple((float(t[max(i - 1, 0)]), float(t[min(i + 1, t.size - 1)])) for i in at)
    fitted = _segments(t, q, at, h + 1, sigma) if window == "auto" and sigma > 0 else None
    # segments describe a depth whose residual is the depth's noise and no more
    if fitted is not None and np.mean((q - fitted[1]) ** 2) <= _NOISE_RATIO * sigma**2:
        method, depth, rate = "segments", fitted[1], fitted[2]
        changes = tuple((float(k), float(k)) for k in fitted[0])
    elif h > 0:
        method, depth, rate = "kernel", _kernel_smooth(q, h), slope_noise(sigma, 2 * h + 2, dt)
        span = (h + 1) * dt
        changes = tuple((float(t[i]) - span, float(t[i]) + span) for i in at)
    how = Smoothing(trial.name, method, 2 * h + 1, dt, sigma, rate, speed, changes)
    if depth is q:
        return trial, how
    return replace(trial, depth=depth, meta={**trial.meta, "depth": how.note()}), how


def check_window(window: object) -> int | str:
    """The ``rate`` option of a fit: ``"auto"``, ``"raw"`` or an odd int >= 1 [samples]."""
    if isinstance(window, str) and window in ("auto", "raw"):
        return window
    if isinstance(window, (int, np.integer)) and not isinstance(window, bool):
        if window >= 1 and window % 2 == 1:
            return int(window)
    raise MudrftError(
        f"rate must be 'auto', 'raw' or an odd number of samples >= 1 to smooth the depth "
        f"over, got {window!r}"
    )


def smooth_dataset(
    ds: IntrusionDataset, window: int | str = "auto"
) -> tuple[IntrusionDataset, list[Smoothing], list[str]]:
    """Every trial through :func:`smooth_trial`: the data, what was done to each trial, and
    the warnings (a rate noise that biases the rate-dependent constants more than
    :data:`BIAS_WARNING`)."""
    window = check_window(window)
    hint = "; rate='auto' reads the depth for a rate that survives it" if window == "raw" else ""
    read = [smooth_trial(tr, window=window) for tr in ds.trials]
    done = [how for _, how in read]
    warned = [
        f"trial {how.name!r}: the depth's noise ({1e3 * how.depth_noise:.3g} mm) leaves "
        f"a rate noise of {1e3 * how.rate_noise:.3g} mm/s, "
        f"{100 * how.rate_noise / how.speed:.3g} % of the speed "
        f"({1e3 * how.speed:.3g} mm/s), the depth read {how.method}: the "
        "rate-dependent constants (eta_inf, eta_m, lam, gamma_dot_c, tau_build, "
        f"tau_leak) come out about {100 * how.bias:.2g} % too small{hint}"
        for how in done
        if how.bias > BIAS_WARNING
    ]
    return replace(ds, trials=tuple(tr for tr, _ in read)), done, warned
