"""Notes and progress of a fit (internal): notes go to the ``mudrft.calibration`` logger,
or to a callable ``progress``; ``progress=True`` shows them with the percent done."""

from __future__ import annotations

import logging
import warnings
from collections.abc import Callable

from .._progress import make_progress
from .._validation import CalibrationWarning, MudrftError, _caller_level

logger = logging.getLogger("mudrft.calibration")


class Reporter:
    """Where a fit reports (``progress`` as :func:`~mudrft.calibration.calibrate`'s); the
    job is called ``label`` and made of ``steps`` calls of :meth:`step`."""

    def __init__(
        self, progress: bool | Callable[[str], object] | None, *, label: str, steps: int
    ) -> None:
        if progress is True:
            self._lines: Callable[[str], object] | None = None
            self._fraction = make_progress(True, label)
        elif progress is None or progress is False:
            self._lines, self._fraction = None, None
        elif callable(progress):
            self._lines, self._fraction = progress, None
        else:
            raise MudrftError(f"progress must be True, False, None or a callable, got {progress!r}")
        self._steps = max(int(steps), 1)
        self._done = 0

    def note(self, message: str) -> None:
        """Pass one line to the line callable, or log it when there is none (never both)."""
        if self._lines is not None:
            self._lines(message)
        else:
            logger.info("%s", message)

    @staticmethod
    def warn(message: str) -> None:
        """Something the user must see, whatever ``progress`` is: a
        :class:`~mudrft._validation.CalibrationWarning`."""
        warnings.warn(message, CalibrationWarning, stacklevel=_caller_level())

    def step(self) -> None:
        """One more step of the job is done."""
        self._done = min(self._done + 1, self._steps)
        if self._fraction is not None:
            self._fraction(self._done / self._steps)


def ordinal(k: int) -> str:
    """``2`` -> ``"2nd"``, ``11`` -> ``"11th"``, ``21`` -> ``"21st"``.

    Examples
    --------
    >>> [ordinal(k) for k in (1, 2, 3, 4, 11, 12, 13, 21, 102)]
    ['1st', '2nd', '3rd', '4th', '11th', '12th', '13th', '21st', '102nd']
    """
    if 10 <= k % 100 <= 20:
        return f"{k}th"
    return f"{k}{ {1: 'st', 2: 'nd', 3: 'rd'}.get(k % 10, 'th') }"
