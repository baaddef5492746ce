"""Only the headline batch number: ``batch_speedup_1e4`` of every backend, in one run.

Run ``python benchmarks/bench_batch_speedup.py [--quick]``: time per foot of a Python loop
over single-foot ``MudTerrain.step`` calls divided by time per foot of one batched call of
10,000 flat feet (:class:`mudrft.backends.BatchedMud`), measured in the same run.
"""

from __future__ import annotations

import json
import sys

from mudrft.cli.bench import load_harness

if __name__ == "__main__":
    quick = "--quick" in sys.argv[1:]
    harness = load_harness()
    res = harness.bench_speedup(quick, 0.05 if quick else 0.4, lambda m: print(m, file=sys.stderr))
    print(json.dumps(res, indent=2))
