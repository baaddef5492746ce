"""How a subcommand builds its parser: the help layout and the options several commands share."""

from __future__ import annotations

import argparse
from collections.abc import Callable

#: The default gait of the subcommands: speed [m/s] and deepest tip depth [m] (as
#: ``mudrft.trajectories.STANCE_DEPTH``; written here so that ``--help`` needs no physics).
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


def add_subcommand(
    subparsers: argparse._SubParsersAction[argparse.ArgumentParser],
    name: str,
    run: Callable[[argparse.Namespace], int],
    *,
    help: str,
    description: str,
) -> argparse.ArgumentParser:
    """Register ``mudrft NAME`` (``run`` runs it) with the house help layout; its parser."""
    p = subparsers.add_parser(
        name, help=help, description=description, formatter_class=HelpFormatter
    )
    p.set_defaults(func=run)
    return p


def add_run_options(
    parser: argparse.ArgumentParser,
    *,
    force: str,
    strict: str | None = None,
    refuses: str = "",
) -> None:
    """Add ``--force`` (overwrites ``force``), ``--quiet`` and ``--strict``: a warning
    (``strict`` says which) makes the exit status 1, and ``refuses`` is refused outright."""
    parser.add_argument("--force", action="store_true", help=f"overwrite {force}")
    parser.add_argument("--quiet", action="store_true", help="no progress output")
    if strict is not None:
        text = (
            f"exit with status 1 if the command warns ({strict}); the outputs are written as "
            "without it"
        )
        if refuses:
            text = f"refuse {refuses} (an error: nothing is written), and {text}"
        parser.add_argument("--strict", action="store_true", help=text)


def add_foot_options(parser: argparse.ArgumentParser, *, default: str | None = None) -> None:
    """Add ``--foot`` (required without ``default``), and a mesh file's ``--unit``,
    ``--up`` and ``--trailing``."""
    parser.add_argument(
        "--foot",
        required=default is None,
        default=default,
        help="flat, semi-cylinder, semi-sphere, morphing, or a mesh file (.stl/.obj/.ply)",
    )
    parser.add_argument(
        "--unit",
        choices=["m", "mm", "cm", "in"],
        help="length unit of a mesh file's coordinates (default: m; a mesh more than 1 m or "
        "less than 1 mm across warns)",
    )
    parser.add_argument(
        "--up",
        choices=["z", "y", "x", "-z", "-y", "-x"],
        help="the mesh file's up axis, turned to z (a Y-up export: y; default: z)",
    )
    parser.add_argument(
        "--trailing",
        action="store_true",
        default=None,
        help="a mesh foot's trailing facets resist too (as in the semi-sphere's closed form, "
        "D23; default: leading facets only)",
    )


def add_evaluation_options(parser: argparse.ArgumentParser, *, what: str) -> None:
    """Add ``--thixotropy`` (``what``: its help) and ``--clock``: how eqs. (3), (5) are
    evaluated (D15)."""
    parser.add_argument("--thixotropy", choices=["ode", "quasi-static"], default="ode", help=what)
    parser.add_argument(
        "--clock",
        choices=["contact", "retraction"],
        default="contact",
        help="quasi-static only: clock of eq. (9) from first contact or from the retraction",
    )
