"""Benchmarks of the backends: the same run as ``mudrft bench``, from the checkout.

Run ``python benchmarks/bench_backends.py [--quick] [--json FILE] [--force] [--quiet]``.
The benchmarks are in ``benchmarks/harness`` (loaded by :mod:`mudrft.cli.bench`); results
and their discussion are in docs/performance.md.
"""

from __future__ import annotations

import argparse
import sys

from mudrft.cli import bench


def _parse(argv: list[str]) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="cmd", required=True)
    bench.add_parser(sub)
    return parser.parse_args(["bench", *argv])


if __name__ == "__main__":
    sys.exit(bench.run(_parse(sys.argv[1:])))
