"""``mudrft bench``: the speed benchmarks of :mod:`mudrft.bench`, summarised on stdout."""

from __future__ import annotations

import argparse
import json
from typing import Any

from ._common import HelpFormatter, Outputs, add_force, logger

__all__ = ["add_parser", "run"]

DESCRIPTION = (
    "Run the speed benchmarks (the machine's bandwidth and peak, the constitutive step, "
    "mesh feet, batches of feet on every backend, the single-foot fast path, the MuJoCo "
    "overhead and a roofline estimate) and print a summary; --json writes every number."
)


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    """Add ``mudrft bench`` to an argparse subparsers object."""
    p = subparsers.add_parser(
        "bench",
        help="speed benchmarks (constitutive step, mesh, batches, fast path, MuJoCo)",
        description=DESCRIPTION,
        formatter_class=HelpFormatter,
    )
    p.add_argument("--quick", action="store_true", help="short run (well under a minute)")
    p.add_argument("--json", metavar="FILE", help="write the results as JSON to FILE")
    add_force(p, "--json FILE if it exists")
    p.add_argument("--quiet", action="store_true", help="no progress output")
    p.set_defaults(func=run)
    return p


def run(args: argparse.Namespace) -> int:
    """Run the benchmarks, print the summary, write ``--json``; returns the exit status (0)."""
    from .. import bench

    with Outputs(force=args.force) as outputs:
        json_tmp = outputs.file("--json", args.json) if args.json is not None else None
        progress = None if args.quiet else logger.info
        res = bench.run_benchmarks(quick=bool(args.quick), progress=progress)
        for line in bench.summary_lines(res):
            print(line)
        if json_tmp is not None:
            json_tmp.write_text(json.dumps(res, indent=2, default=float) + "\n")
    for path in outputs.written:
        print(f"wrote {path}")
    return 0
