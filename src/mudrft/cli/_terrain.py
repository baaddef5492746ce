"""Command-line options that choose terrains and describe a granular medium.

``mudrft compare --terrains NAME,...`` and ``mudrft simulate --terrain NAME`` take the names
of :data:`mudrft.baselines.TERRAIN_NAMES`; ``--zeta`` describes granular RFT's medium and
``--rho-c``, ``--mu-int``, ``--mu-surf`` 3D-RFT's. The other baselines keep their defaults.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from .._validation import MudrftError
from ._common import check_nonnegative_option, check_positive_option

if TYPE_CHECKING:
    from ..parameters import Mud
    from ..terrains import Terrain

__all__ = ["TERRAIN_NAMES", "add_terrain_options", "terrain_names", "terrains_from_options"]

#: ``mudrft.baselines.TERRAIN_NAMES``, written here so that ``--help`` needs no physics
#: (a test holds the two equal).
TERRAIN_NAMES = ("mud", "granular-rft", "granular-rft3d", "linear", "maxwell", "rigid")

#: Option -> (terrain it describes, unit for messages).
MEDIUM_OPTIONS = {
    "--zeta": ("granular-rft", "N/m^3"),
    "--rho-c": ("granular-rft3d", "kg/m^3"),
    "--mu-int": ("granular-rft3d", ""),
    "--mu-surf": ("granular-rft3d", ""),
}


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
            "--terrain",
            default="mud",
            metavar="NAME",
            help=f"the terrain: {names}",
        )
    parser.add_argument(
        "--zeta",
        type=float,
        default=None,
        help="granular-rft: scale of the medium [N/m^3], the vertical stress per depth of a "
        "horizontal plate (Li et al. print N/cm^3: 0.254 N/cm^3 is 2.54e5; default: loosely "
        "packed poppy seeds, 2.54e5)",
    )
    parser.add_argument(
        "--rho-c",
        type=float,
        default=None,
        help="granular-rft3d: bulk density of the medium [kg/m^3] (default: 1310)",
    )
    parser.add_argument(
        "--mu-int",
        type=float,
        default=None,
        help="granular-rft3d: internal friction coefficient [-], not an angle (default: 0.21)",
    )
    parser.add_argument(
        "--mu-surf",
        type=float,
        default=None,
        help="granular-rft3d: foot-surface friction coefficient [-], not an angle (default: 0.4)",
    )


def terrain_names(args: argparse.Namespace, value: str, option: str) -> list[str]:
    """Check the names in ``value`` (comma-separated for ``--terrains``) and the media
    options; returns the names."""
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
        if opt == "--mu-surf":  # 0: a frictionless foot
            check_nonnegative_option(opt, v)
        else:
            check_positive_option(opt, v, unit=unit)
        if owner not in names:
            raise MudrftError(f"{opt} describes {owner}, which {option} leaves out")
    return names


def terrains_from_options(
    args: argparse.Namespace,
    value: str,
    option: str,
    *,
    water_content: float,
    mud: Mud | None,
) -> dict[str, Terrain]:
    """The terrains named in ``value`` (:func:`terrain_names`), by name, with the media
    options; the other baselines with their defaults (D59)."""
    from ..parameters import paper_mud
    from ..terrains import (
        GranularRFT,
        GranularRFT3D,
        LinearStiffness,
        MaxwellMud,
        MudTerrain,
        RigidGround,
    )

    names = terrain_names(args, value, option)
    given = _media(args)
    extrapolate = bool(getattr(args, "extrapolate", False))
    out: dict[str, Terrain] = {}
    for name in names:
        if name == "mud":
            out[name] = MudTerrain(
                mud if mud is not None else paper_mud(water_content, extrapolate=extrapolate)
            )
        elif name == "granular-rft" and given["--zeta"] is not None:
            out[name] = GranularRFT(zeta=float(given["--zeta"]))
        elif name == "granular-rft3d":
            d = GranularRFT3D
            out[name] = GranularRFT3D(
                rho_c=d.rho_c if given["--rho-c"] is None else float(given["--rho-c"]),
                mu_int=d.mu_int if given["--mu-int"] is None else float(given["--mu-int"]),
                mu_surf=d.mu_surf if given["--mu-surf"] is None else float(given["--mu-surf"]),
            )
        else:
            out[name] = {
                "granular-rft": GranularRFT,
                "linear": LinearStiffness,
                "maxwell": MaxwellMud,
                "rigid": RigidGround,
            }[name]()
    return out


def _media(args: argparse.Namespace) -> dict[str, float | None]:
    """The media options as given (None where left out)."""
    return {o: getattr(args, o[2:].replace("-", "_")) for o in MEDIUM_OPTIONS}
