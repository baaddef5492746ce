"""``mudrft bench``: the speed benchmarks of a source checkout, summarised on stdout.

The benchmarks are not part of the installed library: they live in the checkout's
``benchmarks/harness`` package (beside ``src/``), which :func:`load_harness` imports by
path. From an installation without the checkout (a wheel), the command says so in one line.
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
from pathlib import Path
from types import ModuleType

from .._validation import MudrftError
from ..io.atomic import json_text
from ._common import Outputs, logger
from ._parser import add_force, add_quiet, add_subcommand

__all__ = ["HARNESS_MODULE", "add_parser", "harness_path", "load_harness", "run"]

#: Name under which the harness package is registered in ``sys.modules``.
HARNESS_MODULE = "mudrft_benchmarks_harness"

DESCRIPTION = (
    "Run the speed benchmarks (the machine's bandwidth and peak, the constitutive step, "
    "mesh feet, batches of feet on every backend, one foot per step, simulate, the MuJoCo "
    "overhead, robot-steps per second with mud at 1, 64 and 1,024 robots for the CPU coupling "
    "and MJX, and a roofline estimate) and print a summary; --json writes every number. "
    "Needs a source checkout: the benchmarks live in its benchmarks/ directory."
)


def harness_path() -> Path:
    """Where the harness package of the source checkout is: ``<checkout>/benchmarks/harness``."""
    import mudrft

    return Path(mudrft.__file__).resolve().parents[2] / "benchmarks" / "harness"


def load_harness() -> ModuleType:
    """Import the benchmark harness of the source checkout by path (once per process).

    Returns
    -------
    module
        The ``benchmarks/harness`` package (``run_benchmarks``, ``summary_lines``, ...).

    Raises
    ------
    MudrftError
        When this mudrft was not imported from a source checkout (installed from a wheel),
        so that ``benchmarks/harness`` is not beside its ``src/`` directory.
    """
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
    if spec is None or spec.loader is None:  # pragma: no cover - a readable __init__.py loads
        raise MudrftError(f"mudrft bench could not load the benchmark harness from {init}")
    module = importlib.util.module_from_spec(spec)
    sys.modules[HARNESS_MODULE] = module  # the harness's relative imports look it up here
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[HARNESS_MODULE]
        raise
    return module


def add_parser(
    subparsers: argparse._SubParsersAction[argparse.ArgumentParser],
) -> argparse.ArgumentParser:
    """Add ``mudrft bench`` to an argparse subparsers object."""
    p = add_subcommand(
        subparsers,
        "bench",
        help="speed benchmarks (constitutive step, mesh, batches, one foot, MuJoCo)",
        description=DESCRIPTION,
    )
    p.add_argument("--quick", action="store_true", help="short run (minutes: MJX compiles)")
    p.add_argument("--json", metavar="FILE", help="write the results as JSON to FILE")
    add_force(p, "--json FILE if it exists")
    add_quiet(p)
    p.set_defaults(func=run)
    return p


def run(args: argparse.Namespace) -> int:
    """Run the benchmarks, print the summary, write ``--json``; returns the exit status (0)."""
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
