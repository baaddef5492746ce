"""``mudrft reproduce``: the paper's comparisons, written to one directory."""

from __future__ import annotations

import argparse
from pathlib import Path

from ._common import Outputs, require_extra
from ._parser import add_run_options, add_subcommand


def add_parser(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    p = add_subcommand(
        subparsers,
        "reproduce",
        run,
        help="the paper's claims under its readings: summary.csv, claims.csv, report.md, figures",
        description="Reproduce the paper's comparisons as the paper computes them: every foot "
        "(flat, semi-cylinder, semi-sphere, morphing) through one stepping cycle at the paper's "
        "three gait speeds and tabulated water contents under the headline reading (the "
        "paper's quasi-static eqs. (9)-(11), feet not buried), then under the other readings "
        "of the paper and at every stance depth of 10-26 mm, which the paper does not give. "
        "Writes DIR/summary.csv (headline: one row per foot, speed and water content), "
        "DIR/claims.csv (one row per claim and reading: claim, reading, paper, mudrft, "
        "verdict), DIR/depths.csv (one row per claim and stance depth), DIR/report.md (the "
        "headline's 'N of 9 claims' and its range over the stance depths, the matrix of "
        "readings x claims and where the paper supports each reading) and figures like the "
        "paper's Figs. 9, 10, 12 and 13 and of the verdicts against the depth (PNG).",
    )
    p.add_argument("--out", default="mudrft-results", help="output directory DIR")
    p.add_argument("--no-figures", action="store_true", help="skip the PNG figures")
    add_run_options(p, force="existing results in DIR")


def run(args: argparse.Namespace) -> int:
    """Run :func:`mudrft.reproduce.reproduce` into ``--out``."""
    from ..reproduce import reproduce
    from ..reproduce.runner import FIGURES, TABLES

    figures = not args.no_figures
    if figures:
        require_extra(
            "matplotlib", needed_for="the figures of mudrft reproduce", unless="--no-figures"
        )
    with Outputs(force=args.force) as outputs:
        stage = outputs.directory("--out", args.out, TABLES + (FIGURES if figures else ()))
        reproduce(stage, force=True, figures=figures, quiet=args.quiet)
    written = ", ".join(p.name for p in outputs.written)
    print(f"results in {Path(args.out)}: {written}")
    return 0
