"""What the subcommands share: option checks, optional extras, all-or-nothing outputs."""

from __future__ import annotations

import logging
import math
import os
import shutil
import signal
import sys
import threading
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path
from types import TracebackType
from typing import TYPE_CHECKING, Any, ClassVar

from .._progress import logger
from .._validation import MudrftError, require_extra
from ..io.atomic import move_into_place, regular_target, staging_directory

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def require_plot_file(option: str, path: str | Path) -> None:
    """Check, before any work, that matplotlib can write ``path``'s format (its suffix)."""
    require_extra("matplotlib", needed_for=option)
    from matplotlib.figure import Figure

    formats = Figure().canvas.get_supported_filetypes()
    suffix = Path(path).suffix.lower().lstrip(".")
    if suffix not in formats:
        got = f"'.{suffix}'" if suffix else "no suffix"
        raise MudrftError(
            f"{option} {str(path)!r}: expected a figure file name ending in one of "
            f"{', '.join('.' + f for f in sorted(formats))}; got {got}"
        )


def save_figure(fig: Figure, path: str | Path, *, dpi: int = 120) -> None:
    """Write ``fig`` to ``path`` [dpi: dots per inch] and close it, also when writing fails."""
    import matplotlib.pyplot as plt

    try:
        fig.savefig(path, dpi=dpi)
    finally:
        plt.close(fig)


def check_finite_option(option: str, value: float, *, unit: str = "") -> float:
    """Return ``value`` as a float; raise naming ``option`` if it is NaN or infinite."""
    if not math.isfinite(value):
        where = f" [{unit}]" if unit else ""
        raise MudrftError(f"{option} must be a finite number{where}, got {float(value):g}")
    return float(value)


def check_positive_option(option: str, value: float, *, unit: str = "", ge: bool = False) -> float:
    """Return ``value`` as a float; raise naming ``option`` unless it is finite and > 0
    (``ge``: >= 0)."""
    v = check_finite_option(option, value, unit=unit)
    if not (v >= 0 if ge else v > 0):
        bound = f"{'>=' if ge else '>'} 0{' ' + unit if unit else ''}"
        raise MudrftError(f"{option} must be {bound}, got {v:g}")
    return v


def same_file(a: str | Path, b: str | Path) -> bool:
    """Whether two paths name the same file (after resolving links and ``..``)."""
    try:
        return Path(a).resolve() == Path(b).resolve()
    except (OSError, RuntimeError):  # unresolvable (3.11 raises RuntimeError on a link loop)
        return False


def _cannot_write(option: str, final: Path, exc: OSError) -> MudrftError:
    return MudrftError(f"{option}: cannot write {str(final)!r}: {exc.strerror or exc}")


class Terminated(BaseException):
    """SIGTERM turned into an exception, so that unwinding discards unfinished outputs."""


class _Signals:
    """The command's signal bookkeeping (main thread only): while ``held`` is above zero a
    signal waits in ``pending`` (:func:`_signals_held`)."""

    held = 0
    pending: type[BaseException] | None = None
    #: The first signal delivered during the command (:func:`raise_swallowed`).
    received: type[BaseException] | None = None
    #: Per running command (innermost last), its outputs not yet moved or removed.
    commands: ClassVar[list[list[Outputs]]] = []


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


@contextmanager
def signals_as_exceptions() -> Iterator[None]:
    """While a command runs, SIGTERM raises :class:`Terminated` and SIGINT
    ``KeyboardInterrupt`` (held while an output is created, moved or removed); on the way
    out every output of the command not yet moved is removed. A signal the caller ignores
    stays ignored. Main thread only, where Python delivers signals."""
    if not _main_thread():
        yield
        return

    def deliver(signum: int, frame: object) -> None:
        """Raise now, or once the outputs' bookkeeping is consistent again."""
        exc_type = Terminated if signum == signal.SIGTERM else KeyboardInterrupt
        _Signals.received = _Signals.received or exc_type
        if _Signals.held:
            _Signals.pending = _Signals.pending or exc_type
        else:
            raise exc_type

    def unraisable(u: Any) -> None:
        """Python's "Exception ignored" report, quiet for our signal's (raised again later)."""
        if not (isinstance(u.exc_value, Terminated | KeyboardInterrupt) and _Signals.received):
            hook(u)

    mine: list[Outputs] = []
    _Signals.commands.append(mine)
    _Signals.received = None
    hook, sys.unraisablehook = sys.unraisablehook, unraisable
    previous: dict[int, Any] = {}
    for signum in (signal.SIGTERM, signal.SIGINT):
        # a background job starts with SIGINT ignored: kept so, as Python itself does
        if signal.getsignal(signum) is not signal.SIG_IGN:
            previous[signum] = signal.signal(signum, deliver)
    try:
        yield
    finally:
        _Signals.held += 1  # a signal now waits; the command is over, so it is dropped
        try:
            for outputs in mine:  # this command's, not an outer one's
                outputs.discard()
            _Signals.commands = [c for c in _Signals.commands if c is not mine]
            for restored, before in previous.items():
                signal.signal(restored, before)
            sys.unraisablehook = hook
        finally:
            _Signals.held -= 1
            _Signals.pending = _Signals.received = None


