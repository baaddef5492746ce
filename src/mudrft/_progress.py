"""Logging and progress of long jobs through the ``mudrft`` logger (silent unless configured).

>>> p = Progress("demo", enabled=False)
>>> p(0.5); p.last
50
"""

from __future__ import annotations

import logging
import sys
from collections.abc import Callable

__all__ = ["Progress", "enable_stderr_logging", "logger", "make_progress"]

logger = logging.getLogger("mudrft")
logger.addHandler(logging.NullHandler())

_HANDLER_FLAG = "_mudrft_stderr"


def enable_stderr_logging(level: int = logging.INFO) -> logging.Handler:
    """Attach (once) a plain stderr handler to the ``mudrft`` logger at ``level``; return it."""
    for h in logger.handlers:
        if getattr(h, _HANDLER_FLAG, False):
            logger.setLevel(level)
            return h
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter("%(message)s"))
    setattr(handler, _HANDLER_FLAG, True)
    logger.addHandler(handler)
    logger.setLevel(level)
    return handler


class Progress:
    """Called with the fraction done in [0, 1], log ``"label: 40 %"`` every ``step`` %."""

    def __init__(self, label: str, *, enabled: bool = True, step: int = 10) -> None:
        self.label, self.enabled, self.step = label, enabled, int(step)
        self.last = -self.step
        self._log = logging.getLogger("mudrft.progress")

    def __call__(self, fraction: float) -> None:
        pct = int(100 * min(max(float(fraction), 0.0), 1.0))
        if pct >= self.last + self.step or (pct == 100 and self.last < 100):
            self.last = pct
            if self.enabled:
                self._log.info("  %s: %3d %%", self.label, pct)

    def note(self, message: str) -> None:
        """A one-line note about the job (a stage that starts, a file written)."""
        if self.enabled:
            self._log.info("%s", message)


def make_progress(
    progress: bool | Callable[[float], None] | None, label: str
) -> Callable[[float], None] | None:
    """A user's ``progress=`` as a reporter: True a :class:`Progress`, a callable as it is."""
    if progress is True:
        if not any(not isinstance(h, logging.NullHandler) for h in logger.handlers) and not (
            logging.getLogger().handlers
        ):
            enable_stderr_logging()
        elif logger.level == logging.NOTSET or logger.level > logging.INFO:
            logger.setLevel(logging.INFO)
        return Progress(label)
    if callable(progress):
        return progress
    if progress is None or progress is False or type(progress).__name__ == "bool_":
        return None  # numpy's False
    from ._validation import MudrftError

    raise MudrftError(
        f"progress must be True, False or a callable taking the fraction done, got {progress!r}"
    )
