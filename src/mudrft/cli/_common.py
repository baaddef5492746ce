"""What the subcommands share: option checks, optional extras, safe outputs.

Outputs are all-or-nothing (:class:`Outputs`). A command registers every file (or
directory) it will write *before* it starts working, so that an existing output without
``--force``, a directory that is a file, or a missing parent directory is reported at once.
It writes in staging directories beside the targets; :meth:`Outputs.commit` then moves
every file to its final name. When anything fails (also SIGTERM or Ctrl-C), the staging
directories and the directories the command created are removed.
"""

from __future__ import annotations

import importlib
import logging
import math
import os
import shutil
import signal
import threading
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path
from types import ModuleType, TracebackType
from typing import TYPE_CHECKING, Any, ClassVar

from .._progress import logger
from .._validation import MudrftError
from ..io.atomic import move_into_place, regular_target, staging_directory

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..parameters import Mud

__all__ = [
    "EXTRAS",
    "Outputs",
    "check_finite_option",
    "check_nonnegative_option",
    "check_positive_option",
    "logger",
    "paper_mud_option",
    "require_extra",
    "require_plot_file",
    "same_file",
    "save_figure",
]

#: Optional packages and the extra of ``pip install 'mudrft[EXTRA]'`` that provides them.
EXTRAS = {
    "matplotlib": "plot",
    "mujoco": "mujoco",
    "jax": "jax",
    "numba": "numba",
    "pandas": "pandas",
    "h5py": "hdf5",
    "dask": "sweep",
    "distributed": "sweep",
    "xarray": "sweep",
    "zarr": "sweep",
}


def require_extra(module: str, *, needed_for: str, unless: str | None = None) -> ModuleType:
    """Import an optional package, or fail with one line naming the extra to install.

    Parameters
    ----------
    module : str
        The package, a key of :data:`EXTRAS`.
    needed_for : str
        What needs it, for the message (``"mudrft walk"``, ``"--plot"``).
    unless : str, optional
        The option that does without it (``"--no-figures"``), named in the message.
    """
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise MudrftError(
            f"{needed_for} needs the optional package {module}, which is not installed: "
            f"pip install 'mudrft[{EXTRAS.get(module, module)}]'"
            + (f", or pass {unless}" if unless else "")
        ) from exc


def require_plot_file(option: str, path: str | Path) -> None:
    """Check, before any work, that matplotlib is installed and can write ``path``'s format.

    Parameters
    ----------
    option : str
        The option that names the figure (``"--plot"``), for the message.
    path : str or Path
        The figure's file name; its suffix chooses the format (``.png``, ``.pdf``, ...).
    """
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
    """Write ``fig`` to ``path`` and close it, also when writing fails (pyplot keeps every
    figure it made open, and its memory, until it is closed).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        A figure made through pyplot (``Result.plot``, ``plot_maps``, ...).
    path : str or Path
        The file; its suffix chooses the format.
    dpi : int, keyword-only
        Resolution of a raster format [dots per inch].
    """
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


def check_positive_option(option: str, value: float, *, unit: str = "") -> float:
    """Return ``value`` as a float; raise naming ``option`` unless it is finite and > 0."""
    return _compare(option, value, unit, ">")


def check_nonnegative_option(option: str, value: float, *, unit: str = "") -> float:
    """Return ``value`` as a float; raise naming ``option`` unless it is finite and >= 0."""
    return _compare(option, value, unit, ">=")


def _compare(option: str, value: float, unit: str, sign: str) -> float:
    v = check_finite_option(option, value, unit=unit)
    if not (v > 0 if sign == ">" else v >= 0):
        raise MudrftError(f"{option} must be {sign} 0{' ' + unit if unit else ''}, got {v:g}")
    return v


def paper_mud_option(water_content: float, *, extrapolate: bool, labels: str = "table") -> Mud:
    """The paper's mud at ``--water-content``; errors name the options, not the arguments."""
    from ..parameters import paper_mud

    check_finite_option("--water-content", water_content)
    try:
        return paper_mud(water_content, extrapolate=extrapolate, labels=labels)
    except MudrftError as exc:
        text = str(exc).replace("pass extrapolate=True", "pass --extrapolate")
        if text.startswith("water_content "):
            text = "--water-content " + text[len("water_content ") :]
        raise MudrftError(text) from None


