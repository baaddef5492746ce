"""Intrusion data in memory, in SI: :class:`Trial` (one test) and :class:`IntrusionDataset`."""

from __future__ import annotations

import csv
import io
import os
import re
from collections.abc import Iterator
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import (
    PLAUSIBLE_FOOT_SIZE,
    MudrftError,
    check_choice,
    check_increasing,
    check_shape,
    positive_number,
    warn_implausible,
    warn_plausibility,
)
from ..plate import DEFAULT_PLATE_LENGTH
from .atomic import atomic_write

#: How the writers of this package name the permission to replace a file, in errors.
OVERWRITE_OPTION = "overwrite=True (CLI: --force)"


@dataclass(frozen=True, eq=False)
class Trial:
    """One intrusion test: displacement and stress sampled in time (SI), as
    :func:`mudrft.calibrate` takes data already in memory (gathered in an
    :class:`IntrusionDataset`).

    Parameters
    ----------
    time : array_like, shape (n,)
        Strictly increasing sample times [s].
    depth : array_like, shape (n,)
        Intrusion displacement of the plate [m] (vertical: depth below the surface;
        horizontal: travel through the mud), positive into the mud.
    stress : array_like, shape (n,)
        Stress resisting the intrusion [Pa] (negative under suction).
    name : str
        Label of the trial.
    characteristic_length : float
        Plate characteristic length :math:`L_c` [m] (decision D1: 50 mm by default).
    meta : dict
        Anything else known about the trial (area [m^2], source line numbers, ...).

    Examples
    --------
    >>> tr = Trial([0.0, 0.5, 1.0], [0.0, 0.01, 0.02], [0.0, 900.0, 1500.0])
    >>> tr.gamma.round(6).tolist(), round(tr.speed, 6)
    ([0.0, 0.2, 0.4], 0.02)
    """

    # Any: given as array_like, held as float arrays once checked
    time: Any
    depth: Any
    stress: Any
    name: str = "trial"
    characteristic_length: float = DEFAULT_PLATE_LENGTH
    meta: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        t = check_increasing("time", self.time)
        if t.size < 2:
            raise MudrftError(
                f"trial {self.name!r}: time must have at least 2 samples, got {t.size}"
            )
        for attr in ("depth", "stress"):
            a = check_shape(f"trial {self.name!r}: {attr}", getattr(self, attr), t.shape)
            object.__setattr__(self, attr, a)
        object.__setattr__(self, "time", t)
        d = self.depth
        if float(np.max(d)) <= 0.0 < -float(np.min(d)):
            raise MudrftError(
                f"trial {self.name!r}: depth is never positive (it reaches "
                f"{float(np.min(d)):.3g} m); mudrft measures it into the mud, positive while "
                "the plate intrudes: flip its sign"
            )
        if float(np.max(d)) < 0.01 * -float(np.min(d)):  # a few positive samples of noise
            warn_plausibility(
                f"trial {self.name!r}: depth reaches {float(np.min(d)):.3g} m but only "
                f"{float(np.max(d)):.3g} m into the mud; mudrft measures depth into the mud, "
                "positive while the plate intrudes: is its sign flipped?"
            )
        intruding = (np.diff(d) > 0) & (d[1:] > 0)
        if intruding.any() and float(np.median(self.stress[1:][intruding])) < 0:
            warn_plausibility(
                f"trial {self.name!r}: the stress is mostly negative while the plate intrudes; "
                "mudrft's stress resists the intrusion, positive while intruding (negative "
                "only under suction): is its sign flipped?"
            )
        L = positive_number("characteristic_length", self.characteristic_length, unit="m")
        warn_implausible(
            "characteristic_length (the plate's size) is",
            L,
            PLAUSIBLE_FOOT_SIZE,
            unit="m",
            hint="it is in metres (50 mm is 0.05); a file's value without a unit is read as metres",
        )
        object.__setattr__(self, "characteristic_length", L)

    @property
    def gamma(self) -> NDArray[np.float64]:
        """Dimensionless displacement :math:`\\gamma = q/L_c` [-]."""
        return self.depth / self.characteristic_length

    @property
    def speed(self) -> float:
        """Intrusion speed through the mud [m/s] (:func:`intrusion_speed`); 0 if none."""
        return intrusion_speed(self.time, self.depth)

    @property
    def duration(self) -> float:
        """Duration [s]."""
        return float(self.time[-1] - self.time[0])

    def __len__(self) -> int:
        return int(self.time.size)

    def __repr__(self) -> str:
        return (
            f"Trial(name={self.name!r}, samples={len(self)}, duration={self.duration:.3g} s, "
            f"speed={self.speed:.3g} m/s, depth_max={float(np.max(np.abs(self.depth))):.3g} m)"
        )


