"""The mud of a command: the paper's row at ``--water-content``, or fitted sets in its place.

``--vertical FIT.json`` and ``--horizontal FIT.json`` put a parameter set written by
``mudrft calibrate --out`` in place of the paper's row of that direction;
the direction not given stays the paper's. Shared by ``mudrft simulate`` and ``mudrft walk``.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from .._validation import MudrftError
from ._common import paper_mud_option

if TYPE_CHECKING:
    from ..parameters import Mud

__all__ = ["add_fit_options", "mud_from_options"]


def add_fit_options(p: argparse.ArgumentParser) -> None:
    """Add ``--vertical FIT.json`` and ``--horizontal FIT.json`` to a command's parser."""
    for d in ("vertical", "horizontal"):
        p.add_argument(
            f"--{d}",
            metavar="FIT.json",
            help=f"{d} parameter set from a file (mudrft calibrate --out, SI) in place of the "
            f"paper's {d} row at --water-content",
        )


def mud_from_options(args: argparse.Namespace) -> Mud:
    """The paper's mud at ``--water-content``, with a set from ``--vertical`` or
    ``--horizontal`` in place of its row; errors name the option."""
    from ..calibration.persistence import load_parameters
    from ..parameters import Mud

    paper = paper_mud_option(
        args.water_content,
        extrapolate=args.extrapolate,
        labels=getattr(args, "labels", "table"),
    )
    sets, names = {}, []
    for d in ("vertical", "horizontal"):
        path = getattr(args, d)
        if path is None:
            sets[d] = getattr(paper, d)
            continue
        try:
            params = load_parameters(path)
        except MudrftError as exc:
            raise MudrftError(f"--{d}: {exc}") from None
        if params.direction not in ("", d):
            raise MudrftError(
                f"--{d}: {path!r} holds a {params.direction} parameter set, expected a {d} one "
                "(were --vertical and --horizontal swapped?)"
            )
        sets[d] = params
        names.append(f"{d} {path}")
    if not names:
        return paper
    w = f"W = {100 * args.water_content:g} %"
    name = ", ".join(names) + ("" if len(names) == 2 else f", the rest of the paper's mud at {w}")
    return Mud(sets["vertical"], sets["horizontal"], paper.water_content, name=name)
