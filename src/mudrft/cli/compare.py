"""``mudrft compare``: the mud model against the baseline terrains (Figs. S5, S6)."""

from __future__ import annotations

import argparse
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

from .._validation import MudrftError
from ._common import Outputs, check_positive_option, require_extra, save_figure
from ._parser import GAIT_SPEED, STANCE_DEPTH, add_foot_options, add_run_options, add_subcommand
from ._terrain import add_mud_options, add_terrain_options, mud_from_options, terrains_from_options

if TYPE_CHECKING:
    from ..feet import Foot
    from ..terrains import Terrain

#: The files ``mudrft compare`` writes in its directory: key -> (name, is a figure).
FILES = {
    "csv": ("compare.csv", False),
    "summary": ("compare_summary.csv", False),
    "s6": ("compare_s6.png", True),
    "gait": ("compare_gait.png", True),
}


def add_parser(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    p = add_subcommand(
        subparsers,
        "compare",
        run,
        help="mud model vs granular RFT, linear, Maxwell-type and rigid ground -> DIR/compare.csv",
        description="Run the vertical plate test and one gait cycle through the mud model and "
        "the baseline terrains (granular RFT, linear stiffness, Maxwell-type mud, rigid "
        "ground), and write DIR/compare.csv (every sample, long format), "
        "DIR/compare_summary.csv (peak support, suction, impulses and energy per run) and the "
        "figures DIR/compare_s6.png and DIR/compare_gait.png (as in the paper's Figs. S5 and "
        "S6). --vertical/--horizontal FIT.json put calibrated sets in the mud model; "
        "--terrains picks the terrains, and --zeta, --rho-c, --mu-int, --mu-surf describe your "
        "own granular medium (the other baselines keep their defaults).",
    )
    add_foot_options(p, default="flat")
    p.add_argument("--out", default="mudrft-compare", help="output directory DIR")
    add_mud_options(p, water="mud water content W [-]")
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
    add_run_options(
        p,
        force="existing results in DIR",
        strict="an extrapolated water content, a unit that looks wrong, ...",
        refuses="a foot pushed deeper than its own height",
    )


def write_comparison(
    foot: Foot,
    out: str | Path,
    *,
    speed: float = GAIT_SPEED,
    depth: float = STANCE_DEPTH,
    hold: float = 1.0,
    figures: bool = True,
    force: bool = False,
    quiet: bool = False,
    terrains: Mapping[str, Terrain] | None = None,
    strict: bool = False,
) -> dict[str, Path]:
    """Run and write what ``mudrft compare`` writes in ``out`` (created with its parents if
    missing), all files or none: the plate test to ``depth`` [m] held ``hold`` [s] and one
    gait cycle at ``speed`` [m/s] to the same ``depth``, of ``foot`` through ``terrains`` by
    name (default: :func:`~mudrft.baselines.default_terrains`). ``figures``: also the PNG
    figures; ``force``: overwrite existing files; ``quiet``: no progress lines; ``strict``:
    refuse a depth deeper than the foot is tall. Returns the paths written, by key of
    :data:`FILES`."""
    from ..baselines.compare import compare, default_terrains, summarize, write_csv
    from ..reproduce.runner import write_rows
    from ..trajectories import gait, plate_intrusion

    terrains = default_terrains() if terrains is None else terrains
    keys = [k for k, (_, is_figure) in FILES.items() if figures or not is_figure]
    with Outputs(force=force) as outputs:
        stage = outputs.directory("--out", out, [FILES[k][0] for k in keys])
        paths = {"plate": plate_intrusion(depth=depth, hold=hold), "gait": gait(speed, depth=depth)}
        runs = {
            k: compare(foot, path, terrains, progress=not quiet, strict=strict)
            for k, path in paths.items()
        }
        write_csv(runs, stage / FILES["csv"][0], overwrite=True)
        rows = [{"trajectory": k, **r} for k, h in runs.items() for r in summarize(h)]
        write_rows(stage / FILES["summary"][0], rows, list(rows[0]))
        if figures:
            from ..baselines.plots import plot_gait, plot_s6
            from ..plotting import require_matplotlib

            require_matplotlib()  # the Agg backend, before the first figure
            title = f"{foot.name} foot, one gait cycle at {speed:g} m/s"
            save_figure(plot_s6(runs["plate"]), stage / FILES["s6"][0])
            # rigid ground's penalty spring dwarfs the others: left out unless alone
            rigid = ("rigid",) if len(terrains) > 1 else ()
            fig = plot_gait(runs["gait"], title=title, exclude=rigid)
            save_figure(fig, stage / FILES["gait"][0])
    return {k: Path(out) / FILES[k][0] for k in keys}


def run(args: argparse.Namespace) -> int:
    """Run ``mudrft compare`` with parsed arguments."""
    from ..feet import by_name

    speed = check_positive_option("--speed", args.speed, unit="m/s")
    depth = check_positive_option("--depth", args.depth, unit="m")
    if depth > 1.0:  # 30 (mm) ran a 3 million-sample plate test for hours
        raise MudrftError(
            f"--depth must be at most 1 m (it is in metres: 30 mm is 0.03), got {depth:g} m"
        )
    hold = check_positive_option("--hold", args.hold, unit="s", ge=True)
    with warnings.catch_warnings():  # refuse before any work; the run itself warns
        warnings.simplefilter("ignore")
        mud = mud_from_options(args)
    if not args.no_figures:
        require_extra(
            "matplotlib", needed_for="the figures of mudrft compare", unless="--no-figures"
        )
    terrains = terrains_from_options(args, mud)
    foot = by_name(args.foot, unit=args.unit, trailing=args.trailing, up=args.up)
    paths = write_comparison(
        foot,
        args.out,
        speed=speed,
        depth=depth,
        hold=hold,
        figures=not args.no_figures,
        force=args.force,
        quiet=args.quiet,
        terrains=terrains,
        strict=args.strict,
    )
    for p in paths.values():
        print(f"wrote {p}")
    return 0
