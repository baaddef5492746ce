"""``mudrft bench``: the speed benchmarks of a source checkout (its ``benchmarks/harness``)."""

from __future__ import annotations

import argparse
import importlib.util
import sys
from pathlib import Path
from types import ModuleType

from .._validation import MudrftError
from ..io.atomic import json_text
from ._common import Outputs, logger
from ._parser import add_run_options, add_subcommand

#: Name under which the harness package is registered in ``sys.modules``.
HARNESS_MODULE = "mudrft_benchmarks_harness"


def harness_path() -> Path:
    """Where the harness package of the source checkout is: ``<checkout>/benchmarks/harness``."""
    import mudrft

    return Path(mudrft.__file__).resolve().parents[2] / "benchmarks" / "harness"


def load_harness() -> ModuleType:
    """Import the benchmark harness of the source checkout by path (once per process);
    a :class:`~mudrft.MudrftError` when mudrft was not installed from a checkout."""
    loaded = sys.modules.get(HARNESS_MODULE)
    if loaded is not None:
        return loaded
    where = harness_path()
    init = where / "__init__.py"
    if not init.is_file():
        raise MudrftError(
            f"mudrft bench needs the benchmarks/ directory of a source checkout, and {where} "
            "does not exist (this mudrft was installed without it, e.g. from a wheel): clone "
            "the mudrft repository and run 'pip install -e .' there, then 'mudrft bench'"
        )
    spec = importlib.util.spec_from_file_location(
        HARNESS_MODULE, init, submodule_search_locations=[str(where)]
    )
    assert spec is not None and spec.loader is not None  # a readable __init__.py loads
    module = importlib.util.module_from_spec(spec)
    sys.modules[HARNESS_MODULE] = module  # the harness's relative imports look it up here
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[HARNESS_MODULE]
        raise
    return module


def add_parser(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    p = add_subcommand(
        subparsers,
        "bench",
        run,
        help="speed benchmarks (constitutive step, mesh, batches, one foot, MuJoCo)",
        description="Run the speed benchmarks (the machine's bandwidth and peak, the "
        "constitutive step, mesh feet, batches of feet on every backend, one foot per step, "
        "simulate, the MuJoCo overhead, robot-steps per second with mud at 1, 64 and 1,024 "
        "robots for the CPU coupling and MJX, and a roofline estimate) and print a summary; "
        "--json writes every number. Needs a source checkout: the benchmarks live in its "
        "benchmarks/ directory.",
    )
    p.add_argument("--quick", action="store_true", help="short run (minutes: MJX compiles)")
    p.add_argument("--json", metavar="FILE", help="write the results as JSON to FILE")
    add_run_options(p, force="--json FILE if it exists")


def run(args: argparse.Namespace) -> int:
    """Run the benchmarks, print the summary, write ``--json``."""
    harness = load_harness()
    with Outputs(force=args.force) as outputs:
        json_tmp = outputs.file("--json", args.json) if args.json is not None else None
        progress = None if args.quiet else logger.info
        res = harness.run_benchmarks(quick=bool(args.quick), progress=progress)
        for line in harness.summary_lines(res):
            print(line)
        if json_tmp is not None:
            json_tmp.write_text(json_text(res))
    for path in outputs.written:
        print(f"wrote {path}")
    return 0
