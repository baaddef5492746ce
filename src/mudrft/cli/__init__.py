"""The ``mudrft`` command: one module per subcommand, each thin over the library.

Each subcommand module has ``add_parser(subparsers)`` and ``run(args) -> int`` and imports
no heavy package before it runs, so ``mudrft --help`` parses without the physics. A user
mistake prints one line ``mudrft COMMAND: error: ...`` (exit status 2), a warning one line
``mudrft COMMAND: warning: ...``; notes go to stderr through the ``mudrft`` logger, results
to stdout.
"""

from __future__ import annotations

import argparse
import difflib
import logging
import sys
import warnings
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from types import ModuleType

from .. import __version__
from .._progress import enable_stderr_logging, logger
from .._validation import EXTRAS, MudrftError, plain_text
from . import bench, calibrate, compare, params, reproduce, simulate, sweep, walk
from ._common import Terminated, raise_swallowed, signals_as_exceptions
from ._parser import HelpFormatter

__all__ = ["COMMANDS", "build_parser", "main"]

#: The subcommands, in the order ``mudrft --help`` lists them.
COMMANDS: dict[str, ModuleType] = {
    m.__name__.rsplit(".", 1)[1]: m
    for m in (params, simulate, reproduce, calibrate, compare, walk, sweep, bench)
}


def build_parser() -> argparse.ArgumentParser:
    """The parser of ``mudrft``; parsed arguments carry ``command`` and ``func`` (its ``run``)."""
    p = argparse.ArgumentParser(
        prog="mudrft",
        description="Forces of mud on robot feet (Chen et al. 2026 model).",
        formatter_class=HelpFormatter,
    )
    p.add_argument("--version", action="version", version=f"mudrft {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")
    for module in COMMANDS.values():
        module.add_parser(sub)
    return p


def _plain(message: str) -> str:
    """One line, without numpy scalar reprs (``np.float64(1.0)`` reads ``1.0``)."""
    return " ".join(plain_text(message).split())


class _CommandLines(logging.Formatter):
    """Notes as they are; a warning as ``mudrft COMMAND: warning: ...``, also kept in ``warned``."""

    def __init__(self, prog: str) -> None:
        super().__init__("%(message)s")
        self.prog = prog
        self.warned: list[str] = []

    def format(self, record: logging.LogRecord) -> str:
        text = super().format(record)
        if record.levelno < logging.WARNING:
            return text
        self.warned.append(_plain(record.getMessage()).removeprefix(f"{self.prog}: warning: "))
        return (
            text if text.startswith(f"{self.prog}: ") else f"{self.prog}: warning: {_plain(text)}"
        )