def same_file(a: str | Path, b: str | Path) -> bool:
    """Whether two paths name the same file (after resolving links and ``..``)."""
    try:
        return Path(a).resolve() == Path(b).resolve()
    except (OSError, RuntimeError):  # unresolvable (3.11 raises RuntimeError on a link loop)
        return False


def _check_named(option: str, path: str | Path, expected: str) -> None:
    """Refuse an empty output name: ``Path("")`` is the current directory, so ``--out ""``
    (an unset shell variable, ``--out "$DIR"``) would write there unasked."""
    if not os.fspath(path):
        raise MudrftError(f"{option}: expected {expected}, got an empty string")


class _RenameFilter(logging.Filter):
    """Show final names, not temporary ones, in the log lines written during a command."""

    def __init__(self, names: dict[str, str]) -> None:
        super().__init__()
        self.names = names

    def filter(self, record: logging.LogRecord) -> bool:
        text = original = record.getMessage()
        for tmp, final in self.names.items():
            text = text.replace(tmp, final)
        if text != original:
            record.msg, record.args = text, ()
        return True


class Terminated(BaseException):
    """SIGTERM turned into an exception, so that unwinding discards unfinished outputs."""


class _Signals:
    """The command's signal bookkeeping (main thread only)."""

    #: While above zero, a signal waits (:func:`_signals_held`); the one that waits.
    held = 0
    pending: type[BaseException] | None = None
    #: Per running command (innermost last), its outputs not yet moved or removed.
    commands: ClassVar[list[list[Outputs]]] = []


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


def _deliver(exc_type: type[BaseException]) -> None:
    """Raise ``exc_type`` now, or once the outputs' bookkeeping is consistent again."""
    if _Signals.held:
        _Signals.pending = _Signals.pending or exc_type
    else:
        raise exc_type


@contextmanager
def signals_as_exceptions() -> Iterator[None]:
    """While a command runs, SIGTERM (``kill``, a batch system's time limit, ``timeout``)
    raises :class:`Terminated` and SIGINT (Ctrl-C) ``KeyboardInterrupt``, unless an output
    is being created, moved or removed (:func:`_signals_held`): then they are raised when
    that ends. On the way out every output neither moved nor removed yet is removed (also
    one whose ``with`` block the signal cut short before its cleanup began): a failed run
    leaves nothing behind. A signal the caller ignores stays ignored. Only in the main
    thread, where Python delivers signals."""
    if not _main_thread():
        yield
        return

    def terminate(signum: int, frame: object) -> None:
        _deliver(Terminated)

    def interrupt(signum: int, frame: object) -> None:
        _deliver(KeyboardInterrupt)

    mine: list[Outputs] = []
    _Signals.commands.append(mine)
    previous: dict[int, Any] = {}
    for signum, handler in ((signal.SIGTERM, terminate), (signal.SIGINT, interrupt)):
        # a background job starts with SIGINT ignored: kept so, as Python itself does
        if signal.getsignal(signum) is not signal.SIG_IGN:
            previous[signum] = signal.signal(signum, handler)
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
        finally:
            _Signals.held -= 1
            _Signals.pending = None


