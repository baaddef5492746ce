"""From columns in SI to trials: the plate, the direction, one trial per label (internal).

Shared by the CSV and HDF5 loaders once :mod:`.columns` has resolved and converted the
columns: :func:`resolve_direction` and :func:`resolve_plate` combine the caller's
arguments with the file's metadata; :func:`build_trials` splits the samples into
:class:`~mudrft.io.Trial` objects and turns a force into a stress.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._progress import logger
from .._validation import (
    MudrftError,
    check_choice,
    plain,
    positive_number,
    warn_implausible,
)
from ..plate import DEFAULT_PLATE_LENGTH
from .columns import fail, parse_header_name
from .dataset import Trial

__all__ = [
    "DIRECTIONS",
    "PLAUSIBLE_AREA",
    "PLAUSIBLE_DEPTH",
    "PLAUSIBLE_PEAK_STRESS",
    "PLAUSIBLE_SPEED",
    "build_trials",
    "check_plausible",
    "resolve_direction",
    "resolve_plate",
]

#: One trial for :func:`check_plausible`: column labels by role, depth [m], stress [Pa],
#: time [s].
LogColumns = tuple[dict[str, str], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]

#: Loading directions of a test.
DIRECTIONS = ("vertical", "horizontal")
#: Deepest intrusion of a plausible plate or foot test [m] (decision D105).
PLAUSIBLE_DEPTH = (1e-3, 1.0)
#: Peak stress magnitude of a plausible test in mud [Pa] (decision D105).
PLAUSIBLE_PEAK_STRESS = (10.0, 1e7)
#: Area of a plausible plate or foot [m^2]: 1 mm^2 to 1 m^2 (decision D105).
PLAUSIBLE_AREA = (1e-6, 1.0)
#: Intrusion speed of a plausible test [m/s] (decision D105): 1 mm/s to 20 m/s. Above it a
#: log warns; below it, a log sampled at most every :data:`SLOW_SAMPLING` [s] (100 Hz) warns:
#: the paper's 0.13 m/s logged at 1-100 kHz in ms and read as s is 0.13 mm/s at 1-100 Hz.
PLAUSIBLE_SPEED = (1e-3, 20.0)
SLOW_SAMPLING = 0.01


def resolve_direction(path: str, given: str | None, from_file: str | None, where: str) -> str:
    """The loading direction: the caller's, else the file's (checked even when given),
    else vertical.

    Parameters
    ----------
    path : str
        The file, for errors.
    given : str or None
        The ``direction`` argument.
    from_file : str or None
        The file's metadata value.
    where : str
        Where the file states it (``"line 2"``, ``"attribute 'direction'"``).
    """
    file_direction = None
    if from_file is not None:
        file_direction = from_file.strip().lower()
        if file_direction not in DIRECTIONS:
            raise fail(
                path,
                where,
                f"metadata 'direction' must be 'vertical' or 'horizontal', got {from_file!r}",
            )
    if given:
        direction = check_choice("direction", given, DIRECTIONS)
        if file_direction is not None and file_direction != direction:
            logger.warning(
                "%s: direction %r given overrides the file's %r (%s)",
                path, direction, file_direction, where,
            )  # fmt: skip
        return direction
    return file_direction or "vertical"


def resolve_plate(
    path: str,
    *,
    meta_len: float | None,
    meta_area: float | None,
    characteristic_length: float | None,
    area: float | None,
    need_area: bool,
) -> tuple[float, float | None, str]:
    """Plate length [m] and area [m^2] (None if unknown and not needed), and where the
    length came from: the caller's argument, else the file's metadata, else the default
    (decision D1)."""
    try:
        if characteristic_length is not None:
            L = positive_number("characteristic_length", characteristic_length, unit="m")
            src = "argument"
        elif meta_len is not None:
            L, src = meta_len, "file header"
        else:
            L, src = DEFAULT_PLATE_LENGTH, "default (decision D1: 50 mm)"
        A = positive_number("area", area, unit="m^2") if area is not None else meta_area
    except MudrftError as exc:
        raise MudrftError(f"{path}: {exc}") from None
    if A is not None:
        warn_implausible(
            f"{path}: the plate area is",
            A,
            PLAUSIBLE_AREA,
            unit="m^2",
            hint="it is in m^2 (20 cm^2 is 0.002); a file's value without a unit is read as m^2",
        )
    if need_area and A is None:
        raise MudrftError(
            f"{path}: the file logs a force but no plate area is known; pass area=... [m^2] "
            "(CLI: --area) or add a header line '# area [m^2]: ...'"
        )
    return L, A, src


def _groups(labels: Sequence[str] | None, n: int) -> dict[str, NDArray[np.intp]]:
    """Sample indices of each trial label, in order of first appearance."""
    if labels is None:
        return {"trial": np.arange(n)}
    members: dict[str, list[int]] = {}
    for i, lab in enumerate(labels):
        members.setdefault(lab, []).append(i)
    return {k: np.asarray(v) for k, v in members.items()}


#: Where sample ``i`` (or, given None, the whole column) of a column (or, given None, of
#: the trial) stands in the file, for errors: ``"line 12, column 'time'"`` in a CSV log,
#: ``"dataset 'run1/time [s]', row 11"`` in an HDF5 one.
Locate = Callable[[int | None, str | None], str]


def build_trials(
    path: str,
    columns: dict[str, NDArray[np.float64]],
    labels: Sequence[str] | None,
    locate: Locate,
    *,
    L: float,
    A: float | None,
) -> tuple[Trial, ...]:
    """One :class:`Trial` per label (or one for all samples when there are no labels).

    Parameters
    ----------
    path : str
        The file, for errors.
    columns : dict
        ``time`` [s], ``depth`` [m] and ``stress`` [Pa] or ``force`` [N], in SI.
    labels : sequence of str or None
        Trial label of each sample.
    locate : callable
        ``locate(sample, role)``: the place of a sample (or None) of a column (a role such
        as ``"time"``, or None) in the file, for errors (:data:`Locate`).
    L : float, keyword-only
        Plate characteristic length [m].
    A : float or None, keyword-only
        Plate area [m^2], needed if there is no stress column.
    """
    time = columns["time"]
    depth = columns["depth"]
    if not time.size:
        raise fail(path, locate(None, "time"), "holds no samples; a trial needs at least 2")
    if float(np.max(depth)) <= 0.0 < -float(np.min(depth)):
        raise fail(
            path,
            locate(None, "depth"),
            f"the depth is never positive (it reaches {plain(float(np.min(depth)))} m); mudrft "
            "measures it into the mud, positive while the plate intrudes: if your log records "
            "it negative, flip its sign",
        )
    stress = columns["stress"] if "stress" in columns else columns["force"] / float(A)  # type: ignore[arg-type]
    trials = []
    for name, idx in _groups(labels, time.size).items():
        t = time[idx]
        if idx.size < 2:
            raise fail(
                path,
                locate(int(idx[0]), None),
                f"trial {name!r} has {idx.size} sample; a trial needs at least 2",
            )
        d = np.diff(t)
        if not np.all(d > 0):
            k = int(np.argmax(d <= 0)) + 1
            hint = (
                ""
                if labels is not None
                else "; to log several trials in one file add a 'trial' column"
            )
            raise fail(
                path,
                locate(int(idx[k]), "time"),
                f"time must increase strictly within trial {name!r}, but {plain(t[k])} s "
                f"follows {plain(t[k - 1])} s{hint}",
            )
        meta: dict[str, Any] = {"first_sample": locate(int(idx[0]), None)}
        if A is not None:
            meta["area"] = A
        try:
            trials.append(
                Trial(
                    t, depth[idx], stress[idx], name=str(name), characteristic_length=L, meta=meta
                )
            )
        except MudrftError as exc:
            raise fail(path, locate(int(idx[0]), None), str(exc)) from None
    return tuple(trials)


def _unit_hint(label: str, units: str) -> str:
    name = parse_header_name(label)[0] if label else "column"
    first = units.split(" or ")[0]
    return (
        f"if the values are in {units}, state it in the header: '{name} [{first}]' "
        f"(HDF5: a 'unit' attribute '{first}')"
    )


def check_plausible(
    path: str,
    columns: Sequence[LogColumns],
    *,
    area: float | None,
) -> None:
    """Warn (:class:`~mudrft._validation.PlausibilityWarning`) if a log's depths, stresses or
    times look like a unit mistake: a deepest depth outside :data:`PLAUSIBLE_DEPTH`, a peak
    stress outside :data:`PLAUSIBLE_PEAK_STRESS`, an intrusion speed above
    :data:`PLAUSIBLE_SPEED` or below it in a log sampled slower than :data:`SLOW_SAMPLING`
    (decision D105).

    Parameters
    ----------
    path : str
        The file, for the message.
    columns : sequence of (labels, depth, stress, time)
        Per trial: the column labels by role (``"time"``, ``"depth"``, ``"stress"`` or
        ``"force"``), the depths [m], the stresses [Pa] (force / area for a force) and the
        times [s].
    area : float or None, keyword-only
        Plate area [m^2] when the stresses come from a force column.
    """
    if not columns:
        return
    _check_speed(path, columns)
    deep = max(columns, key=lambda c: float(np.max(np.abs(c[1]), initial=0.0)))
    depth = float(np.max(np.abs(deep[1]), initial=0.0))
    if depth > 0:
        label = deep[0].get("depth", "depth")
        units = "mm" if depth > PLAUSIBLE_DEPTH[1] else "m"
        warn_implausible(
            f"{path}: column {label!r} reaches a depth of",
            depth,
            PLAUSIBLE_DEPTH,
            unit="m",
            hint=_unit_hint(label, units),
        )
    peak_of = max(columns, key=lambda c: float(np.max(np.abs(c[2]), initial=0.0)))
    peak = float(np.max(np.abs(peak_of[2]), initial=0.0))
    if peak == 0:
        return
    if "stress" in peak_of[0]:
        label = peak_of[0]["stress"]
        units = "kPa or MPa" if peak < PLAUSIBLE_PEAK_STRESS[0] else "Pa"
        what, hint = f"{path}: column {label!r} peaks at", _unit_hint(label, units)
    else:
        label = peak_of[0].get("force", "force")
        what = f"{path}: column {label!r} over the plate area {plain(area)} m^2 peaks at"
        hint = (
            "check the force unit in the header ('Fz [N]', 'Fz [kN]'; HDF5: the 'unit' "
            "attribute) and the plate area (area=..., CLI: --area, in m^2)"
        )
    warn_implausible(what, peak, PLAUSIBLE_PEAK_STRESS, unit="Pa", hint=hint)


def intrusion_speed(time: NDArray[np.float64], depth: NDArray[np.float64]) -> float:
    """Mean speed of a trial's first intrusion from 10 % to 90 % of its deepest depth [m/s].

    Holds before and after, and noise, hardly change it (unlike the largest
    sample-to-sample rate). NaN for a trial that never goes deeper than its start.
    """
    deepest = float(np.max(depth, initial=0.0))
    if not deepest > 0:
        return math.nan
    i90 = int(np.argmax(depth >= 0.9 * deepest))
    below = np.flatnonzero(depth[: i90 + 1] <= 0.1 * deepest)
    i10 = int(below[-1]) if below.size else 0
    if i10 >= i90:
        return math.nan
    return float((depth[i90] - depth[i10]) / (time[i90] - time[i10]))


def _check_speed(path: str, columns: Sequence[LogColumns]) -> None:
    speeds = [(intrusion_speed(c[3], c[1]), c) for c in columns]
    speeds = [(v, c) for v, c in speeds if math.isfinite(v)]
    if not speeds:
        return
    fast, (names, _, _, time) = max(speeds, key=lambda vc: vc[0])
    label = names.get("time", "time")
    try:
        stated = parse_header_name(label)[1] or "s"
    except ValueError:
        stated = "s"
    what = f"{path}: the intrusion (10 % to 90 % of the deepest depth) runs at"
    if fast > PLAUSIBLE_SPEED[1]:
        larger = {"us": "ms or s", "ms": "s"}.get(stated, "")
        hint = (_unit_hint(label, larger) + "; or " if larger else "") + "check the depth unit"
        warn_implausible(what, fast, PLAUSIBLE_SPEED, unit="m/s", hint=hint)
        return
    step = float(np.median(np.diff(time)))
    if step >= SLOW_SAMPLING:
        smaller = {"ms": "us", "us": ""}.get(stated, "ms")
        hint = f"samples {plain(step)} s apart (read as {stated})" + (
            "; " + _unit_hint(label, smaller) if smaller else ""
        )
        hint += "; if the test really is this slow, ignore this warning"
        warn_implausible(what, fast, PLAUSIBLE_SPEED, unit="m/s", hint=hint)
