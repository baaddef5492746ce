"""``mudrft compare``: the mud model against the baseline terrains (Figs. S5, S6).

Runs the vertical plate test (:func:`mudrft.plate_intrusion`) and one gait cycle
(:func:`mudrft.gait`) through the mud model and every baseline, and writes
``DIR/compare.csv`` (long format, :data:`mudrft.baselines.CSV_COLUMNS`),
``DIR/compare_summary.csv`` (peak support, suction, impulses, energy per run) and the
figures ``DIR/compare_s6.png`` and ``DIR/compare_gait.png``.
"""

from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path
from typing import Any

from .._validation import MudrftError

__all__ = ["add_parser", "main", "run"]


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    """Add the ``compare`` subcommand to an argparse subparsers object."""
    sp = subparsers.add_parser(
        "compare",
        help="mud model vs granular RFT, linear, Maxwell-type and rigid ground -> DIR/compare.csv",
        description=__doc__.split("\n\n")[1] if __doc__ else None,
    )
    sp.add_argument(
        "--foot",
        default="flat",
        help="flat, semi-cylinder, semi-sphere, morphing, or a mesh file (default flat)",
    )
    sp.add_argument(
        "--out", default="mudrft-compare", help="output directory (default ./mudrft-compare)"
    )
    sp.add_argument(
        "--water-content", type=float, default=0.25, help="mud water content (default 0.25)"
    )
    sp.add_argument("--speed", type=float, default=0.2, help="gait speed [m/s] (default 0.2)")
    sp.add_argument(
        "--depth", type=float, default=0.03, help="intrusion depth [m] of both runs (default 0.03)"
    )
    sp.add_argument(
        "--hold", type=float, default=1.0, help="hold time [s] of the plate test (default 1.0)"
    )
    sp.add_argument("--no-figures", action="store_true", help="skip the PNG figures")
    sp.add_argument("--force", action="store_true", help="overwrite existing results in DIR")
    sp.set_defaults(func=main)
    return sp


def run(
    foot: Any,
    out: str | Path,
    *,
    water_content: float = 0.25,
    speed: float = 0.2,
    depth: float = 0.03,
    hold: float = 1.0,
    figures: bool = True,
    force: bool = False,
    quiet: bool = False,
) -> dict[str, Path]:
    """Library form of ``mudrft compare``; returns the paths written.

    Parameters
    ----------
    foot : Foot
        The foot.
    out : str or Path
        Output directory (created).
    water_content : float, keyword-only
        Mud water content [-].
    speed : float, keyword-only
        Gait speed [m/s].
    depth : float, keyword-only
        Plate intrusion depth and deepest gait depth [m].
    hold : float, keyword-only
        Hold time of the plate test [s].
    figures : bool, keyword-only
        Write the PNG figures (needs matplotlib).
    force : bool, keyword-only
        Overwrite existing files.
    quiet : bool, keyword-only
        No progress lines on stderr.
    """
    from ..trajectories import gait, plate_intrusion
    from .compare import compare, summarize, write_csv

    d = Path(out)
    paths = {"csv": d / "compare.csv", "summary": d / "compare_summary.csv"}
    if figures:
        paths.update(s6=d / "compare_s6.png", gait=d / "compare_gait.png")
    existing = [str(p) for p in paths.values() if p.exists()]
    if existing and not force:
        raise MudrftError(
            f"{existing[0]!r} exists; pass --force to overwrite the results in {str(d)!r}"
        )
    d.mkdir(parents=True, exist_ok=True)
    runs = {
        "plate": compare(
            foot,
            plate_intrusion(depth=depth, hold=hold),
            water_content=water_content,
            progress=not quiet,
        ),
        "gait": compare(
            foot, gait(speed, depth=depth), water_content=water_content, progress=not quiet
        ),
    }
    write_csv(runs, paths["csv"], overwrite=True)
    with paths["summary"].open("w", newline="") as fh:
        rows = [{"trajectory": k, **r} for k, h in runs.items() for r in summarize(h)]
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    if figures:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from .plots import plot_gait, plot_s6

        fig = plot_s6(runs["plate"])
        fig.savefig(paths["s6"], dpi=120)
        plt.close(fig)
        fig = plot_gait(runs["gait"], title=f"{foot.name} foot, one gait cycle at {speed:g} m/s")
        fig.savefig(paths["gait"], dpi=120)
        plt.close(fig)
    return paths


def main(args: argparse.Namespace) -> int:
    """Run ``mudrft compare`` with parsed arguments; returns the exit status."""
    from ..feet import by_name

    if args.speed <= 0:
        raise MudrftError(f"--speed must be > 0 m/s, got {args.speed!r}")
    if args.depth <= 0:
        raise MudrftError(f"--depth must be > 0 m, got {args.depth!r}")
    foot = by_name(args.foot)
    paths = run(
        foot,
        args.out,
        water_content=args.water_content,
        speed=args.speed,
        depth=args.depth,
        hold=args.hold,
        figures=not args.no_figures,
        force=args.force,
    )
    for p in paths.values():
        print(f"wrote {p}", file=sys.stdout)
    return 0
