"""``mudrft calibrate``: fit the model to intrusion logs; the table to stdout, the fit to JSON
(:meth:`mudrft.calibration.FitResult.to_json`)."""

from __future__ import annotations

import argparse
import csv
from typing import Any

from .._validation import MudrftError
from ..units import parse_quantity
from ._common import (
    Outputs,
    check_finite_option,
    check_positive_option,
    logger,
    require_plot_file,
    same_file,
    save_figure,
)
from ._parser import add_evaluation_options, add_run_options, add_subcommand

#: The roles --columns maps.
ROLES = ("time", "depth", "stress", "force", "trial")


def add_parser(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    p = add_subcommand(
        subparsers,
        "calibrate",
        run,
        help="fit the model to your own intrusion logs",
        description="Fit the mud model (Chen et al. 2026) to plate-intrusion logs: bounded "
        "least squares, phase by phase (intrusion, relaxation, retraction) then jointly; prints "
        "parameters with standard errors, confidence intervals and an identifiability verdict, "
        "and writes them as JSON. Columns: 'time', 'depth' and 'stress' or 'force' (or 'Fz'), "
        "each with its unit as 'time [s]', 'Time (s)' or 'time in s' (ms, mm, kPa, N, ... are "
        "converted), an optional 'trial' column, separated by commas, tabs or semicolons; "
        "--columns names the columns a logger calls otherwise.",
    )
    p.add_argument("data", nargs="+", help="intrusion log(s): CSV, or HDF5 (.h5/.hdf5)")
    p.add_argument(
        "--direction",
        choices=["vertical", "horizontal"],
        help="loading direction of the tests (default: the file's, else vertical)",
    )
    p.add_argument(
        "--columns",
        metavar="ROLE=NAME,...",
        help="the log's names of its columns, for names mudrft does not read: e.g. "
        'time="Time (s)",depth="Position (mm)",force="Load (N)"; roles: ' + ", ".join(ROLES),
    )
    p.add_argument(
        "--area",
        help="plate area, with a unit (1600mm^2, 16cm^2) or in m^2; needed when the log has "
        "a force column",
    )
    p.add_argument(
        "--length",
        help="plate characteristic length L_c, with a unit (40mm) or in m (default: the "
        "file's, else 0.05)",
    )
    p.add_argument(
        "--groups",
        nargs="+",
        default=["all"],
        help="what to fit: all, b, th, s, or parameter names",
    )
    p.add_argument(
        "--starts", type=int, default=1, help="multi-start: grid points refined per phase stage"
    )
    p.add_argument(
        "--decimate",
        type=int,
        metavar="K",
        help="keep every K-th sample of each trial; 1 fits every sample (default: trials "
        "longer than 2000 samples are thinned to about 2000, with a warning naming K)",
    )
    p.add_argument(
        "--confidence",
        type=float,
        default=0.95,
        help="level of the confidence intervals, a fraction between 0 and 1",
    )
    add_evaluation_options(
        p, what="fit the ODE model or the paper's quasi-static closed forms (9)-(11) (D15)"
    )
    p.add_argument(
        "--clipped",
        choices=["exclude", "keep"],
        default="exclude",
        help="a trial with 5 or more samples at exactly its extreme stress is a saturated "
        "sensor (named by a warning): leave those samples out of the fit, or fit them (D153)",
    )
    p.add_argument(
        "--zero",
        choices=["check", "subtract"],
        default="check",
        help="the stress while the plate is out of the mud (depth <= 0, vertical tests) is "
        "the sensor's zero: warn when it is clearly off 0, or subtract it from each trial (D154)",
    )
    p.add_argument("--out", help="write the fit to this JSON file")
    p.add_argument("--overwrite", action="store_true", help=argparse.SUPPRESS)  # old --force
    p.add_argument("--plot", help="save a PNG of the fit against the data (needs mudrft[plot])")
    add_run_options(
        p,
        force="--out and --plot if they exist",
        strict="a fit that does not describe the data, a log thinned, units that look wrong, "
        "a sensor saturated or not zeroed",
    )


def parse_columns(text: str) -> dict[str, str]:
    """``time="Time (s)",depth=Pos`` -> ``{"time": "Time (s)", "depth": "Pos"}``."""
    pairs = [p for p in next(csv.reader([text], skipinitialspace=True), []) if p.strip()]
    out: dict[str, str] = {}
    for pair in pairs:
        role, sep, name = (part.strip() for part in pair.partition("="))
        if not sep or role not in ROLES or not name.strip("\"'"):
            raise MudrftError(
                f"--columns must be ROLE=NAME pairs separated by commas, ROLE one of "
                f'{", ".join(ROLES)} (e.g. time="Time (s)",depth="Depth (mm)"), got {pair!r}'
            )
        if role in out:
            raise MudrftError(f"--columns names the {role} twice ({out[role]!r}, {name!r})")
        out[role] = name.strip("\"'")
    if not out:
        raise MudrftError(f"--columns must name at least one column, got {text!r}")
    return out


def _check_options(args: argparse.Namespace) -> dict[str, Any]:
    """The loader's options in SI, checked before any file is read and named as the
    command line names them."""
    for option, value in (("--starts", args.starts), ("--decimate", args.decimate)):
        if value is not None and value < 1:
            raise MudrftError(f"{option} must be an integer >= 1, got {value}")
    opts: dict[str, Any] = {"area": None, "characteristic_length": None}
    for option, key, value, quantity, unit in (
        ("--area", "area", args.area, "area", "m^2"),
        ("--length", "characteristic_length", args.length, "length", "m"),
    ):
        if value is not None:
            si = parse_quantity(option, value, quantity)
            opts[key] = check_positive_option(option, si, unit=unit)
    if args.columns is not None:
        opts["columns"] = parse_columns(args.columns)
    if args.direction:
        opts["direction"] = args.direction
    level = check_finite_option("--confidence", args.confidence)
    if not 0 < level < 1:
        hint = f" (give a fraction: {level:g} % is {level / 100:g})" if 1 < level < 100 else ""
        raise MudrftError(f"--confidence must lie between 0 and 1, got {level:g}{hint}")
    return opts


def run(args: argparse.Namespace) -> int:
    """Fit, print the table, write ``--out``/``--plot``; 1 if the fit failed."""
    from ..calibration.fit import calibrate
    from ..io import load_dataset

    for option in ("out", "plot"):
        target = getattr(args, option)
        if target and any(same_file(target, d) for d in args.data):
            raise MudrftError(f"--{option} {target!r} names an input file; choose another name")
    if args.plot:
        require_plot_file("--plot", args.plot)
    opts = _check_options(args)
    with Outputs(force=args.force or getattr(args, "overwrite", False)) as outputs:
        json_tmp = outputs.file("--out", args.out) if args.out else None
        plot_tmp = outputs.file("--plot", args.plot) if args.plot else None
        ds = load_dataset(args.data if len(args.data) > 1 else args.data[0], **opts)
        fit = calibrate(
            ds,
            args.direction,
            groups=args.groups,
            starts=args.starts,
            confidence_level=args.confidence,
            progress=None if args.quiet else logger.info,
            decimate=args.decimate,
            thixotropy=args.thixotropy,
            clock=args.clock,
            clipped=args.clipped,
            zero=args.zero,
        )
        print(fit.summary())
        if ds.synthetic:
            print("note: the data say they are synthetic (generated by a model, not measured)")
        if json_tmp is not None:
            fit.to_json(json_tmp, overwrite=True)
        if plot_tmp is not None:
            save_figure(fit.plot(), plot_tmp)
    for path in outputs.written:
        print(f"wrote {path}")
    return 0 if fit.success else 1
