"""From a log's resolved columns to trials, for the CSV and HDF5 loaders (internal)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._progress import logger
from .._validation import MudrftError, check_choice, plain, positive_number, warn_implausible
from ..parameters import DIRECTIONS
from ..units import SCALE
from .columns import LOG_COLUMNS, SI_UNIT, Column, fail, split_label
from .dataset import DEFAULT_PLATE_LENGTH, IntrusionDataset, Trial

#: Plausible deepest intrusion [m], peak stress [Pa], plate area [m^2] and speed [m/s] (a
#: slow speed warns only in a log sampled at most every SLOW_SAMPLING [s]).
PLAUSIBLE_DEPTH = (1e-3, 1.0)
PLAUSIBLE_PEAK_STRESS = (100.0, 1e7)
PLAUSIBLE_AREA = (1e-6, 1.0)
PLAUSIBLE_SPEED = (1e-3, 20.0)
SLOW_SAMPLING = 0.01

#: Where sample ``i`` (None: the whole column) of a role's column (None: of the trial)
#: stands in the file: ``"line 12, column 'time [s]'"``.
Locate = Callable[[int | None, str | None], str]
Columns = dict[str, NDArray[np.float64]]


def file_bytes(p: Path, kind: str, *, max_bytes: int | None = None) -> bytes:
    """The bytes of ``p`` (none with ``max_bytes=0``: only checked readable); an error naming
    ``p`` for a directory, a missing or unreadable file, or one over ``max_bytes``; ``kind``
    names what was expected ("a CSV file")."""
    where = str(p)
    try:
        if p.is_dir():
            raise fail(where, "", f"is a directory, expected {kind}")
        if max_bytes and p.stat().st_size > max_bytes:
            raise fail(where, "", f"is larger than {max_bytes} bytes, too large for CSV (use HDF5)")
        with open(p, "rb") as fh:  # read only: a loader never writes its input
            return fh.read(max_bytes) if max_bytes != 0 else b""
    except FileNotFoundError:
        raise fail(where, "", "no such file") from None
    except PermissionError:
        raise fail(where, "", "permission denied (cannot read the file)") from None
    except OSError as exc:
        raise fail(where, "", f"cannot be read ({exc.strerror or exc})") from None


def check_roles(
    path: str, where: str, columns: dict[str, Column], names: Sequence[str], *, direction: str
) -> None:
    """Refuse columns that make no intrusion log (a time, a depth, a stress or a force; no
    ``Fz`` in a horizontal test)."""
    named = {r: [repr({"fz": "Fz", "f": "F"}.get(k, k)) for k, v in LOG_COLUMNS.items() if v == r]
             for r in ("time", "depth", "stress", "force")}  # fmt: skip
    words = {r: f"{', '.join(n[:-1])} or {n[-1]}" for r, n in named.items()}
    how = "name it with columns={'ROLE': 'NAME'} (CLI: --columns ROLE=NAME)"
    units = [split_label(label)[1] for label in names]
    for need, quantity in (("time", "time"), ("depth", "length")):
        if need not in columns:
            like = next((u for u in units if u in SCALE[quantity]), SI_UNIT[quantity])
            raise fail(
                path,
                where,
                f"no {need} column; name it {words[need]}, with its unit (e.g. "
                f"'{need} [{like}]'), or {how.replace('ROLE', need)}; "
                f"got {list(names)!r}",
            )
    if "stress" not in columns and "force" not in columns:
        raise fail(
            path,
            where,
            f"needs a stress or a force column; name it {words['stress']} (e.g. 'stress "
            f"[Pa]'), or {words['force']} (e.g. 'force [N]'), or {how.replace('ROLE', 'force')}"
            f"; got {list(names)!r}",
        )
    force = columns.get("force")
    fz = "stress" not in columns and force and force.label.lower().startswith("fz")
    if fz and direction == "horizontal":
        raise fail(
            path,
            where,
            "'Fz' is the vertical force but the test is horizontal; name the column "
            "'force [N]' (the force resisting the intrusion)",
        )


def resolve_direction(path: str, given: str | None, from_file: str | None, where: str) -> str:
    """The loading direction: the caller's, else the file's (checked even when given, at
    ``where``), else vertical."""
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


def assemble(
    path: str,
    parts: Sequence[tuple[Columns, Sequence[str] | None, Locate]],
    labels: dict[str, str],
    *,
    direction: str,
    notes: Sequence[str],
    meta: dict[str, Any],
    meta_len: float | None,
    meta_area: float | None,
    characteristic_length: float | None,
    area: float | None,
) -> IntrusionDataset:
    """The dataset of a log from its ``parts`` (the arguments of :func:`build_trials` but
    the plate) and column ``labels`` by role, its units checked (:func:`check_plausible`).
    The plate length [m] is the argument's, else the file's (``meta_len``), else 50 mm
    (D1); the area [m^2] the argument's, else the file's (needed for a force)."""
    try:
        if characteristic_length is not None:
            L = positive_number("characteristic_length", characteristic_length, unit="m")
            source = "argument"
        elif meta_len is not None:
            L, source = meta_len, "file header"
        else:
            L, source = DEFAULT_PLATE_LENGTH, "default (decision D1: 50 mm)"
        A = positive_number("area", area, unit="m^2") if area is not None else meta_area
    except MudrftError as exc:
        raise MudrftError(f"{path}: {exc}") from None
    meta = {**meta, "characteristic_length_source": source}
    if A is not None:
        warn_implausible(
            f"{path}: the plate area is",
            A,
            PLAUSIBLE_AREA,
            unit="m^2",
            hint="it is in m^2 (20 cm^2 is 0.002; CLI: --area 20cm^2); a file's value without "
            "a unit is read as m^2",
        )
        meta["area"] = A
    elif any("stress" not in columns for columns, _, _ in parts):
        raise MudrftError(
            f"{path}: the file logs a force but no plate area is known; pass area=... [m^2] "
            "(CLI: --area, e.g. 1600mm^2) or add a header line '# area [m^2]: ...'"
        )
    trials = [tr for part in parts for tr in build_trials(path, *part, L=L, A=A)]
    check_plausible(path, trials, labels, area=A)
    return IntrusionDataset(tuple(trials), direction, path, tuple(notes), meta)


def build_trials(
    path: str,
    columns: Columns,
    labels: Sequence[str] | None,
    locate: Locate,
    *,
    L: float,
    A: float | None,
) -> tuple[Trial, ...]:
    """One :class:`Trial` per label of the samples (in order; one for all without labels)
    from the ``columns`` ``time`` [s], ``depth`` [m] and ``stress`` [Pa] or ``force`` [N],
    with plate length ``L`` [m] and area ``A`` [m^2]; ``locate`` names places in ``path``."""
    time, depth = columns["time"], columns["depth"]
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
    groups: dict[str, list[int]] = {}
    for i, label in enumerate(labels if labels is not None else ["trial"] * time.size):
        groups.setdefault(label, []).append(i)
    trials = []
    for name, members in groups.items():
        idx = np.asarray(members)
        t = time[idx]
        if idx.size < 2:
            raise fail(
                path,
                locate(int(idx[0]), None),
                f"trial {name!r} has {idx.size} sample; a trial needs at least 2",
            )
        steps = np.diff(t)
        if not np.all(steps > 0):
            k = int(np.argmax(steps <= 0)) + 1
            hint = "; to log several trials in one file add a 'trial' column"
            hint = "" if labels is not None else hint
            raise fail(
                path,
                locate(int(idx[k]), "time"),
                f"time must increase strictly within trial {name!r}, but {plain(t[k])} s "
                f"follows {plain(t[k - 1])} s{hint}",
            )
        if float(np.ptp(stress[idx])) == 0.0:
            raise fail(
                path,
                locate(int(idx[0]), "stress" if "stress" in columns else "force"),
                f"trial {name!r}: stress is {plain(float(stress[idx[0]]))} Pa in every sample; "
                "a test records the stress changing as the plate moves (a sensor that did not "
                "record, or not the stress column?)",
            )
        meta: dict[str, Any] = {"first_sample": locate(int(idx[0]), None)}
        if A is not None:
            meta["area"] = A
        try:
            trials.append(
                Trial(t, depth[idx], stress[idx], name=name, characteristic_length=L, meta=meta)
            )
        except MudrftError as exc:
            raise fail(path, locate(int(idx[0]), None), str(exc)) from None
    return tuple(trials)


def _unit_hint(label: str, units: str) -> str:
    first = units.split(" or ")[0]
    return (
        f"if the values are in {units}, state it in the header: "
        f"'{split_label(label)[0] or 'column'} [{first}]' (HDF5: a 'unit' attribute '{first}')"
    )


def check_plausible(
    path: str, trials: Sequence[Trial], labels: dict[str, str], *, area: float | None
) -> None:
    """Warn where the units of the trials look wrong (the ``PLAUSIBLE_*`` ranges);
    ``labels`` are the column names by role, ``area`` the plate area [m^2] of a force."""
    _check_speed(path, trials, labels.get("time", "time"))
    depth = max(float(np.max(np.abs(t.depth))) for t in trials)
    if depth > 0:
        label = labels.get("depth", "depth")
        warn_implausible(
            f"{path}: column {label!r} reaches a depth of",
            depth,
            PLAUSIBLE_DEPTH,
            unit="m",
            hint=_unit_hint(label, "mm" if depth > PLAUSIBLE_DEPTH[1] else "m"),
        )
    peak = max(float(np.max(np.abs(t.stress))) for t in trials)
    if "stress" in labels:
        label = labels["stress"]
        units = "kPa or MPa" if peak < PLAUSIBLE_PEAK_STRESS[0] else "Pa"
        what, hint = f"{path}: column {label!r} peaks at", _unit_hint(label, units)
    else:
        label = labels.get("force", "force")
        what = f"{path}: column {label!r} over the plate area {plain(area)} m^2 peaks at"
        hint = (
            "check the force unit in the header ('Fz [N]', 'Fz [kN]'; HDF5: the 'unit' "
            "attribute) and the plate area (area=..., CLI: --area, e.g. 1600mm^2)"
        )
    warn_implausible(what, peak, PLAUSIBLE_PEAK_STRESS, unit="Pa", hint=hint)


def _check_speed(path: str, trials: Sequence[Trial], label: str) -> None:
    fast, trial = max(((t.speed, t) for t in trials), key=lambda vt: vt[0])
    if not fast > 0:
        return
    stated = split_label(label)[1] or "s"
    step = float(np.median(np.diff(trial.time)))
    if fast > PLAUSIBLE_SPEED[1]:
        larger = {"us": "ms or s", "ms": "s"}.get(stated, "")
        hint = (_unit_hint(label, larger) + "; or " if larger else "") + "check the depth unit"
    elif step >= SLOW_SAMPLING:
        smaller = {"ms": "us", "us": ""}.get(stated, "ms")
        hint = f"samples {plain(step)} s apart (read as {stated})" + (
            "; " + _unit_hint(label, smaller) if smaller else ""
        )
        hint += "; if the test really is this slow, ignore this warning"
    else:
        return
    what = f"{path}: the intrusion (10 % to 90 % of the deepest depth) runs at"
    warn_implausible(what, fast, PLAUSIBLE_SPEED, unit="m/s", hint=hint)
