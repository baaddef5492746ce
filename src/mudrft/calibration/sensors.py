"""What a log's force sensor did wrong, found before a fit: a saturated sensor's flat top
(decision D153) and a sensor not zeroed (decision D154), on the stress [Pa] of a trial."""

from __future__ import annotations

import math
from dataclasses import replace
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from .._validation import MudrftError
from ..constitutive.contact import in_contact
from ..io import IntrusionDataset, Trial
from ._problem import PHASES, segment

#: Fewest samples in the mud at exactly a trial's extreme stress that make a saturated
#: sensor's flat top (D153) [-].
CLIPPED_SAMPLES = 5
#: Samples within this fraction of the stress range of the extreme are at it [-].
_AT_EXTREME = 1e-9
#: A trial's median stress out of the mud is a sensor offset (D154) when it exceeds this
#: fraction of the trial's stress range in the mud [-], on at least OFFSET_SAMPLES samples,
#: and lies this many standard errors from 0 [-].
OFFSET_FRACTION = 0.02
OFFSET_SAMPLES = 5
_OFFSET_SIGNIFICANCE = 4.0


def clipped_samples(trial: Trial) -> NDArray[np.bool_]:
    """The samples (bool, shape (n,)) of a ``trial`` at a saturated sensor's limit (decision
    D153): at least :data:`CLIPPED_SAMPLES` samples in the mud exactly at its largest,
    positive stress [Pa], or at its smallest, negative one; none for a trial not clipped.

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


class Offset(NamedTuple):
    """The median stress ``value`` [Pa] a trial logs on its ``samples`` out of the mud,
    ``|value|`` as a ``fraction`` of its range in the mud [-], whether it is a sensor
    offset (``significant``), and the standard ``error`` of ``value`` [Pa] (D154)."""

    value: float
    samples: int
    fraction: float
    significant: bool
    error: float = math.nan


def stress_offset(trial: Trial) -> Offset:
    r"""The :class:`Offset`: the stress [Pa] a ``trial`` logs while the plate is out of the
    mud (depth <= 0 [m]), and whether it is an offset; its standard error is
    :math:`1.25\,\hat s/\sqrt{m}`, :math:`\hat s` the scaled median absolute deviation of the
    ``m`` samples (``value`` nan and ``samples`` 0 for a trial that never leaves the mud).

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
    span = float(np.ptp(s[~out])) if m < s.size else 0.0
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


def check_zero(
    ds: IntrusionDataset, *, zero: str, direction: str
) -> tuple[IntrusionDataset, list[Offset] | None, list[str], list[str]]:
    """The sensor's zero of a fit's data (decision D154): warn about an unzeroed sensor
    (``zero="check"``) or subtract each trial's stress out of the mud (``"subtract"``), in a
    vertical test only (a horizontal plate at zero travel is still in the mud). Returns the
    data, the offsets subtracted (None when none were), the warnings and the notes."""
    offsets = [stress_offset(tr) for tr in ds.trials]
    if zero == "check":
        warned = [
            f"trial {tr.name!r}: the stress is {off.value:.4g} Pa "
            f"({100 * off.fraction:.1f} % of the trial's range) while the plate is out of the "
            f"mud ({off.samples} samples at depth <= 0, where the model's stress is 0): a force "
            "sensor that was not zeroed? An offset biases every constant; zero the sensor, or "
            "pass zero='subtract' (CLI --zero subtract) to subtract each trial's stress out "
            "of the mud (decision D154)"
            for tr, off in zip(ds.trials, offsets, strict=True)
            if direction == "vertical" and off.significant
        ]
        return ds, None, warned, []
    if direction != "vertical":
        raise MudrftError(
            "zero='subtract' needs a vertical test, whose plate leaves the mud (depth <= 0); "
            f"this one is {direction}: a horizontal plate at zero travel is still in the mud, "
            "and its stress there is not the sensor's zero. Zero the sensor before the test"
        )
    trials = []
    for tr, off in zip(ds.trials, offsets, strict=True):
        if off.samples < OFFSET_SAMPLES:
            raise MudrftError(
                f"zero='subtract' needs at least {OFFSET_SAMPLES} samples out of the mud "
                f"(depth <= 0) in every trial to measure the sensor's zero; trial "
                f"{tr.name!r} has {off.samples}: log the plate above the surface before it "
                "enters or after it leaves, or zero the sensor and leave zero='check'"
            )
        meta = {**tr.meta, "stress_offset": off.value}
        trials.append(replace(tr, stress=tr.stress - off.value, meta=meta))
    note = "calibrate: sensor zero subtracted (decision D154): " + ", ".join(
        f"{tr.name} {off.value:.4g} Pa" for tr, off in zip(ds.trials, offsets, strict=True)
    )
    return replace(ds, trials=tuple(trials)), offsets, [], [note]


def check_clipped(
    ds: IntrusionDataset, *, clipped: str
) -> tuple[list[NDArray[np.bool_]] | None, list[str]]:
    """A saturated sensor in a fit's data (decision D153): the samples to leave out of each
    trial (None with ``clipped="keep"`` or when there are none) and the warnings."""
    masks = [clipped_samples(tr) for tr in ds.trials]
    done = (
        "they are fitted as they are (clipped='keep', CLI --clipped keep), which biases "
        "the constants; leave them out with clipped='exclude'"
        if clipped == "keep"
        else "they are left out of the fit (a clipped sample only says the stress was at "
        "least the limit); clipped='keep' (CLI --clipped keep) fits them"
    )
    warned = []
    for tr, mask in zip(ds.trials, masks, strict=True):
        if mask.any():
            s = tr.stress[mask]
            limits = " and ".join(f"{v:.4g} Pa" for v in sorted({float(s.max()), float(s.min())}))
            warned.append(
                f"trial {tr.name!r}: {int(np.count_nonzero(mask))} of {len(tr)} samples sit "
                f"at the same stress, {limits}, the trial's extreme: a force sensor that "
                f"saturated? {done} (decision D153)"
            )
    if clipped == "keep" or not warned:
        return None, warned
    return masks, warned
