"""``mudrft compare``: the mud model against the baseline terrains (Figs. S5, S6).

Runs the vertical plate test (``mudrft.plate_intrusion``) and one gait cycle
(``mudrft.gait``) through the mud model and every baseline of :mod:`mudrft.baselines`,
and writes ``DIR/compare.csv`` (long format, ``mudrft.baselines.CSV_COLUMNS``),
``DIR/compare_summary.csv`` (peak support, suction, impulses, energy per run) and the
figures ``DIR/compare_s6.png`` and ``DIR/compare_gait.png``.
"""

from __future__ import annotations

import argparse
import csv
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

from .._validation import MudrftError
from ._common import (
    Outputs,
    check_finite_option,
    check_nonnegative_option,
    check_positive_option,
    require_extra,
    save_figure,
)
from ._mud import add_fit_options, mud_from_options
from ._parser import (
    GAIT_SPEED,
    STANCE_DEPTH,
    add_foot_options,
    add_force,
    add_quiet,
    add_strict,
    add_subcommand,
)
from ._terrain import add_terrain_options, terrains_from_options

if TYPE_CHECKING:
    from ..feet import Foot
    from ..parameters import Mud
    from ..terrains import Terrain

__all__ = ["FILES", "add_parser", "run", "write_comparison"]

DESCRIPTION = (
    "Run the vertical plate test and one gait cycle through the mud model and the baseline "
    "terrains (granular RFT, linear stiffness, Maxwell-type mud, rigid ground), and write "
    "DIR/compare.csv (every sample, long format), DIR/compare_summary.csv (peak support, "
    "suction, impulses and energy per run) and the figures DIR/compare_s6.png and "
    "DIR/compare_gait.png (as in the paper's Figs. S5 and S6). --vertical/--horizontal "
    "FIT.json put calibrated sets in the mud model; --terrains picks the terrains, and "
    "--zeta, --rho-c, --mu-int, --mu-surf describe your own granular medium (the other "
    "baselines keep their defaults)."
)

#: The files ``mudrft compare`` writes in its directory: key -> (name, is a figure).
FILES = {
    "csv": ("compare.csv", False),
    "summary": ("compare_summary.csv", False),
    "s6": ("compare_s6.png", True),
    "gait": ("compare_gait.png", True),
}


def add_parser(
    subparsers: argparse._SubParsersAction[argparse.ArgumentParser],
) -> argparse.ArgumentParser:
    """Add ``mudrft compare`` to an argparse subparsers object."""
    p = add_subcommand(
        subparsers,
        "compare",
        help="mud model vs granular RFT, linear, Maxwell-type and rigid ground -> DIR/compare.csv",
        description=DESCRIPTION,
    )
    add_foot_options(p, default="flat")
    p.add_argument("--out", default="mudrft-compare", help="output directory DIR")
    p.add_argument("--water-content", type=float, default=0.25, help="mud water content W [-]")
    add_fit_options(p)
    p.add_argument("--speed", type=float, default=GAIT_SPEED, help="gait speed [m/s]")
    p.add_argument(
        "--depth",
        type=float,
        default=STANCE_DEPTH,
        help="intrusion depth [m] of both runs (the gait's stance, as mudrft simulate's)",
    )
    p.add_argument("--hold", type=float, default=1.0, help="hold time [s] of the plate test")
    add_terrain_options(p, several=True)
    p.add_argument(
        "--extrapolate", action="store_true", help="allow water content outside 0.25-0.45 (warns)"
    )
    p.add_argument("--no-figures", action="store_true", help="skip the PNG figures")
    add_force(p, "existing results in DIR")
    add_quiet(p)
    add_strict(
        p,
        "an extrapolated water content, a unit that looks wrong, ...",
        refuses="a foot pushed deeper than its own height",
    )
    p.set_defaults(func=run)
    return p


