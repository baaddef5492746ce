"""How a subcommand builds its parser: the help layout and the options several commands share.

Each ``mudrft`` subcommand registers itself with :func:`add_subcommand` (the one place that
gives it the house help layout, :class:`HelpFormatter`) and takes the shared options from
here: ``--force`` (the one overwrite flag), ``--strict``, ``--quiet`` and the foot options.
"""

from __future__ import annotations

import argparse

__all__ = [
    "GAIT_SPEED",
    "STANCE_DEPTH",
    "HelpFormatter",
    "add_foot_options",
    "add_force",
    "add_quiet",
    "add_strict",
    "add_subcommand",
]


#: The gait the subcommands share by default: its speed [m/s] and its deepest tip depth [m],
#: ``mudrft.trajectories.STANCE_DEPTH`` (D10; written here so that ``--help`` needs no
#: physics, and tested equal).
GAIT_SPEED = 0.2
STANCE_DEPTH = 0.02


class HelpFormatter(argparse.HelpFormatter):
    """Help that shows each option's default, except for flags and options without one."""

    def _get_help_string(self, action: argparse.Action) -> str | None:
        text = action.help or ""
        default = action.default
        if (
            "%(default)" in text
            or default in (None, False, argparse.SUPPRESS)
            or not action.option_strings
        ):
            return text
        if isinstance(default, list):
            return f"{text} (default: {' '.join(map(str, default))})"
        return f"{text} (default: %(default)s)"


def add_force(parser: argparse.ArgumentParser, what: str = "existing output files") -> None:
    """Add the one overwrite flag, ``--force``, to a subcommand's parser."""
    parser.add_argument("--force", action="store_true", help=f"overwrite {what}")


def add_strict(parser: argparse.ArgumentParser, what: str, *, refuses: str = "") -> None:
    """Add ``--strict``: a warning of the command makes its exit status 1 (``main`` acts on
    it); ``what`` says which warnings a script would fail on, ``refuses``
    what the command then refuses outright (an error, nothing written)."""
    text = (
        f"exit with status 1 if the command warns ({what}); the outputs are written as without it"
    )
    if refuses:
        text = f"refuse {refuses} (an error: nothing is written), and {text}"
    parser.add_argument("--strict", action="store_true", help=text)


def add_foot_options(parser: argparse.ArgumentParser, *, default: str | None = None) -> None:
    """Add ``--foot`` (a built-in foot or a mesh file; required when ``default`` is None),
    ``--unit`` (the mesh file's length unit), ``--up`` and ``--trailing`` to a subcommand's
    parser."""
    parser.add_argument(
        "--foot",
        required=default is None,
        default=default,
        help="flat, semi-cylinder, semi-sphere, morphing, or a mesh file (.stl/.obj/.ply)",
    )
    parser.add_argument(
        "--unit",
        choices=["m", "mm", "cm", "in"],
        default=None,
        help="length unit of a mesh file's coordinates (default: m; a mesh more than 1 m or "
        "less than 1 mm across warns)",
    )
    parser.add_argument(
        "--up",
        choices=["z", "y", "x", "-z", "-y", "-x"],
        default=None,
        help="the mesh file's up axis, turned to z (a Y-up export: y; default: z)",
    )
    parser.add_argument(
        "--trailing",
        action="store_const",
        const=True,
        default=None,
        help="a mesh foot's trailing facets resist too (as in the semi-sphere's closed form, "
        "D23; default: leading facets only)",
    )


def add_subcommand(
    subparsers: argparse._SubParsersAction[argparse.ArgumentParser],
    name: str,
    *,
    help: str,
    description: str,
) -> argparse.ArgumentParser:
    """Register ``mudrft NAME`` with the house help layout and return its parser.

    Parameters
    ----------
    subparsers : argparse subparsers action
        From :func:`mudrft.cli.build_parser`.
    name : str
        The subcommand.
    help : str
        One line for ``mudrft --help``.
    description : str
        The paragraph of ``mudrft NAME --help``.
    """
    return subparsers.add_parser(
        name, help=help, description=description, formatter_class=HelpFormatter
    )


def add_evaluation_options(parser: argparse.ArgumentParser, *, what: str) -> None:
    """Add ``--thixotropy`` and ``--clock``: how eqs. (3), (5) are evaluated (decision D15).

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The subcommand's parser.
    what : str
        What ``--thixotropy`` does in this command (its help text).
    """
    parser.add_argument("--thixotropy", choices=["ode", "quasi-static"], default="ode", help=what)
    parser.add_argument(
        "--clock",
        choices=["contact", "retraction"],
        default="contact",
        help="quasi-static only: clock of eq. (9) from first contact or from the retraction",
    )


def add_quiet(parser: argparse.ArgumentParser) -> None:
    """Add ``--quiet``: no progress output."""
    parser.add_argument("--quiet", action="store_true", help="no progress output")