@dataclass(frozen=True, eq=False)
class IntrusionDataset:
    """Several trials of one mud in one loading direction, fitted jointly.

    Parameters
    ----------
    trials : sequence of Trial
        The trials (several speeds, repetitions).
    direction : {"vertical", "horizontal"}
        Loading direction of the tests.
    source : str
        Where the data come from (file path).
    notes : tuple of str
        Free-text notes (the comment lines of a CSV file), e.g. that the data are synthetic.
    meta : dict
        Metadata read from the file header.

    Examples
    --------
    >>> tr = Trial([0.0, 0.5, 1.0], [0.0, 0.01, 0.02], [0.0, 900.0, 1500.0])
    >>> ds = IntrusionDataset([tr])
    >>> len(ds), ds.direction
    (1, 'vertical')
    """

    # Any: given as a Trial or an iterable of them, held as tuple[Trial, ...]
    trials: Any
    direction: str = "vertical"
    source: str = ""
    notes: tuple[str, ...] = ()
    meta: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        trials = (self.trials,) if isinstance(self.trials, Trial) else tuple(self.trials)
        if not trials:
            raise MudrftError("trials must hold at least one Trial, got none")
        for i, tr in enumerate(trials):
            if not isinstance(tr, Trial):
                raise MudrftError(f"trials[{i}] must be a Trial, got {type(tr).__name__}")
        object.__setattr__(self, "trials", trials)
        check_choice("direction", self.direction, ("vertical", "horizontal"))
        object.__setattr__(self, "notes", tuple(str(n) for n in self.notes))

    @classmethod
    def from_arrays(
        cls,
        time: ArrayLike,
        depth: ArrayLike,
        stress: ArrayLike,
        *,
        characteristic_length: float = DEFAULT_PLATE_LENGTH,
        direction: str = "vertical",
        name: str = "trial",
    ) -> IntrusionDataset:
        """A one-trial dataset from arrays in SI units (time [s], depth [m], stress [Pa])."""
        tr = Trial(time, depth, stress, name=name, characteristic_length=characteristic_length)
        return cls((tr,), direction=direction)

    @property
    def synthetic(self) -> bool:
        """True if ``meta`` or a note says ``synthetic: ...`` with a value that is not a no
        (``no``, ``false``, ``0``, ``none``, empty, ``not ...``)."""
        said = [self.meta["synthetic"]] if "synthetic" in self.meta else []
        lines = [line.strip() for note in self.notes for line in note.splitlines()]
        said += [x.partition(":")[2] for x in lines if x.lower().startswith("synthetic:")]
        said = [str(v).strip().lower() for v in said]
        no = ("", "no", "false", "0", "none")
        return any(v not in no and not v.startswith("not ") for v in said)

    @property
    def speeds(self) -> list[float]:
        """Intrusion speed of each trial [m/s]."""
        return [tr.speed for tr in self.trials]

    def merge(self, *others: IntrusionDataset) -> IntrusionDataset:
        """Join the trials of several datasets of the same direction into one."""
        trials = list(self.trials)
        for o in others:
            if not isinstance(o, IntrusionDataset):
                raise MudrftError(f"merge expects IntrusionDataset objects, got {type(o).__name__}")
            if o.direction != self.direction:
                named = [f" ({x.source})" if x.source else "" for x in (o, self)]
                raise MudrftError(
                    f"cannot merge a {o.direction} dataset{named[0]} into a "
                    f"{self.direction} one{named[1]}"
                )
            trials.extend(o.trials)
        seen: dict[str, int] = {}
        for i, tr in enumerate(trials):  # two files' trials of one name stay apart
            seen[tr.name] = seen.get(tr.name, 0) + 1
            if seen[tr.name] > 1:
                trials[i] = replace(tr, name=f"{tr.name} ({seen[tr.name]})")
        notes = tuple(dict.fromkeys(self.notes + tuple(n for o in others for n in o.notes)))
        src = "; ".join(s for s in [self.source, *(o.source for o in others)] if s)
        return IntrusionDataset(
            tuple(trials), direction=self.direction, source=src, notes=notes, meta=dict(self.meta)
        )

    def _one_length(self, fmt: str) -> float:
        """The trials' characteristic length [m], which a ``fmt`` file holds once."""
        lengths = {tr.characteristic_length for tr in self.trials}
        if len(lengths) != 1:
            raise MudrftError(
                f"a {fmt} file holds one characteristic length for all trials; got "
                f"{sorted(lengths)}; save the trials in separate files"
            )
        return lengths.pop()

    def to_csv(self, path: str | os.PathLike[str], *, overwrite: bool = False) -> Path:
        """Write the dataset as CSV in SI units, its notes and metadata as ``#`` comments,
        atomically; it loads back with :func:`~mudrft.io.load_intrusion_csv`.

        Parameters
        ----------
        path : str or path-like
            Output file.
        overwrite : bool, keyword-only
            Replace an existing file (default: refuse).

        Returns
        -------
        Path
            The file written.
        """
        names = [tr.name for tr in self.trials]
        twice = sorted({n for n in names if names.count(n) > 1})
        if twice:  # their rows would read back as one trial
            raise MudrftError(
                f"a CSV file tells trials apart by name; several trials are named {twice}: "
                "rename them (IntrusionDataset.merge does)"
            )
        length = self._one_length("CSV")
        buf = io.StringIO()
        for note in self.notes:
            for line in note.splitlines() or [""]:  # one comment a line
                # the plate and direction are written once below, not as a file's own lines
                if not re.match(r"\s*(direction|characteristic_length|area)\b", line, re.I):
                    buf.write(f"# {line}\n")
        buf.write(f"# direction: {self.direction}\n")
        buf.write(f"# characteristic_length [m]: {length!r}\n")
        buf.write("trial,time [s],depth [m],stress [Pa]\n")
        # labels quoted ("#1" would read as a comment), numbers as their shortest repr
        rows = csv.writer(buf, quoting=csv.QUOTE_NONNUMERIC, lineterminator="\n")
        for tr in self.trials:
            label = " ".join(tr.name.split())  # the reader splits lines first: no line breaks
            columns = (tr.time.tolist(), tr.depth.tolist(), tr.stress.tolist())
            rows.writerows((label, *row) for row in zip(*columns, strict=True))
        return atomic_write(path, buf.getvalue(), overwrite=overwrite, option=OVERWRITE_OPTION)

    def __len__(self) -> int:
        return len(self.trials)

    def __iter__(self) -> Iterator[Trial]:
        return iter(self.trials)

    def __getitem__(self, i: int) -> Trial:
        return self.trials[i]

    def __repr__(self) -> str:
        tag = ", synthetic" if self.synthetic else ""
        return (
            f"IntrusionDataset({len(self)} trials, direction={self.direction!r}, "
            f"samples={sum(len(t) for t in self.trials)}{tag})"
        )


def intrusion_speed(time: ArrayLike, depth: ArrayLike) -> float:
    """A trial's speed through the mud [m/s]: the rate of its first intrusion from 10 % to
    90 % of its deepest depth [m] (0 if never below 0), over ``time`` [s].

    Examples
    --------
    >>> t = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5]
    >>> round(intrusion_speed(t, [-0.005, 0.0, 0.001, 0.002, 0.003, 0.003]), 9)  # 10 mm/s
    0.01
    """
    t, d = np.asarray(time, dtype=float), np.asarray(depth, dtype=float)
    deepest = float(np.max(d, initial=0.0))
    if not deepest > 0:
        return 0.0
    i90 = int(np.argmax(d >= 0.9 * deepest))
    below = np.flatnonzero(d[: i90 + 1] <= 0.1 * deepest)
    i10 = int(below[-1]) if below.size else 0
    if i10 >= i90:
        return 0.0
    return float((d[i90] - d[i10]) / (t[i90] - t[i10]))
