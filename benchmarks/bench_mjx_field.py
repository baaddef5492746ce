"""MJX robot-steps per second on a field of mud drawn per robot, beside one mud.

``python benchmarks/bench_mjx_field.py [--quick] [--json FILE]``; see
``benchmarks/harness/robots.py`` (:func:`bench_fields`). Results: docs/performance.md.
"""

from __future__ import annotations

import argparse
import json
import sys

from harness.machine import machine_info
from harness.robots import bench_fields


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="50 steps a call, 2 repeats")
    ap.add_argument("--json", help="write the results to this file")
    ap.add_argument("--robots", type=int, nargs="*", help="robot counts (default 1 64 1024)")
    ap.add_argument(
        "--chunk", type=int, default=0,
        help="vmap this many robots at a time inside the one jitted call (lax.map over the "
        "groups); 0: all at once",
    )  # fmt: skip
    args = ap.parse_args(argv)
    res = {
        "machine": machine_info(),
        **bench_fields(args.quick, lambda m: print(m, file=sys.stderr), args.robots, args.chunk),
    }
    text = json.dumps(res, indent=2)
    if args.json:
        with open(args.json, "x") as fh:  # never over an existing file
            fh.write(text + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
