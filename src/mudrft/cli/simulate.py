"""``mudrft simulate``: one stepping cycle (or a measured path, ``--path``) of a foot in mud, to CSV."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from .._validation import MudrftError
from ._common import (
    Outputs,
    check_positive_option,
    logger,
    require_plot_file,
    same_file,
    save_figure,
)
from ._parser import (
    GAIT_SPEED,
    STANCE_DEPTH,
    add_evaluation_options,
    add_foot_options,
    add_run_options,
    add_subcommand,
)
from ._terrain import (
    add_mud_options,
    add_terrain_options,
    baseline_from_options,
    mud_from_options,
    terrain_names,
)

if TYPE_CHECKING:
    from ..simulation import LoadControl, Result
    from ..terrains import Terrain
    from ..trajectories import Trajectory

#: ``--load``'s defaults: the time over which it rises [s] and the time simulated [s]
#: (a ramped load creeps to the static depth in 10-30 s, D13).
LOAD_RAMP = 1.0
LOAD_DURATION = 30.0


def add_parser(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    p = add_subcommand(
        subparsers,
        "simulate",
        run,
        help="one stepping cycle of a foot in mud -> run.csv",
        description="Run one stepping cycle (intrusion, stance, retraction; mudrft.gait), or a "
        "path of the foot's tip read from a CSV file (--path), of a foot through the paper's mud "
        "at the given water content (or a mud calibrated by mudrft calibrate: --vertical, "
        "--horizontal) and speed, and write the tip position and the force of the mud on the foot "
        "to a CSV file with the columns time [s],x [m],y [m],z [m],Fx [N],Fy [N],Fz [N]. Prints "
        "the cycle's metrics (peak support, suction, impulses, energy). --terrain runs a baseline "
        "instead of the mud (granular RFT with --zeta, 3D-RFT with --rho-c, --mu-int, --mu-surf, "
        "...). Which evaluation to use: the ODEs (the default) to design a foot or step a robot, "
        "--thixotropy quasi-static to reproduce the paper's numbers (mudrft reproduce); why, and "
        "what each gives: the user guide, docs/guide/evaluations.md.",
    )
    add_foot_options(p)
    add_mud_options(p)
    p.add_argument(
        "--path",
        metavar="PATH.csv",
        help="the foot tip's own path in place of the gait: a CSV file with 'time [s]' and "
        "'z [m]' (negative below the surface; or 'depth'), optionally 'x' and 'y', units in "
        "brackets (mudrft.io.load_path_csv; a --out file reads back as its path)",
    )
    p.add_argument(
        "--load",
        metavar="WEIGHT",
        type=float,
        help="press the foot into the mud with this weight [N] instead of moving it "
        "(mudrft.LoadControl; a rigid leg, the foot starting at the surface): the CSV holds "
        "the sinking, and the static sinking depth is printed beside the final one",
    )
    p.add_argument(
        "--ramp",
        type=float,
        help=f"--load only: time over which the weight rises from 0 [s] (default: {LOAD_RAMP}; "
        "0 drops it at once, and the foot overshoots, D13)",
    )
    p.add_argument(
        "--duration", type=float, help=f"--load only: simulated time [s] (default: {LOAD_DURATION})"
    )
    p.add_argument("--speed", type=float, help=f"gait speed [m/s] (default: {GAIT_SPEED})")
    p.add_argument(
        "--depth",
        type=float,
        help=f"deepest tip depth of the gait [m] (decision D10) (default: {STANCE_DEPTH})",
    )
    add_evaluation_options(
        p,
        what="step eqs. (3), (5), or the paper's quasi-static closed forms (9)-(11) (D15); "
        "which to use: docs/guide/evaluations.md",
    )
    p.add_argument(
        "--labels",
        choices=["table", "text"],
        default="table",
        help="water content as the tables label the rows (25/35/45 %%) or the text (15/25/35 %%)",
    )
    p.add_argument(
        "--dt", type=float, default=1e-3, help="time step [s] (a --path is resampled at it)"
    )
    add_terrain_options(p, several=False)
    p.add_argument(
        "--out", required=True, help="output CSV (time [s],x [m],y [m],z [m],Fx [N],Fy [N],Fz [N])"
    )
    p.add_argument("--plot", help="also write a PNG figure here (needs mudrft[plot])")
    p.add_argument(
        "--extrapolate", action="store_true", help="allow water content outside 0.25-0.45 (warns)"
    )
    add_run_options(
        p,
        force="--out and --plot if they exist",
        strict="an extrapolated water content, a unit that looks wrong, ...",
        refuses="a foot pushed deeper than its own height",
    )
    # the mud's own options and their defaults: given with a baseline they are refused
    mud = ("vertical", "horizontal", "thixotropy", "clock", "labels", "water_content")
    p.set_defaults(mud_defaults={d: p.get_default(d) for d in (*mud, "extrapolate")})


def run(args: argparse.Namespace) -> int:
    """Simulate, write ``--out`` (and ``--plot``), print the metrics."""
    from ..feet import by_name
    from ..simulation import LoadControl, simulate, static_sinking
    from ..terrains import MudTerrain
    from ..trajectories import Trajectory

    _check_motion_options(args)
    dt = check_positive_option("--dt", args.dt, unit="s")
    for option, path in (("--out", args.out), ("--plot", args.plot)):
        for other, given in (("--foot", args.foot), ("--path", args.path)):
            if path and given and same_file(path, given):
                raise MudrftError(f"{option} {path!r} is the {other} file; choose another name")
    if args.plot:
        require_plot_file("--plot", args.plot)

    foot = by_name(args.foot, unit=args.unit, trailing=args.trailing, up=args.up)
    terrain: Terrain
    (chosen,) = terrain_names(args, args.terrain, "--terrain")  # and the media options
    if chosen == "mud":
        terrain = MudTerrain(mud_from_options(args), thixotropy=args.thixotropy, clock=args.clock)
    else:  # a baseline: the mud's own options would be silently ignored
        for dest, default in args.mud_defaults.items():
            if getattr(args, dest) != default:
                option = "--" + dest.replace("_", "-")
                raise MudrftError(f"{option} describes the mud, but --terrain is {args.terrain!r}")
        terrain = baseline_from_options(args, chosen)
    motion, what = _motion(args, dt)  # checked before anything is written
    static = None  # the line on the static sinking depth, for a load on the mud
    if isinstance(motion, LoadControl) and isinstance(terrain, MudTerrain):
        try:
            depth = static_sinking(foot, terrain.mud, motion.weight)
            static = f"  {'static sinking':14s} {depth: .6g} m (relaxed mud, no suction; D13)"
        except MudrftError as exc:  # too heavy to balance: say why, run anyway
            static = f"  static sinking: {exc}"
    with Outputs(force=args.force) as outputs:
        csv_tmp = outputs.file("--out", args.out)
        plot_tmp = outputs.file("--plot", args.plot) if args.plot else None
        label = terrain.mud.name if isinstance(terrain, MudTerrain) else terrain.name
        logger.info("simulating %s foot, %s, %s", foot.name, label, what)
        res = simulate(
            foot,
            terrain,
            motion,
            dt=dt if args.path else None,
            progress=not args.quiet,
            strict=args.strict,
        )
        res.to_csv(csv_tmp, overwrite=True)
        if plot_tmp is not None:
            save_figure(res.plot(), plot_tmp)
    print(f"wrote {args.out}")
    from ..sweep.catalog import METRICS  # names and units only (no Dask, no xarray)

    kind = "load" if isinstance(motion, LoadControl) else "gait"
    for k, v in res.metrics().items():
        print(f"  {k:14s} {v: .6g} {METRICS[kind][k].unit}")
    if isinstance(motion, Trajectory):
        _print_against_measured(res, motion)
    if static is not None:
        print(static)
    if args.plot:
        print(f"wrote {args.plot}")
    return 0


def _check_motion_options(args: argparse.Namespace) -> None:
    """One motion: the gait (--speed, --depth), --path, or --load (--ramp, --duration)."""
    chosen = [o for o, v in (("--path", args.path), ("--load", args.load)) if v is not None]
    if len(chosen) == 2:
        raise MudrftError("--path moves the foot and --load presses it; give one or the other")
    gait_options = [
        o for o, v in (("--speed", args.speed), ("--depth", args.depth)) if v is not None
    ]
    if chosen and gait_options:
        raise MudrftError(
            f"{gait_options[0]} sets the gait, which {chosen[0]} replaces; give one or the other"
        )
    if args.load is None:
        for option, value in (("--ramp", args.ramp), ("--duration", args.duration)):
            if value is not None:
                raise MudrftError(f"{option} applies to --load only; give --load WEIGHT [N]")


def _motion(args: argparse.Namespace, dt: float) -> tuple[Trajectory | LoadControl, str]:
    """The motion the options ask for, and its description for the log."""
    from ..io import load_path_csv
    from ..simulation import LoadControl
    from ..trajectories import gait

    def option(name: str, default: float, unit: str, *, ge: bool = False) -> float:
        given = getattr(args, name)
        value = default if given is None else given
        return check_positive_option(f"--{name}", value, unit=unit, ge=ge)

    if args.path is not None:
        return load_path_csv(args.path), f"path {args.path}"
    if args.load is not None:
        weight = check_positive_option("--load", args.load, unit="N")
        ramp = option("ramp", LOAD_RAMP, "s", ge=True)
        duration = option("duration", LOAD_DURATION, "s")
        load = LoadControl(weight, duration=duration, dt=dt, ramp=ramp)
        return load, f"a load of {weight:g} N"
    speed = option("speed", GAIT_SPEED, "m/s")
    return gait(speed, depth=option("depth", STANCE_DEPTH, "m"), dt=dt), f"{speed:g} m/s gait"


def _print_against_measured(res: Result, path: Trajectory) -> None:
    """The relative RMSE [-] of each force the path's file measured (the paper's Table II),
    the prediction read at the file's own times."""
    import numpy as np

    from ..metrics import relative_rmse

    for name, measured in path.meta.get("measured_force", {}).items():
        axis = "xyz".index(name[1])
        predicted = np.interp(path.time, res.time, res.force[:, axis])
        try:
            error = f"{relative_rmse(predicted, measured): .6g} -"
        except MudrftError as exc:  # a constant column has no range to normalise by
            error = f" not defined: {exc}"
        print(f"  {'rel_rmse_' + name:14s} {error} (against the file's {name}; Table II)")