@contextmanager
def _command_logging(quiet: bool, prog: str) -> Iterator[list[str]]:
    """For one command: notes and progress to the current stderr (``--quiet``: warnings
    only), Python warnings as log lines, and the warnings shown, for ``--strict``. The
    ``mudrft`` logger does not propagate meanwhile, so a root handler (MJX's
    ``logging.basicConfig``) does not print each line again."""
    had = any(getattr(h, "_mudrft_stderr", False) for h in logger.handlers)
    level, propagate = logger.level, logger.propagate
    logger.propagate = False
    handler = enable_stderr_logging(logging.WARNING if quiet else logging.INFO)
    assert isinstance(handler, logging.StreamHandler)  # the only kind it attaches
    old_format = handler.formatter
    lines = _CommandLines(prog)
    handler.setFormatter(lines)
    old_stream = handler.setStream(sys.stderr)  # None if it already writes there

    def show(message: Warning | str, *args: object, **kwargs: object) -> None:
        logger.warning("%s: warning: %s", prog, _plain(str(message)))

    try:
        with warnings.catch_warnings():
            warnings.showwarning = show
            yield lines.warned
    finally:
        handler.flush()
        handler.setFormatter(old_format)
        if not had:
            logger.removeHandler(handler)
        elif old_stream is not None:
            handler.setStream(old_stream)
        logger.setLevel(level)
        logger.propagate = propagate


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``mudrft`` command.

    Parameters
    ----------
    argv : sequence of str or None
        The arguments after ``mudrft`` (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status: 0 success, 1 a fit that did not converge or, with ``--strict``,
        a command that warned, 2 a user error, 130 interrupted (Ctrl-C), 143
        terminated (SIGTERM).
    """
    parser = build_parser()
    words = sys.argv[1:] if argv is None else list(argv)
    parser.exit_on_error = False  # a mistyped command is one line, as an option is
    try:
        args, unknown = parser.parse_known_args(words)
    except argparse.ArgumentError as exc:
        _unknown_command(parser, words, exc)
    if unknown:
        _unrecognized(parser, getattr(args, "command", None), unknown)
    if not getattr(args, "command", None):
        parser.print_help()
        return 0
    prog = f"mudrft {args.command}"
    with _command_logging(bool(getattr(args, "quiet", False)), prog) as warned:
        with signals_as_exceptions():
            if getattr(args, "overwrite", False):  # calibrate's old name of --force
                args.force = True
                logger.warning("--overwrite is deprecated and will be removed; use --force")
                warned.clear()  # not a warning of the run, for --strict
            try:
                code = int(args.func(args) or 0)
                raise_swallowed()
                if getattr(args, "strict", False) and warned and code == 0:
                    more = f" (and {len(warned) - 1} more warnings)" if len(warned) > 1 else ""
                    _error(prog, f"--strict: the command warned: {warned[0]}{more}")
                    return 1
                return code
            except MudrftError as exc:
                _error(prog, str(exc))
            except ModuleNotFoundError as exc:
                top = (exc.name or "").split(".")[0]
                if top not in EXTRAS:
                    raise
                extra = EXTRAS[top]
                _error(prog, f"needs the optional package {top}: pip install 'mudrft[{extra}]'")
            except FileNotFoundError as exc:
                _error(prog, f"{exc.filename or exc}: no such file or directory")
            except OSError as exc:
                where = f"{exc.filename}: " if exc.filename else ""
                _error(prog, f"{where}{exc.strerror or exc}")
            except KeyboardInterrupt:
                print(f"{prog}: interrupted", file=sys.stderr)
                return 130
            except Terminated:
                print(f"{prog}: terminated", file=sys.stderr)
                return 143
    return 2


def _unrecognized(parser: argparse.ArgumentParser, command: str | None, unknown: list[str]) -> None:
    """A word the command (or ``mudrft`` before any command) does not know: one line
    naming the closest option, exit status 2."""
    commands = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices
    if command is None:
        sub, prog, lists = parser, "mudrft", "the commands and options"
    else:
        sub, prog, lists = commands[command], f"mudrft {command}", "the options"
    options = [o for o in _options(sub) if o.startswith("--")]
    word = next((u for u in unknown if u.startswith("-")), unknown[0])
    name = word.split("=", 1)[0]
    if name in options:  # the command's own option, given before the command
        what = f"option {name!r} goes after the command: {prog} ... {name}"
    elif command is None and any(name in _options(c) for c in commands.values()):
        what = (
            f"unrecognized option {name!r}; a command's options go after it: mudrft COMMAND {name}"
        )
    elif name.startswith("-"):
        what = f"unrecognized option {name!r}{_did_you_mean(name, options)}"
    else:
        what = f"unrecognized argument {name!r}"
    sub.exit(2, f"{prog}: error: {what} ({prog} --help lists {lists})\n")


def _unknown_command(
    parser: argparse.ArgumentParser, words: list[str], exc: argparse.ArgumentError
) -> None:
    """A command that does not exist (``mudrft reproduc``): one line naming the closest."""
    if exc.argument_name != "COMMAND":
        parser.exit(2, f"mudrft: error: {_plain(str(exc))} (mudrft --help lists the options)\n")
    word = next((w for w in words if not w.startswith("-")), None)
    what = (
        f"unrecognized command {word!r}{_did_you_mean(word, list(COMMANDS))}"
        if word is not None
        else _plain(str(exc))
    )
    parser.exit(2, f"mudrft: error: {what} (mudrft --help lists the commands)\n")


def _options(parser: argparse.ArgumentParser) -> list[str]:
    return [o for a in parser._actions for o in a.option_strings]


def _did_you_mean(word: str, choices: list[str]) -> str:
    close = difflib.get_close_matches(word, choices, n=1, cutoff=0.6)
    return f"; did you mean {close[0]!r}?" if close else ""


def _error(prog: str, message: str) -> None:
    print(f"{prog}: error: {_plain(message)}", file=sys.stderr)
