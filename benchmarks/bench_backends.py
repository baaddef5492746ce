"""Benchmarks of the backends: a thin script over :mod:`mudrft.bench` (same as ``mudrft bench``).

Run ``python benchmarks/bench_backends.py [--quick] [--json FILE]``. The implementations
live in the installed package (``src/mudrft/bench.py``) so that ``mudrft bench`` works
from any installation; results and their discussion are in docs/performance.md.
"""

from __future__ import annotations

import argparse
import sys

from mudrft import bench


def _parse(argv: list[str]) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="cmd", required=True)
    bench.add_parser(sub)
    return parser.parse_args(["bench", *argv])


if __name__ == "__main__":
    sys.exit(bench.main(_parse(sys.argv[1:])))