@contextmanager
def _signals_held() -> Iterator[None]:
    """Hold SIGINT and SIGTERM back while an output is created and registered, or while
    the outputs are moved or removed: a signal between the two would leave a file that no
    cleanup knows about (the staging directory of a terminated run, seen on a busy CI
    machine). A held signal is raised as the block ends. (A thread's signal mask cannot do
    this: the kernel hands a process's signal to any thread that does not block it, and
    Python then runs the handler in the main thread at once.)"""
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
    """The files one command writes, written all-or-nothing.

    Use it as a context manager: on leaving the block normally every registered output is
    moved to its final name; on an exception nothing of the command's stays behind. Each
    output is written in a staging directory beside its target
    (:func:`mudrft.io.atomic.staging_directory`, which also removes what killed runs left).

    Parameters
    ----------
    force : bool, keyword-only
        Replace existing outputs (the ``--force`` flag).

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
        self._filter = _RenameFilter({})
        self._registry: list[Outputs] | None = None  # the running command's, once entered
        #: The final paths, once :meth:`commit` has moved the outputs there.
        self.written: list[Path] = []

    # -- registration -------------------------------------------------------------------
    def file(self, option: str, path: str | Path) -> Path:
        """Register the output file ``path`` of ``option``; return the name to write to.

        The directory of ``path`` must exist. The name returned is ``path``'s own name in
        a staging directory beside it (so writers that look at its suffix, such as
        matplotlib's ``savefig``, choose the right format).
        """
        _check_named(option, path, "a file name")
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
        self._filter.names[str(staged)] = str(final)
        return staged

    def directory(self, option: str, path: str | Path, names: Iterable[str]) -> Path:
        """Register the output directory ``path``; return a staging directory to write in.

        ``names`` are the files the command may write there; those that exist are an
        error without ``--force``. ``path`` and its missing parents are created (and
        removed again if the command fails).
        """
        _check_named(option, path, "a directory name")
        final = Path(path)
        self._check_parents(option, final)
        if final.exists() and not final.is_dir():
            raise MudrftError(f"{option} {str(final)!r} exists and is not a directory")
        for name in names:
            self._check_free(option, regular_target(final / name, option))
        with _signals_held():
            self._mkdirs(option, final)
        stage = self._stage(option, final)
        self._filter.names[str(stage)] = str(final)
        return stage

    def _stage(self, option: str, final: Path) -> Path:
        """A staging directory in ``final``, registered for the move or the cleanup (a
        signal waits until it is: a signal between the two would leave it behind)."""
        with _signals_held():
            try:
                stage = staging_directory(final)
            except OSError as exc:
                raise MudrftError(
                    f"{option} {str(final)!r} is not writable: {exc.strerror or exc}"
                ) from exc
            self._stages.append((stage, final, option))
        return stage

    # -- checks -------------------------------------------------------------------------
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

    # -- the end ------------------------------------------------------------------------
    def commit(self) -> list[Path]:
        """Move every output to its final name; return the final paths (also ``written``)."""
        moves = [
            (item, regular_target(final / item.name, option), option)
            for stage, final, option in list(self._stages)
            for item in sorted(stage.iterdir())
        ]
        for _, final, option in moves:  # also an output that was not announced
            self._check_free(option, final)
        moves = self._beside_targets(moves)
        for staged, final, option in moves:
            try:
                move_into_place(staged, final, overwrite=True, option=option)
            except OSError as exc:
                raise MudrftError(
                    f"{option}: cannot write {str(final)!r}: {exc.strerror or exc}"
                ) from exc
            self.written.append(final)
        self._made = []
        self.discard()
        return self.written

    def _beside_targets(self, moves: list[tuple[Path, Path, str]]) -> list[tuple[Path, Path, str]]:
        """Each staged file copied next to its target where that is elsewhere (a symbolic
        link in an output directory names a file in another directory, maybe on another
        file system, where a rename cannot reach): every copy is made before any output
        is moved, so a copy that fails leaves the outputs as they were."""
        out = []
        for staged, final, option in moves:
            try:
                same = os.path.samefile(staged.parent.parent, final.parent)
            except OSError:  # a link into a directory that is not there: _stage names it
                same = False
            if not same:
                near = self._stage(option, final.parent) / final.name
                try:
                    shutil.copyfile(staged, near)
                except OSError as exc:
                    raise MudrftError(
                        f"{option}: cannot write {str(final)!r}: {exc.strerror or exc}"
                    ) from exc
                staged = near
            out.append((staged, final, option))
        return out

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

    @contextmanager
    def _renaming_logs(self) -> Iterator[None]:
        handlers = [h for h in logger.handlers if not isinstance(h, logging.NullHandler)]
        for h in handlers:
            h.addFilter(self._filter)
        try:
            yield
        finally:
            for h in handlers:
                h.removeFilter(self._filter)

    def __enter__(self) -> Outputs:
        self._logs = self._renaming_logs()
        self._logs.__enter__()
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
                        try:
                            self.commit()
                        except BaseException:
                            self.discard()
                            raise
                    else:
                        self.discard()
                finally:
                    if self._registry is not None and self in self._registry:
                        self._registry.remove(self)
        finally:
            self._logs.__exit__(None, None, None)
