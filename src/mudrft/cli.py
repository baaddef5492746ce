"""The ``mudrft`` command: a thin layer over the library.

``mudrft --help`` lists the subcommands. Every error that comes from a user mistake
is printed as one line (``mudrft: error: ...``) with exit status 2, no traceback.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence
from pathlib import Path

from ._validation import MudrftError

__all__ = ["build_parser", "main"]

# subcommands that live next to the code they drive: (module, description)
_HOOKS = {
    "calibrate": "mudrft.calibration.cli",
    "compare": "mudrft.baselines.cli",
    "walk": "mudrft.integrations.walk",
    "bench": "mudrft.bench",
}


def _cmd_params(args: argparse.Namespace) -> int:
    from .parameters import DIRECTIONS, PARAMETER_UNITS, sigma_y_consistency, table_rows
    from .parameters.chen2026 import TABLE_NAME

    names = list(PARAMETER_UNITS)[:10]
    for d in DIRECTIONS:
        print(f"Chen et al. 2026, {TABLE_NAME[d]} -- SI units")
        head = ["W"] + [f"{n} [{PARAMETER_UNITS[n]}]" for n in names]
        print("  " + "  ".join(f"{h:>14s}" for h in head))
        checks = {c["water_content"]: c for c in sigma_y_consistency(d)}
        for w, row in table_rows(d).items():
            vals = [f"{w * 100:>13g}%"] + [f"{row[n]:>14.6g}" for n in names]
            flag = (
                ""
                if checks[w]["consistent"]
                else (
                    f"   (sigma_y violates (eta_m-eta_inf)*gamma_dot_c = {checks[w]['sigma_y_relation']:.4g} Pa)"
                )
            )
            print("  " + "  ".join(vals) + flag)
        print()
    print("Between rows the sets are interpolated (log-linear); see docs/model.md, decision D7.")
    print("nu = 0.01 1/s and k_a = 1/lam are model choices (decisions D5, D8), not table values.")
    return 0


def _cmd_simulate(args: argparse.Namespace) -> int:
    from .feet import by_name
    from .parameters import paper_mud
    from .simulation import simulate
    from .trajectories import gait

    out = Path(args.out)
    if out.exists() and not args.force:
        raise MudrftError(f"--out {str(out)!r} exists; pass --force to overwrite it")
    foot = by_name(args.foot)
    mud = paper_mud(args.water_content, extrapolate=args.extrapolate)
    if args.speed <= 0:
        raise MudrftError(f"--speed must be > 0 m/s, got {args.speed!r}")
    print(
        f"simulating {foot.name} foot, W = {args.water_content * 100:g} %, {args.speed:g} m/s",
        file=sys.stderr,
    )
    res = simulate(foot, mud, gait(args.speed, depth=args.depth, dt=args.dt), progress=True)
    res.to_csv(out, overwrite=args.force)
    m = res.metrics()
    print(f"wrote {out}")
    for k, v in m.items():
        print(f"  {k:14s} {v: .6g}")
    if args.plot:
        fig = res.plot()
        fig.savefig(args.plot, dpi=120)
        print(f"wrote {args.plot}")
    return 0


def _cmd_reproduce(args: argparse.Namespace) -> int:
    from .reproduce import reproduce

    reproduce(args.out, force=args.force, figures=not args.no_figures, quiet=args.quiet)
    print(f"results in {args.out}: summary.csv, report.md and figures")
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``mudrft`` command."""
    from . import __version__

    p = argparse.ArgumentParser(
        prog="mudrft", description="Forces of mud on robot feet (Chen et al. 2026 model)."
    )
    p.add_argument("--version", action="version", version=f"mudrft {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")

    sp = sub.add_parser("params", help="list the built-in parameter sets")
    sp.set_defaults(func=_cmd_params)

    sp = sub.add_parser("simulate", help="one stepping cycle of a foot in mud -> run.csv")
    sp.add_argument(
        "--foot",
        required=True,
        help="flat, semi-cylinder, semi-sphere, morphing, or a mesh file (.stl/.obj/.ply)",
    )
    sp.add_argument(
        "--water-content",
        type=float,
        default=0.25,
        help="volume fraction, 0.25-0.45 (default 0.25)",
    )
    sp.add_argument("--speed", type=float, default=0.2, help="gait speed [m/s] (default 0.2)")
    sp.add_argument(
        "--depth", type=float, default=0.03, help="deepest tip depth [m] (default 0.03)"
    )
    sp.add_argument("--dt", type=float, default=1e-3, help="time step [s] (default 1e-3)")
    sp.add_argument(
        "--out", required=True, help="output CSV (time [s],x [m],y [m],z [m],Fx [N],Fy [N],Fz [N])"
    )
    sp.add_argument("--plot", help="also write a PNG figure here")
    sp.add_argument(
        "--extrapolate", action="store_true", help="allow water content outside 0.25-0.45 (warns)"
    )
    sp.add_argument("--force", action="store_true", help="overwrite --out if it exists")
    sp.set_defaults(func=_cmd_simulate)

    sp = sub.add_parser(
        "reproduce", help="the paper's comparisons: summary.csv, figures, report.md"
    )
    sp.add_argument(
        "--out", default="mudrft-results", help="output directory (default ./mudrft-results)"
    )
    sp.add_argument("--force", action="store_true", help="overwrite existing results")
    sp.add_argument("--no-figures", action="store_true", help="skip the PNG figures")
    sp.add_argument("--quiet", action="store_true", help="no progress output")
    sp.set_defaults(func=_cmd_reproduce)

    for _name, modname in _HOOKS.items():
        try:
            mod = importlib.import_module(modname)
        except ImportError:
            continue
        if hasattr(mod, "add_parser"):
            mod.add_parser(sub)
    return p


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``mudrft`` command; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "command", None):
        parser.print_help()
        return 0
    try:
        return int(args.func(args) or 0)
    except MudrftError as exc:
        print(f"mudrft: error: {exc}", file=sys.stderr)
        return 2
    except FileNotFoundError as exc:
        print(f"mudrft: error: {exc.filename or exc}: no such file", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # pragma: no cover
        print("mudrft: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
