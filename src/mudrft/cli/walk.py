"""``mudrft walk``: a planar biped walking in mud (MuJoCo), written to one directory."""

from __future__ import annotations

import argparse
import math
import os
import time
from typing import TYPE_CHECKING, Any

from .._progress import Progress
from .._validation import MudrftError
from ..io.atomic import json_text
from ._common import Outputs, check_positive_option, logger, require_extra
from ._parser import add_foot_options, add_run_options, add_subcommand
from ._terrain import add_mud_options, mud_from_options

if TYPE_CHECKING:
    from ..parameters import Mud

#: The files ``mudrft walk`` may write in its directory.
FILES = ("walk.csv", "steps.csv", "summary.json", "walk.png", "frames.png")
#: The files ``mudrft walk --compare`` writes in its directory.
COMPARE_FILES = ("compare.csv", "claims.csv", "compare.json", "compare.png")


def add_parser(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    p = add_subcommand(
        subparsers,
        "walk",
        run,
        help="a planar biped walking in mud (MuJoCo): walk.csv, summary.json, walk.png",
        description="Walk a 10 kg planar biped in mud with the chosen foot and write "
        "DIR/walk.csv (per physics step), DIR/steps.csv (per gait step), DIR/summary.json "
        "(fell, distance, energy per step, mean sinking, max suction, ...), DIR/walk.png and, "
        "when offscreen rendering works, DIR/frames.png. Needs MuJoCo: pip install "
        "'mudrft[mujoco]'.",
    )
    add_foot_options(p, default="flat")
    add_mud_options(p)
    p.add_argument("--seconds", type=float, default=10.0, help="simulated time [s]")
    p.add_argument("--out", required=True, help="output directory DIR")
    p.add_argument("--dt", type=float, default=1e-3, help="physics time step [s]")
    p.add_argument("--speed", type=float, default=0.1, help="walking speed command [m/s]")
    p.add_argument("--step-time", type=float, default=1.0, help="duration of a step [s]")
    p.add_argument(
        "--bottom", type=float, default=0.15, help="depth of the rigid bed under the mud [m]"
    )
    p.add_argument(
        "--explicit", action="store_true", help="removed in 0.3 (the coupling is always implicit)"
    )
    p.add_argument(
        "--extrapolate", action="store_true", help="allow water contents outside 0.25-0.45"
    )
    p.add_argument("--no-render", action="store_true", help="skip the rendered image strip")
    p.add_argument(
        "--compare",
        action="store_true",
        help="walk every foot (flat, semi-cylinder, semi-sphere, morphing) on the same mud and "
        "write DIR/compare.csv, DIR/claims.csv (the paper's claims beside the results), "
        "DIR/compare.json and DIR/compare.png (--foot is ignored)",
    )
    add_run_options(
        p,
        force="existing results in DIR",
        strict="a foot sunk deeper than its height, ...",
        refuses="a foot sunk deeper than its own height",
    )


def run(args: argparse.Namespace) -> int:
    """Walk the biped and write ``DIR``."""
    os.environ.setdefault("MUJOCO_GL", "egl")  # headless rendering where available

    if args.explicit:
        raise MudrftError(
            "--explicit was removed in mudrft 0.3: the walk's coupling always takes the "
            "implicit step of the mud's damping; drop the flag"
        )
    seconds = check_positive_option("--seconds", args.seconds, unit="s")
    dt = check_positive_option("--dt", args.dt, unit="s")
    step_time = check_positive_option("--step-time", args.step_time, unit="s")
    bottom = check_positive_option("--bottom", args.bottom, unit="m")
    speed = check_positive_option("--speed", args.speed, unit="m/s", ge=True)
    require_extra("mujoco", needed_for="mudrft walk")
    require_extra("matplotlib", needed_for="mudrft walk (walk.png)")
    from ..feet import by_name
    from ..integrations import walk as W

    if dt > W.MAX_DT:
        raise MudrftError(f"--dt must be <= {W.MAX_DT} s for the biped, got {dt:g}")
    if step_time < W.MIN_STEP_SAMPLES * dt:
        raise MudrftError(
            f"--step-time must span at least {W.MIN_STEP_SAMPLES} time steps (>= "
            f"{W.MIN_STEP_SAMPLES * dt:g} s at --dt {dt:g}), got {step_time:g}"
        )

    mud = mud_from_options(args)
    options: dict[str, Any] = {"seconds": seconds, "dt": dt, "speed": speed, "step_time": step_time}
    options["bottom"] = bottom
    if args.compare:
        return _compare(args, mud, **options)
    foot = by_name(args.foot, unit=args.unit, trailing=args.trailing, up=args.up)
    with Outputs(force=args.force) as outputs:
        stage = outputs.directory("--out", args.out, FILES)
        logger.info("mudrft walk: %s feet, %s, %g s at dt = %g s", foot.name, mud.name, seconds, dt)
        t0 = time.perf_counter()
        progress = None if args.quiet else Progress("walking")
        frames, strict = (0 if args.no_render else 6), getattr(args, "strict", False)
        res = W.walk(foot, mud, **options, frames=frames, progress=progress, strict=strict)
        s = res.summary
        s["water_content"] = float(args.water_content)
        s["mud"] = mud.name
        s["wall_time [s]"] = round(time.perf_counter() - t0, 3)
        W._write_csv(stage / "walk.csv", res.table, W.WALK_COLUMNS)
        W._write_csv(stage / "steps.csv", res.steps, W.STEP_COLUMNS)
        W.plot_walk(res, stage / "walk.png")
        strip = W.save_strip(res.frames, stage / "frames.png")
        s["frames"] = strip.name if strip is not None else None
        (stage / "summary.json").write_text(json_text(s))
    _warn_if_no_step({foot.name: s}, seconds, step_time)
    print(
        f"{'FELL' if s['fell'] else 'walked'} {s['distance [m]']:.3f} m in {s['seconds']:.2f} s; "
        f"{_num(s['energy_per_step [J]'], '.3f')} J/step; "
        f"sinking {_num(1e3 * s['mean_sinking [m]'], '.1f')} mm; "
        f"max suction {s['max_suction [N]']:.2f} N"
    )
    for path in outputs.written:
        print(f"wrote {path}")
    return 0


def _compare(args: argparse.Namespace, mud: Mud, **options: Any) -> int:
    """``mudrft walk --compare``: every foot on the same mud, a table and a figure."""
    from ..integrations.walk_compare import compare_feet, write_compare

    with Outputs(force=args.force) as outputs:
        stage = outputs.directory("--out", args.out, COMPARE_FILES)
        what = f"{options['seconds']:g} s at dt = {options['dt']:g} s"
        logger.info("mudrft walk --compare: %s, %s", mud.name, what)
        summaries = compare_feet(
            mud,
            progress=None if args.quiet else (lambda name: Progress(f"walking ({name})")(0.0)),
            **options,
        )
        write_compare(stage, summaries, mud_name=f"({mud.name})")
    _warn_if_no_step(summaries, options["seconds"], options["step_time"])
    for foot, s in summaries.items():
        print(
            f"{foot}: {'FELL, ' if s['fell'] else ''}"
            f"{_num(s['energy_per_step [J]'], '.2f')} J/step, "
            f"sinking {_num(1e3 * s['mean_sinking [m]'], '.1f')} mm, "
            f"suction {s['max_suction [N]']:.0f} N"
        )
    for path in outputs.written:
        print(f"wrote {path}")
    return 0


def _num(value: float, fmt: str) -> str:
    """A number for the console; an undefined one (NaN) as ``n/a``."""
    return format(value, fmt) if math.isfinite(value) else "n/a"


def _warn_if_no_step(summaries: dict[str, dict[str, Any]], seconds: float, step: float) -> None:
    """Say so when a walk had no complete gait step: its per-step metrics are undefined."""
    short = [foot for foot, s in summaries.items() if s["steps"] == 0]
    if short:
        logger.warning(
            "%s: no complete gait step in %g s (a step takes %g s); the per-step energy, "
            "sinking and slip are undefined (null in the JSON, 'undetermined' in claims.csv): "
            "walk longer (--seconds)",
            ", ".join(short),
            seconds,
            step,
        )