def raise_swallowed() -> None:
    """Raise a signal delivered during the command whose exception Python ignored (it
    came while a weakref callback or ``__del__`` ran), so the command does not finish,
    and commit its outputs, as if it had not been terminated."""
    if _Signals.received is not None and _main_thread():
        raise _Signals.received


@contextmanager
def _signals_held() -> Iterator[None]:
    """Hold SIGINT and SIGTERM back while an output is created and registered, or moved
    or removed (a signal between the two would leave a file no cleanup knows about); a
    held signal is raised as the block ends."""
    if not _main_thread():  # Python runs signal handlers in the main thread only
        yield
        return
    _Signals.held += 1
    try:
        yield
    finally:
        _Signals.held -= 1
        exc_type = _Signals.pending
        if not _Signals.held and exc_type is not None:
            _Signals.pending = None
            raise exc_type


class Outputs:
    """The files one command writes, all or nothing (``--force``: replace existing ones).

    Each output is registered before the work starts (so an existing output, a missing
    directory, ... is reported at once) and written in a staging directory beside its
    target (:func:`mudrft.io.atomic.staging_directory`). Leaving the block moves every
    output to its final name; an exception (also SIGTERM, Ctrl-C) removes the staging
    directories and the directories the command created.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> with Outputs(force=False) as out:
    ...     out.file("--out", d / "a.txt").write_text("hello")
    5
    >>> sorted(p.name for p in d.iterdir())
    ['a.txt']
    >>> import shutil; shutil.rmtree(d)
    """

    def __init__(self, *, force: bool) -> None:
        self.force = bool(force)
        #: (staging directory, final directory, option): everything staged is moved there
        self._stages: list[tuple[Path, Path, str]] = []
        self._files: list[tuple[Path, str]] = []  # the files announced, with their option
        self._made: list[Path] = []  # directories this command created, outermost first
        self._names: dict[str, str] = {}  # staging name -> final name, for the log lines
        self._registry: list[Outputs] | None = None  # the running command's, once entered
        #: The final paths, once :meth:`commit` has moved the outputs there.
        self.written: list[Path] = []

    def file(self, option: str, path: str | Path) -> Path:
        """Register the output file ``path`` of ``option`` (its directory must exist);
        return the name to write to, with ``path``'s own name (and suffix)."""
        if not os.fspath(path):  # ``--out "$UNSET"`` would write in the current directory
            raise MudrftError(f"{option}: expected a file name, got an empty string")
        final = regular_target(path, option)
        self._check_parents(option, final)
        if not final.parent.is_dir():
            raise MudrftError(
                f"{option} {str(final)!r}: the directory {str(final.parent)!r} does not exist"
            )
        if final.is_dir():
            raise MudrftError(f"{option} {str(final)!r} is a directory, expected a file name")
        self._check_free(option, final)
        for other, other_option in self._files:
            if same_file(other, final):
                raise MudrftError(f"{option} and {other_option} name the same file {str(final)!r}")
        self._files.append((final, option))
        staged = self._stage(option, final.parent) / final.name
        self._names[str(staged)] = str(final)
        return staged

    def directory(self, option: str, path: str | Path, names: Iterable[str]) -> Path:
        """Register the output directory ``path`` (created with its parents if missing)
        where the command may write ``names``; return a staging directory to write in."""
        if not os.fspath(path):
            raise MudrftError(f"{option}: expected a directory name, got an empty string")
        final = Path(path)
        self._check_parents(option, final)
        if final.exists() and not final.is_dir():
            raise MudrftError(f"{option} {str(final)!r} exists and is not a directory")
        for name in names:
            self._check_free(option, regular_target(final / name, option))
        with _signals_held():
            self._mkdirs(option, final)
        stage = self._stage(option, final)
        self._names[str(stage)] = str(final)
        return stage

    def _stage(self, option: str, final: Path) -> Path:
        """A staging directory in ``final``, registered for the move or the cleanup."""
        with _signals_held():
            try:
                stage = staging_directory(final)
            except OSError as exc:
                raise MudrftError(
                    f"{option} {str(final)!r} is not writable: {exc.strerror or exc}"
                ) from exc
            self._stages.append((stage, final, option))
        return stage

    def _check_free(self, option: str, path: Path) -> None:
        if path.exists() and not self.force:
            raise MudrftError(f"{option}: {str(path)!r} exists; pass --force to overwrite it")

    @staticmethod
    def _check_parents(option: str, path: Path) -> None:
        for parent in path.parents:
            if parent.exists():
                if not parent.is_dir():
                    raise MudrftError(
                        f"{option} {str(path)!r}: {str(parent)!r} is a file, not a directory"
                    )
                return

    def _mkdirs(self, option: str, path: Path) -> None:
        missing = [p for p in (path, *path.parents) if not p.exists()]
        for p in reversed(missing):
            try:
                p.mkdir()
            except FileExistsError:
                continue
            except OSError as exc:
                raise MudrftError(
                    f"{option} {str(path)!r}: cannot create {str(p)!r}: {exc.strerror or exc}"
                ) from exc
            self._made.append(p)

    def commit(self) -> list[Path]:
        """Move every output to its final name; return the final paths (also ``written``).

        A staged file whose target is elsewhere (a symbolic link to another directory or
        file system, where a rename cannot reach) is first copied beside its target: every
        copy is made before any output is moved."""
        moves = [
            (item, regular_target(final / item.name, option), option)
            for stage, final, option in list(self._stages)
            for item in sorted(stage.iterdir())
        ]
        for _, final, option in moves:  # also an output that was not announced
            self._check_free(option, final)
        for k, (staged, final, option) in enumerate(moves):
            try:
                same = os.path.samefile(staged.parent.parent, final.parent)
            except OSError:  # a link into a directory that is not there: _stage names it
                same = False
            if not same:
                near = self._stage(option, final.parent) / final.name
                try:
                    shutil.copyfile(staged, near)
                except OSError as exc:
                    raise _cannot_write(option, final, exc) from exc
                moves[k] = (near, final, option)
        for staged, final, option in moves:
            try:
                move_into_place(staged, final, overwrite=True, option=option)
            except OSError as exc:
                raise _cannot_write(option, final, exc) from exc
            self.written.append(final)
        self._made = []
        self.discard()
        return self.written

    def discard(self) -> None:
        """Remove the staging directories and the directories this command created."""
        for stage, _, _ in self._stages:
            shutil.rmtree(stage, ignore_errors=True)
        for d in reversed(self._made):
            try:
                d.rmdir()
            except OSError:  # not empty: something else wrote there meanwhile
                break
        self._stages, self._made = [], []

    def _rename(self, record: logging.LogRecord) -> bool:
        """A log filter: final names, not staging ones, in the lines logged meanwhile."""
        text = original = record.getMessage()
        for tmp, final in self._names.items():
            text = text.replace(tmp, final)
        if text != original:
            record.msg, record.args = text, ()
        return True

    def __enter__(self) -> Outputs:
        self._handlers = [h for h in logger.handlers if not isinstance(h, logging.NullHandler)]
        for h in self._handlers:
            h.addFilter(self._rename)
        self._registry = _Signals.commands[-1] if _Signals.commands and _main_thread() else None
        if self._registry is not None:
            self._registry.append(self)
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        try:
            with _signals_held():  # a signal now is taken after the move or the cleanup
                try:
                    if exc_type is None:
                        raise_swallowed()
                        self.commit()
                finally:
                    self.discard()  # after a commit there is nothing left to remove
                    if self._registry is not None and self in self._registry:
                        self._registry.remove(self)
        finally:
            for h in self._handlers:
                h.removeFilter(self._rename)