def write_comparison(
    foot: Foot,
    out: str | Path,
    *,
    water_content: float = 0.25,
    speed: float = GAIT_SPEED,
    depth: float = STANCE_DEPTH,
    hold: float = 1.0,
    figures: bool = True,
    force: bool = False,
    quiet: bool = False,
    extrapolate: bool = False,
    mud: Mud | None = None,
    terrains: Mapping[str, Terrain] | None = None,
    strict: bool = False,
) -> dict[str, Path]:
    """Run and write what ``mudrft compare`` writes; all files or none.

    Parameters
    ----------
    foot : Foot
        The foot.
    out : str or Path
        Output directory (created, with its parents, if missing).
    water_content : float, keyword-only
        Mud water content [-].
    speed : float, keyword-only
        Gait speed [m/s].
    depth : float, keyword-only
        Plate intrusion depth and deepest gait depth [m] (default: the gait's stance,
        ``mudrft.trajectories.STANCE_DEPTH``, as ``mudrft simulate`` and ``mudrft.gait``).
    hold : float, keyword-only
        Hold time of the plate test [s].
    figures : bool, keyword-only
        Write the PNG figures (needs matplotlib).
    force : bool, keyword-only
        Overwrite existing files.
    quiet : bool, keyword-only
        No progress lines on stderr.
    extrapolate : bool, keyword-only
        Allow a water content outside the tabulated rows (warns).
    mud : Mud, optional, keyword-only
        The mud model's parameters in place of the paper's at ``water_content`` (a
        calibrated mud); the baselines keep their defaults (D59).
    terrains : mapping of str to Terrain, optional, keyword-only
        The terrains to run, by name (default: every one of
        :func:`~mudrft.baselines.default_terrains`, ``mud`` replaced by ``mud`` if given).
    strict : bool, keyword-only
        Refuse a depth deeper than the foot is tall (a :class:`~mudrft.MudrftError`
        before anything runs) instead of warning.

    Returns
    -------
    dict of str to Path
        The paths written, by key of :data:`FILES`.
    """
    from ..baselines.compare import compare, default_terrains, summarize, write_csv
    from ..terrains import MudTerrain
    from ..trajectories import gait, plate_intrusion

    if terrains is None:
        terrains = default_terrains(water_content, extrapolate=extrapolate)
        if mud is not None:
            terrains["mud"] = MudTerrain(mud)
    keys = [k for k, (_, is_figure) in FILES.items() if figures or not is_figure]
    with Outputs(force=force) as outputs:
        stage = outputs.directory("--out", out, [FILES[k][0] for k in keys])
        runs = {
            "plate": compare(
                foot,
                plate_intrusion(depth=depth, hold=hold),
                terrains,
                progress=not quiet,
                strict=strict,
            ),
            "gait": compare(
                foot,
                gait(speed, depth=depth),
                terrains,
                progress=not quiet,
                strict=strict,
            ),
        }
        write_csv(runs, stage / FILES["csv"][0], overwrite=True)
        rows = [{"trajectory": k, **r} for k, h in runs.items() for r in summarize(h)]
        with (stage / FILES["summary"][0]).open("w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(rows[0]))
            w.writeheader()
            for r in rows:
                w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
        if figures:
            from ..baselines.plots import plot_gait, plot_s6
            from ..plotting import require_matplotlib

            require_matplotlib()  # the Agg backend, before the first figure
            title = f"{foot.name} foot, one gait cycle at {speed:g} m/s"
            makers = {
                "s6": lambda: plot_s6(runs["plate"]),
                # rigid ground's penalty spring dwarfs the others: left out unless alone
                "gait": lambda: plot_gait(
                    runs["gait"], title=title, exclude=("rigid",) if len(terrains) > 1 else ()
                ),
            }
            for key, make in makers.items():
                save_figure(make(), stage / FILES[key][0])
    return {k: Path(out) / FILES[k][0] for k in keys}


def run(args: argparse.Namespace) -> int:
    """Run ``mudrft compare`` with parsed arguments; returns the exit status (0)."""
    from ..feet import by_name

    speed = check_positive_option("--speed", args.speed, unit="m/s")
    depth = check_positive_option("--depth", args.depth, unit="m")
    if depth > 1.0:  # 30 (mm) ran a 3 million-sample plate test for hours
        raise MudrftError(
            f"--depth must be at most 1 m (it is in metres: 30 mm is 0.03), got {depth:g} m"
        )
    hold = check_nonnegative_option("--hold", args.hold, unit="s")
    water_content = check_finite_option("--water-content", args.water_content)
    with warnings.catch_warnings():  # refuse before any work; the run itself warns
        warnings.simplefilter("ignore")
        mud = mud_from_options(args)
    figures = not args.no_figures
    if figures:
        require_extra(
            "matplotlib", needed_for="the figures of mudrft compare", unless="--no-figures"
        )
    terrains = terrains_from_options(
        args, args.terrains, "--terrains", water_content=water_content, mud=mud
    )
    foot = by_name(args.foot, unit=args.unit, trailing=args.trailing, up=args.up)
    paths = write_comparison(
        foot,
        args.out,
        water_content=water_content,
        speed=speed,
        depth=depth,
        hold=hold,
        figures=figures,
        force=args.force,
        quiet=args.quiet,
        extrapolate=args.extrapolate,
        mud=mud,
        terrains=terrains,
        strict=args.strict,
    )
    for p in paths.values():
        print(f"wrote {p}")
    return 0
