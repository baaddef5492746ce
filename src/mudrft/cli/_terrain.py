"""The mud or terrain of a command: the paper's mud at ``--water-content``, fitted sets in
its place (``--vertical``, ``--horizontal FIT.json``), or a baseline (``--terrain(s)``)
with its medium (``--zeta``; ``--rho-c``, ``--mu-int``, ``--mu-surf``)."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

from .._validation import MudrftError
from ._common import check_finite_option, check_positive_option

if TYPE_CHECKING:
    from ..parameters import Mud
    from ..terrains import Terrain

#: ``mudrft.baselines.TERRAIN_NAMES``, written here so that ``--help`` needs no physics.
TERRAIN_NAMES = ("mud", "granular-rft", "granular-rft3d", "linear", "maxwell", "rigid")

#: Option -> (terrain it describes, unit for messages).
MEDIUM_OPTIONS = {
    "--zeta": ("granular-rft", "N/m^3"),
    "--rho-c": ("granular-rft3d", "kg/m^3"),
    "--mu-int": ("granular-rft3d", ""),
    "--mu-surf": ("granular-rft3d", ""),
}


def add_mud_options(
    p: argparse.ArgumentParser, *, water: str = "water content W [-], 0.25 to 0.45"
) -> None:
    """Add ``--water-content`` (``water``: its help), ``--vertical FIT.json`` and
    ``--horizontal FIT.json``."""
    p.add_argument("--water-content", type=float, default=0.25, help=water)
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
    from ..parameters import Mud, paper_mud

    check_finite_option("--water-content", args.water_content)
    try:
        paper = paper_mud(
            args.water_content,
            extrapolate=args.extrapolate,
            labels=getattr(args, "labels", "table"),
        )
    except MudrftError as exc:
        text = str(exc).replace("pass extrapolate=True", "pass --extrapolate")
        if text.startswith("water_content "):
            text = "--water-content " + text[len("water_content ") :]
        raise MudrftError(text) from None
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


def add_terrain_options(parser: argparse.ArgumentParser, *, several: bool) -> None:
    """Add ``--terrains`` (``several``) or ``--terrain``, and the granular media's options."""
    names = ", ".join(TERRAIN_NAMES)
    if several:
        parser.add_argument(
            "--terrains",
            default=",".join(TERRAIN_NAMES),
            metavar="NAME[,NAME...]",
            help=f"the terrains to run, comma-separated, of {names}",
        )
    else:
        parser.add_argument(
            "--terrain", default="mud", metavar="NAME", help=f"the terrain: {names}"
        )
    media = {
        "--zeta": "granular-rft: scale of the medium [N/m^3], the vertical stress per depth of a "
        "horizontal plate (Li et al. print N/cm^3: 0.254 N/cm^3 is 2.54e5; default: loosely "
        "packed poppy seeds, 2.54e5)",
        "--rho-c": "granular-rft3d: bulk density of the medium [kg/m^3] (default: 1310)",
        "--mu-int": "granular-rft3d: internal friction coefficient [-], not an angle (default: 0.21)",
        "--mu-surf": "granular-rft3d: foot-surface friction coefficient [-], not an angle "
        "(default: 0.4)",
    }
    for option, text in media.items():
        parser.add_argument(option, type=float, help=text)


def terrain_names(args: argparse.Namespace, value: str, option: str) -> list[str]:
    """The names in ``value`` (comma-separated for ``--terrains``), checked with the media
    options."""
    names = [n.strip() for n in str(value).split(",") if n.strip()]
    if not names or any(n not in TERRAIN_NAMES for n in names):
        many = " one or more of" if option == "--terrains" else " one of"
        sep = " (comma-separated)" if option == "--terrains" else ""
        raise MudrftError(
            f"{option} must name{many} {', '.join(TERRAIN_NAMES)}{sep}, got {value!r}"
        )
    if option != "--terrains" and len(names) > 1:
        raise MudrftError(f"{option} must name one terrain, got {value!r}")
    if len(set(names)) != len(names):
        raise MudrftError(f"{option} must name each terrain once, got {value!r}")
    for opt, v in _media(args).items():
        if v is None:
            continue
        owner, unit = MEDIUM_OPTIONS[opt]
        check_positive_option(opt, v, unit=unit, ge=opt == "--mu-surf")  # 0: frictionless
        if owner not in names:
            raise MudrftError(f"{opt} describes {owner}, which {option} leaves out")
    return names


def terrains_from_options(args: argparse.Namespace, mud: Mud) -> dict[str, Terrain]:
    """The terrains of ``--terrains`` by name: ``mud`` as the mud model, the baselines as
    :func:`baseline_from_options` makes them."""
    from ..terrains import MudTerrain

    names = terrain_names(args, args.terrains, "--terrains")
    return {n: MudTerrain(mud) if n == "mud" else baseline_from_options(args, n) for n in names}


def baseline_from_options(args: argparse.Namespace, name: str) -> Terrain:
    """The baseline terrain ``name`` with the media options given for it as its keywords,
    its defaults otherwise (D59)."""
    from ..terrains import GranularRFT, GranularRFT3D, LinearStiffness, MaxwellMud, RigidGround

    kw: dict[str, Any] = {
        o[2:].replace("-", "_"): float(v)
        for o, v in _media(args).items()
        if v is not None and MEDIUM_OPTIONS[o][0] == name
    }
    baselines = (GranularRFT, GranularRFT3D, LinearStiffness, MaxwellMud, RigidGround)
    return next(b for b in baselines if b.name == name)(**kw)


def _media(args: argparse.Namespace) -> dict[str, float | None]:
    """The media options as given (None where left out)."""
    return {o: getattr(args, o[2:].replace("-", "_")) for o in MEDIUM_OPTIONS}
