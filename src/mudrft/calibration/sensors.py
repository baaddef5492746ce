r"""What a log's force sensor did wrong, found before a fit (decisions D153, D154).

Two faults of a rig's force sensor bias every fitted constant without the fit noticing:

* **saturation** (:func:`clipped_samples`, decision D153): a sensor at the end of its
  range logs the same value, its limit, for every sample beyond it. The model cannot
  follow a flat top, and one clipped run among four (clipped at 80 % of its peak) moved
  :math:`\lambda` by 42 % and :math:`\eta_m` by 37 % with no warning. A clipped sample
  says only that the stress was *at least* the limit, so :func:`~mudrft.calibration.calibrate`
  leaves those samples out of the fit (``clipped="exclude"``, default) and names the trial;
* **an unzeroed sensor** (:func:`stress_offset`, decision D154): in a vertical test the
  stress while the plate is out of the mud (depth <= 0, before it enters and after it
  leaves) is the sensor's zero; the model's stress there is 0. A zero clearly off is named
  (``zero="check"``, default) or subtracted (``zero="subtract"``).

Both work on the stress [Pa] of one :class:`~mudrft.io.Trial`; a force log is a stress
once divided by the plate's area, which changes neither fault.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from .._validation import MudrftError
from ..constitutive.contact import in_contact
from ..io import IntrusionDataset, Trial
from ._problem import PHASES, segment

__all__ = [
    "CLIPPED_SAMPLES",
    "OFFSET_FRACTION",
    "OFFSET_SAMPLES",
    "Offset",
    "check_clipped",
    "check_zero",
    "clipped_samples",
    "clipped_warning",
    "offset_warning",
    "stress_offset",
    "subtract_offsets",
]

#: Fewest samples in the mud at exactly a trial's largest (or smallest) stress that make it
#: a saturated sensor's flat top (decision D153) [-]. A noisy signal repeats its extreme
#: value by chance almost never; a few repeats can come from a coarse digitisation at the
#: peak, hence more than a couple.
CLIPPED_SAMPLES = 5
#: Samples within this fraction of the trial's stress range of its extreme count as at it
#: (the rounding of a unit conversion, not noise) [-].
_AT_EXTREME = 1e-9
#: A trial's stress out of the mud is a sensor offset when its median exceeds this fraction
#: of the trial's stress range in the mud (decision D154) [-] ...
OFFSET_FRACTION = 0.02
#: ... and it was measured on at least this many samples out of the mud [-].
OFFSET_SAMPLES = 5
#: ... and it is this many standard errors of the median away from 0 [-].
_OFFSET_SIGNIFICANCE = 4.0


def clipped_samples(trial: Trial) -> NDArray[np.bool_]:
    """Samples of a trial at a saturated sensor's limit (decision D153).

    A trial is clipped at its top when at least :data:`CLIPPED_SAMPLES` samples in the mud
    (phases other than "out", decision D42) sit exactly at its largest stress, and that
    stress is positive; at its bottom likewise with the smallest, negative stress (a
    suction beyond the sensor's range).

    Parameters
    ----------
    trial : Trial
        One trial (stress [Pa]).

    Returns
    -------
    ndarray of bool, shape (n,)
        True at the samples at a limit; all False for a trial that is not clipped.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0.0, 1.0, 101)
    >>> depth = 0.03 * np.minimum(t, 1.0 - t)
    >>> stress = np.minimum(1e5 * depth, 1200.0)  # the sensor stops at 1200 Pa
    >>> int(clipped_samples(Trial(t, depth, stress)).sum())
    21
    """
    s = np.asarray(trial.stress, dtype=float)
    inside = segment(trial) != PHASES["out"]
    out = np.zeros(s.size, dtype=bool)
    span = float(np.ptp(s[inside])) if inside.any() else 0.0
    if span == 0.0:
        return out  # a constant is no saturation: the fit refuses it as nothing to fit
    tol = _AT_EXTREME * span
    for extreme, sign in ((float(np.max(s[inside])), 1.0), (float(np.min(s[inside])), -1.0)):
        if sign * extreme <= 0:
            continue  # a limit at 0 is a sensor that reads one sign only, not a saturation
        at = inside & (np.abs(s - extreme) <= tol)
        if np.count_nonzero(at) >= CLIPPED_SAMPLES:
            out |= at
    return out


def clipped_warning(trial: Trial, clipped: NDArray[np.bool_], *, kept: bool) -> str:
    """The warning naming a clipped trial, its limits [Pa] and what the fit did with them."""
    s = trial.stress[clipped]
    limits = " and ".join(f"{v:.4g} Pa" for v in sorted({float(np.max(s)), float(np.min(s))}))
    done = (
        "they are fitted as they are (clipped='keep', CLI --clipped keep), which biases the "
        "constants; leave them out with clipped='exclude'"
        if kept
        else "they are left out of the fit (a clipped sample only says the stress was at "
        "least the limit); clipped='keep' (CLI --clipped keep) fits them"
    )
    return (
        f"trial {trial.name!r}: {int(np.count_nonzero(clipped))} of {len(trial)} samples sit "
        f"at the same stress, {limits}, the trial's extreme: a force sensor that saturated? "
        f"{done} (decision D153)"
    )


class Offset(NamedTuple):
    """The stress a trial logs while the plate is out of the mud (decision D154).

    Attributes
    ----------
    value : float
        Median stress over the samples out of the mud [Pa].
    samples : int
        Samples out of the mud (depth <= 0) [-].
    fraction : float
        ``|value|`` over the trial's stress range in the mud [-].
    significant : bool
        Whether it is a sensor offset: at least :data:`OFFSET_SAMPLES` samples, a
        ``fraction`` above :data:`OFFSET_FRACTION`, and the median four of its standard
        errors from 0.
    error : float
        Standard error of ``value`` [Pa].
    """

    value: float
    samples: int
    fraction: float
    significant: bool
    error: float = math.nan


def stress_offset(trial: Trial) -> Offset:
    r"""The stress a trial logs while the plate is out of the mud, and whether it is an offset.

    Out of the mud is depth <= 0 [m] (at or above the surface): the model's stress is 0
    there (decision D42), so a median clearly off 0 is the sensor's zero. Its standard error
    is :math:`1.25\,\hat s/\sqrt{m}` with :math:`\hat s` the scaled median absolute deviation
    of the ``m`` samples.

    Parameters
    ----------
    trial : Trial
        One trial (depth [m], stress [Pa]).

    Returns
    -------
    Offset
        ``value`` nan and ``samples`` 0 for a trial that never leaves the mud.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0.0, 2.0, 201)
    >>> depth = np.clip(0.03 * np.minimum(t - 0.5, 1.5 - t), 0.0, None)  # out, in, out
    >>> off = stress_offset(Trial(t, depth, 1e5 * depth + 40.0))  # unzeroed by 40 Pa
    >>> round(off.value, 6), off.samples, off.significant
    (40.0, 102, True)
    """
    d = np.asarray(trial.depth, dtype=float)
    s = np.asarray(trial.stress, dtype=float)
    out = ~in_contact(d)
    m = int(np.count_nonzero(out))
    if m == 0:
        return Offset(math.nan, 0, math.nan, False, math.nan)
    inside = ~out
    span = float(np.ptp(s[inside])) if inside.any() else 0.0
    value = float(np.median(s[out]))
    spread = 1.4826 * float(np.median(np.abs(s[out] - value)))
    fraction = abs(value) / span if span > 0 else math.inf
    error = 1.2533 * spread / math.sqrt(m)
    significant = (
        m >= OFFSET_SAMPLES
        and fraction > OFFSET_FRACTION
        and abs(value) > _OFFSET_SIGNIFICANCE * error
    )
    return Offset(value, m, fraction, bool(significant), error)


def offset_warning(trial: Trial, offset: Offset) -> str:
    """The warning naming a trial whose force sensor was not zeroed."""
    return (
        f"trial {trial.name!r}: the stress is {offset.value:.4g} Pa "
        f"({100 * offset.fraction:.1f} % of the trial's range) while the plate is out of the "
        f"mud ({offset.samples} samples at depth <= 0, where the model's stress is 0): a force "
        "sensor that was not zeroed? An offset biases every constant; zero the sensor, or "
        "pass zero='subtract' (CLI --zero subtract) to subtract each trial's stress out of "
        "the mud (decision D154)"
    )


def subtract_offsets(ds: IntrusionDataset) -> tuple[IntrusionDataset, list[Offset]]:
    """Each trial's stress less its median stress out of the mud (``zero="subtract"``, D154).

    Parameters
    ----------
    ds : IntrusionDataset
        The data (stress [Pa]).

    Returns
    -------
    IntrusionDataset, list of Offset
        The zeroed data, and each trial's offset subtracted.

    Raises
    ------
    MudrftError
        For a trial with fewer than :data:`OFFSET_SAMPLES` samples out of the mud: its zero
        cannot be measured.
    """
    trials: list[Trial] = []
    done: list[Offset] = []
    for tr in ds.trials:
        off = stress_offset(tr)
        if off.samples < OFFSET_SAMPLES:
            raise MudrftError(
                f"zero='subtract' needs at least {OFFSET_SAMPLES} samples out of the mud "
                f"(depth <= 0) in every trial to measure the sensor's zero; trial "
                f"{tr.name!r} has {off.samples}: log the plate above the surface before it "
                "enters or after it leaves, or zero the sensor and leave zero='check'"
            )
        trials.append(
            Trial(
                tr.time,
                tr.depth,
                tr.stress - off.value,
                name=tr.name,
                characteristic_length=tr.characteristic_length,
                meta={**tr.meta, "stress_offset": off.value},
            )
        )
        done.append(off)
    zeroed = IntrusionDataset(
        tuple(trials), direction=ds.direction, source=ds.source, notes=ds.notes, meta=dict(ds.meta)
    )
    return zeroed, done


def check_zero(
    ds: IntrusionDataset, *, zero: str, direction: str
) -> tuple[IntrusionDataset, list[Offset] | None, list[str], list[str]]:
    """The sensor's zero of a fit's data (decision D154), on every logged sample.

    Parameters
    ----------
    ds : IntrusionDataset
        The data (depth [m], stress [Pa]).
    zero : {"check", "subtract"}, keyword-only
        Warn about an unzeroed sensor, or subtract each trial's stress out of the mud.
    direction : {"vertical", "horizontal"}, keyword-only
        The test's direction. The zero is checked in vertical tests only: a horizontal
        plate back at zero travel is still in the mud, and its stress there is not 0.

    Returns
    -------
    IntrusionDataset, list of Offset or None, list of str, list of str
        The data (zeroed with ``zero="subtract"``); the offsets subtracted (None when
        none were; their errors widen the fit's robust intervals); the warnings; the notes.
    """
    if zero == "subtract" and direction != "vertical":
        raise MudrftError(
            "zero='subtract' needs a vertical test, whose plate leaves the mud (depth <= 0); "
            f"this one is {direction}: a horizontal plate at zero travel is still in the mud, "
            "and its stress there is not the sensor's zero. Zero the sensor before the test"
        )
    if zero == "subtract":
        ds, done = subtract_offsets(ds)
        note = "calibrate: sensor zero subtracted (decision D154): " + ", ".join(
            f"{tr.name} {off.value:.4g} Pa" for tr, off in zip(ds.trials, done, strict=True)
        )
        return ds, done, [], [note]
    warned = []
    if direction == "vertical":
        for tr in ds.trials:
            off = stress_offset(tr)
            if off.significant:
                warned.append(offset_warning(tr, off))
    return ds, None, warned, []


def check_clipped(
    ds: IntrusionDataset, *, clipped: str
) -> tuple[list[NDArray[np.bool_]] | None, list[str]]:
    """A saturated sensor in a fit's data (decision D153).

    Parameters
    ----------
    ds : IntrusionDataset
        The data (stress [Pa]).
    clipped : {"exclude", "keep"}, keyword-only
        Leave a saturated sensor's samples out of the fit, or fit them.

    Returns
    -------
    list of ndarray or None, list of str
        The samples to leave out of each trial (None when there are none); the warnings.
    """
    masks = [clipped_samples(tr) for tr in ds.trials]
    warned = [
        clipped_warning(tr, mask, kept=clipped == "keep")
        for tr, mask in zip(ds.trials, masks, strict=True)
        if mask.any()
    ]
    if clipped == "keep" or not any(m.any() for m in masks):
        return None, warned
    return masks, warned
