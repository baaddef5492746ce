"""Notes and progress of a fit (internal).

Notes (the start, each stage, the end) go to the ``mudrft.calibration`` logger at INFO
level; nothing is printed. ``progress=True`` makes them visible on stderr and adds
``calibrate: NN %`` lines, through :func:`mudrft._progress.make_progress`, the one
progress mechanism of the library. A callable ``progress`` receives each note line (a
str), as the command line and the examples use it.
"""

from __future__ import annotations

import logging
from collections.abc import Callable

from .._progress import make_progress
from .._validation import MudrftError

__all__ = ["Reporter", "logger"]

logger = logging.getLogger("mudrft.calibration")


class Reporter:
    """Where a fit reports: notes to the logger (and a line callable), fractions done.

    Parameters
    ----------
    progress : bool, callable or None
        ``True``: notes shown on stderr and progress in percent; a callable: called with
        each note line; ``False``/``None``: notes only to the logger.
    label : str, keyword-only
        Name of the job in the progress lines.
    steps : int, keyword-only
        Number of :meth:`step` calls that make the whole job [-].
    """

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

    def note(self, message: str, *, level: int = logging.INFO) -> None:
        """Pass one line to the line callable, or log it when there is none (never both)."""
        if self._lines is not None:
            self._lines(message)
        else:
            logger.log(level, "%s", message)

    def step(self) -> None:
        """One more step of the job is done."""
        self._done = min(self._done + 1, self._steps)
        if self._fraction is not None:
            self._fraction(self._done / self._steps)
