"""``mudrft sweep``: a design sweep from a TOML spec, on Dask, into one directory."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

from .._validation import MudrftError
from ._common import Outputs, logger, require_extra, same_file, save_figure
from ._parser import add_run_options, add_subcommand

if TYPE_CHECKING:
    import xarray as xr

#: The resumable store in DIR (written chunk by chunk, kept when a run fails).
STORE = "sweep.zarr"
#: One row per point (parameters, metrics, error), written when the sweep completes.
TABLE = "points.csv"


def add_parser(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    p = add_subcommand(
        subparsers,
        "sweep",
        run,
        help="design sweeps on Dask -> DIR/sweep.zarr, points.csv, maps",
        description="Run a design sweep: the foot, mud and motion parameters of SPEC.toml "
        "over a grid or a sample, every metric at every point: in this process while that is "
        "quicker than starting a local Dask cluster, else on one (of --workers processes), or "
        "on the cluster at --scheduler. Writes DIR/sweep.zarr chunk by chunk (a killed or "
        "damaged run resumes with --resume and computes only the missing or damaged chunks), "
        "then DIR/points.csv (one row per point) and, with --plot, DIR/METRIC.png maps. A "
        "point that fails is recorded (NaN and its error), the rest completes, and the command "
        "exits with 1. Needs pip install 'mudrft[sweep]'. The spec format: "
        "examples/sweep_example.toml, README.",
    )
    p.add_argument("spec", metavar="SPEC.toml", help="the sweep spec (TOML)")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory")
    p.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="address of a running Dask scheduler (tcp://host:8786), or 'serial' to run in "
        "this process (default: this process, or a local cluster once that is quicker)",
    )
    p.add_argument(
        "--workers",
        type=int,
        metavar="N",
        help="run on a local cluster of N worker processes (default: one per CPU, started "
        "only when quicker than running here)",
    )
    p.add_argument(
        "--plot", action="store_true", help="also write DIR/METRIC.png maps (needs mudrft[plot])"
    )
    p.add_argument(
        "--resume",
        action="store_true",
        help="continue DIR/sweep.zarr (made from the same spec): compute only missing chunks",
    )
    add_run_options(
        p,
        force="existing outputs: without --resume DIR/sweep.zarr is started again; with "
        "--resume it is kept and only points.csv and the maps are replaced",
    )


def _write_table(ds: xr.Dataset, path: Path) -> None:
    """One row per point: swept parameters, fixed parameters, metrics, error."""
    ds = ds.drop_vars("done", errors="ignore")
    df = ds.to_dataframe().reset_index()
    swept = [str(d) for d in ds["error"].dims]
    params = [*swept, *(str(c) for c in ds.coords if c not in swept)]
    df = df[[*params, *(str(v) for v in ds.data_vars)]]
    units = {str(k): ds[k].attrs.get("units", "") for k in ds.variables}
    df.columns = [
        f"{c} [{units[c]}]" if units.get(c) and units[c] != "-" else str(c) for c in df.columns
    ]
    df.to_csv(path, index=False, float_format="%.9g")


def run(args: argparse.Namespace) -> int:
    """Run the sweep and write ``DIR``; 1 if any point failed."""
    from ..sweep.spec import load_spec

    spec = load_spec(args.spec)
    if args.plot:
        require_extra("matplotlib", needed_for="--plot")
    out = Path(args.out)
    store = out / STORE
    if any(part.name == STORE for part in (out, *out.parents)):  # a store inside a store
        raise MudrftError(
            f"--out {str(out)!r} is a sweep store; give the directory that holds it "
            f"({str(out.parent)!r}), where the sweep writes {STORE}, points.csv and maps"
        )
    if args.resume and store.exists():  # another spec's store: said before --force is asked
        from ..sweep.store import open_store

        open_store(store, spec)
    if store.exists() and not (args.resume or args.force):
        raise MudrftError(
            f"--out: {str(store)!r} exists; pass --resume to continue it or --force to start again"
        )
    maps = tuple(spec.plot.get("metrics", spec.metrics)) if args.plot else ()
    names = [TABLE, *(f"{m}.png" for m in maps)]
    spec_path = Path(args.spec).resolve()
    restarts = args.force and not args.resume  # DIR/sweep.zarr is removed and made again
    if any(same_file(spec_path, out / n) for n in names) or (
        restarts and store.resolve() in spec_path.parents
    ):
        raise MudrftError(
            f"--out {str(out)!r} would replace the spec {args.spec!r}; move the spec or "
            "choose another directory"
        )
    with Outputs(force=args.force) as outputs:
        stage = outputs.directory("--out", out, names)
        what = f"{spec.n_points} points in {spec.n_chunks} chunks ({spec.design} design"
        logger.info("mudrft sweep: %s, motion %s) -> %s", what, spec.motion, store)
        from ..sweep.plot import plot_maps
        from ..sweep.run import run_sweep

        ds = run_sweep(
            spec,
            store=store,
            scheduler=args.scheduler,
            workers=args.workers,
            resume=args.resume,
            overwrite=restarts,
            progress=not args.quiet,
        )
        _write_table(ds, stage / TABLE)
        kw = {k: spec.plot.get(k) for k in ("x", "y", "panels")}
        for m in maps:
            save_figure(plot_maps(ds, m, **kw), stage / f"{m}.png", dpi=110)
    failed = int(ds.attrs.get("failed_points", 0))
    print(f"{spec.n_points} points, {failed} failed; wrote {store}")
    errors = [e for e in ds["error"].values.ravel() if e]
    distinct = list(dict.fromkeys(errors))
    for e in distinct[:3]:
        print(f"  failed ({errors.count(e)} points): {e}")
    if len(distinct) > 3:
        print(f"  ... and {len(distinct) - 3} other errors (the 'error' variable)")
    for path in outputs.written:
        print(f"wrote {path}")
    if failed:
        what = f"{failed} of {spec.n_points} points failed"
        where = f"the 'error' column of {out / TABLE}"
        logger.error("mudrft sweep: error: %s (NaN metrics; each error in %s)", what, where)
        return 1
    return 0
