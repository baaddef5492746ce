"""``mudrft reproduce``: the runs, shared where two readings give the same physics, and
``summary.csv``; :func:`reproduce` also writes the tables of :mod:`.report` and the figures
of :mod:`.figures`."""

from __future__ import annotations

import csv
import functools
import time as _time
import warnings
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any, TypeAlias

import numpy as np

from .._progress import logger, make_progress
from .._validation import MudrftError
from ..feet import MorphingFoot, by_name
from ..simulation import Result, simulate, static_sinking
from ..trajectories import GAIT_SPEEDS, BuriedFootWarning, gait
from .claims import FIXED, LOAD, Cell, evaluate, medium_speed
from .readings import CURL_DELAYS, READINGS, STANCE_DEPTHS, Reading

FEET = ("flat", "semi-cylinder", "semi-sphere", "morphing")
WATER_CONTENTS = (0.25, 0.35, 0.45)

#: The tables :func:`reproduce` writes in its directory.
TABLES = ("summary.csv", "claims.csv", "depths.csv", "report.md")
#: The figures it writes there (``figures=True``).
FIGURES = (
    "fig09_forces.png", "fig10_normalized.png", "fig12_hysteresis.png", "fig13_suction_energy.png",
    "fig_depth_verdicts.png",
)  # fmt: skip

#: The columns of ``summary.csv``.
SUMMARY_COLUMNS = (
    *("foot", "speed [m/s]", "water_content", "peak_support [N]", "max_suction [N]"),
    *("impulse_x [N s]", "impulse_y [N s]", "impulse_z [N s]", "energy [J]", "sinking [m]"),
    *("suction_ratio", "peak_normalized_sz [Pa]", "min_normalized_sz [Pa]"),
    "normalized_suction_ratio",
)


def _say(msg: str, quiet: bool) -> None:
    """A progress note on the ``mudrft`` logger, shown as ``progress=True`` shows progress."""
    if not quiet:
        make_progress(True, "reproduce")  # a stderr handler if logging is not configured
        logger.info("%s", msg)


def _prepare_out(out: Path, force: bool, names: Sequence[str]) -> None:
    """Make ``out``; refuse, without ``force``, each of ``names`` that exists there."""
    if out.exists() and not out.is_dir():
        raise MudrftError(f"--out {str(out)!r} exists and is not a directory")
    taken = [n for n in names if (out / n).exists()]
    if taken and not force:
        raise MudrftError(
            f"--out {str(out)!r} already holds {', '.join(taken)}; pass --force "
            "(force=True) to overwrite"
        )
    try:
        out.mkdir(parents=True, exist_ok=True)
        probe = out / ".mudrft_write_test"
        probe.write_text("")
        probe.unlink()
    except OSError as exc:
        raise MudrftError(f"--out {str(out)!r} is not writable: {exc.strerror or exc}") from exc


#: A gait run: (the physics of the reading and foot, foot, speed [m/s], table row).
RunKey: TypeAlias = tuple[tuple[object, ...], str, float, float]
#: A run to make: (reading, foot, speed [m/s], table row, stance depth [m] or None: the reading's).
Task: TypeAlias = tuple[Reading, str, float, float, float | None]


class _Runs:
    """Gait runs and sinking depths, computed once and shared by every reading."""

    def __init__(self, dt: float) -> None:
        self.dt = dt
        self.results: dict[RunKey, Result] = {}
        self.numbers: dict[RunKey, dict[str, float]] = {}
        self._sinking: dict[tuple[str, float], float] = {}

    @staticmethod
    def key(rd: Reading, foot: str, speed: float, row: float, depth: float | None = None) -> RunKey:
        return (rd.run_key(foot, depth), foot, float(speed), float(row))

    def run(
        self, reading: Reading, foot: str, speed: float, row: float, depth: float | None = None
    ) -> None:
        stance = depth or reading.depth
        delay = reading.curl_delay if foot == "morphing" else 0.0
        shape = MorphingFoot(curl_delay=delay) if delay else by_name(foot)
        with warnings.catch_warnings():  # the buried readings say so in the report
            warnings.simplefilter("ignore", BuriedFootWarning)
            res = simulate(shape, reading.terrain(row), gait(speed, depth=stance, dt=self.dt))
        m = res.metrics()
        ns = res.normalized_stress()[:, 2] if res.areas is not None else np.zeros(len(res))
        m.update(
            peak_ns=float(ns.max()),
            min_ns=float(ns.min()),
            peak_ns_depth=float(res.depth[int(np.argmax(ns))]),
        )
        key = self.key(reading, foot, speed, row, depth)
        self.results[key], self.numbers[key] = res, m

    def metrics(
        self, reading: Reading, foot: str, speed: float, row: float, depth: float | None = None
    ) -> dict[str, float] | None:
        """The numbers of a run, or None if it was not run."""
        return self.numbers.get(self.key(reading, foot, speed, row, depth))

    def sinking(self, reading: Reading, foot: str, row: float) -> float:
        """Sinking under :data:`LOAD` on the row's relaxed mud [m] (D13)."""
        key = (foot, float(row))
        if key not in self._sinking:
            self._sinking[key] = static_sinking(by_name(foot), reading.mud(row), LOAD)
        return self._sinking[key]

    def loaded(self, reading: Reading, foot: str, speed: float) -> dict[str, float] | None:
        """``foot``'s gait at its own sinking depth under :data:`LOAD`, on the reading's
        "25 %" row: the load-carrying stance (None if not run)."""
        w = reading.row(0.25)
        return self.metrics(reading, foot, speed, w, self.sinking(reading, foot, w))


#: The feet of the load-carrying stance (claims morphing-vs-*).
LOADED = ("flat", "semi-cylinder", "morphing")


def reproduce(
    out: str | Path,
    *,
    force: bool = False,
    feet: Sequence[str] = FEET,
    speeds: Sequence[float] = tuple(GAIT_SPEEDS.values()),
    water_contents: Sequence[float] = WATER_CONTENTS,
    readings: Sequence[Reading] = READINGS,
    depths: Sequence[float] = STANCE_DEPTHS,
    curl_delays: Sequence[float] = CURL_DELAYS,
    figures: bool = True,
    quiet: bool = False,
    dt: float = 1e-3,
) -> list[dict[str, Any]]:
    """Reproduce the paper's comparisons and write results to ``out``.

    Parameters
    ----------
    out : str or Path
        Output directory (created if needed).
    force : bool, keyword-only
        Overwrite existing results.
    feet : sequence of str, keyword-only
        Foot names (``flat``, ``semi-cylinder``, ``semi-sphere``, ``morphing``).
    speeds : sequence of float, keyword-only
        Gait speeds [m/s].
    water_contents : sequence of float, keyword-only
        Table rows by their printed water content [-] (0.25, 0.35, 0.45).
    readings : sequence of Reading, keyword-only
        Readings of the matrix; the first is the headline (``summary.csv``, figures).
    depths : sequence of float, keyword-only
        Stance depths [m] at which the headline's claims are also evaluated (``depths.csv``).
    curl_delays : sequence of float, keyword-only
        Pad-curl delays of the morphing foot [s] whose suction ratio the report gives.
    figures, quiet : bool, keyword-only
        Write the PNG figures (needs matplotlib); print no progress.
    dt : float, keyword-only
        Time step of the gait runs [s].

    Returns
    -------
    list of dict
        The rows of ``summary.csv``.
    """
    outp = Path(out)
    _prepare_out(outp, force, TABLES + (FIGURES if figures else ()))
    for name, values, unit in (("speeds", speeds, "m/s"), ("depths", depths, "m")):
        for x in values:
            if not (isinstance(x, (int, float)) and x > 0):
                raise MudrftError(f"{name} must be > 0 {unit}, got {x!r}")
    for x in curl_delays:
        if not (isinstance(x, (int, float)) and x >= 0):
            raise MudrftError(f"curl_delays must be >= 0 s, got {x!r}")
    if not readings:
        raise MudrftError("readings must name at least one reading (the headline)")
    t0 = _time.perf_counter()

    runs = _Runs(dt)
    rows_w = [float(w) for w in water_contents]
    head = readings[0]
    at_depth = {float(d): replace(head, depth=float(d)) for d in depths}
    delayed = {float(x): replace(head, curl_delay=float(x)) for x in curl_delays}
    v = medium_speed(speeds)
    fixed = [f for f in feet if f in FIXED]
    loads = set(LOADED) <= set(feet)  # the load-carrying stance is run
    tasks: list[Task] = [(head, f, float(s), w, None) for w in rows_w for f in feet for s in speeds]
    for rd in (*readings, *at_depth.values()):  # the runs the nine claims need
        w = rd.row(0.25)
        if any(abs(w - r) < 1e-9 for r in rows_w):
            tasks += [(rd, f, v, w, None) for f in feet]
            tasks += [(rd, f, s, w, None) for f in fixed for s in speeds]
            tasks += [(rd, f, v, r, None) for f in fixed for r in rows_w]
        if w in rows_w and loads:
            tasks += [(rd, f, v, w, runs.sinking(rd, f, w)) for f in LOADED]
    if "morphing" in feet and head.row(0.25) in rows_w:
        tasks += [(rd, "morphing", v, head.row(0.25), None) for rd in delayed.values()]
    todo: dict[RunKey, Task] = {}
    for t in tasks:  # each physics once, in order, named by the first reading that needs it
        todo.setdefault(runs.key(*t), t)
    width = max(2, len(str(len(todo))))
    for i, (rd, f, s, w, d) in enumerate(todo.values(), 1):
        _say(
            f"[{i:{width}d}/{len(todo)}] {rd.key:17s} {f:13s} {s:.2f} m/s  "
            f"W = {rd.label(w) * 100:g} %  {(d or rd.depth) * 1e3:.1f} mm",
            quiet,
        )
        runs.run(rd, f, s, w, d)
    rows = _summary_rows(runs, head, feet, speeds, rows_w)
    write_rows(outp / "summary.csv", rows, SUMMARY_COLUMNS)
    _say(f"wrote {outp / 'summary.csv'} ({len(rows)} rows)", quiet)

    def cells_of(rd: Reading) -> list[Cell]:
        return evaluate(
            rd,
            functools.partial(runs.metrics, rd),
            functools.partial(runs.sinking, rd),
            feet=list(feet),
            speeds=[float(s) for s in speeds],
            rows=rows_w,
            loaded=functools.partial(runs.loaded, rd, speed=v) if loads else None,
        )

    cells = {rd.key: cells_of(rd) for rd in readings}
    by_depth = {d: cells_of(rd) for d, rd in at_depth.items()}
    ratios = {}
    for x, rd in delayed.items():
        m = runs.metrics(rd, "morphing", v, head.row(0.25))
        if m is not None and m["peak_support"] > 0:
            ratios[x] = m["max_suction"] / m["peak_support"]
    if figures:
        from .figures import make_figures

        for path in make_figures(
            outp,
            lambda f, s, w: runs.results[runs.key(head, f, s, w)],
            rows,
            feet=list(feet),
            speeds=list(speeds),
            water_contents=rows_w,
            by_depth=by_depth,
        ):
            _say(f"wrote {path}", quiet)
    from .report import write_claims_csv, write_depths_csv, write_report

    _say(f"wrote {write_claims_csv(outp / 'claims.csv', cells)}", quiet)
    _say(f"wrote {write_depths_csv(outp / 'depths.csv', head, by_depth)}", quiet)
    sinking = {f: runs.sinking(head, f, head.row(0.25)) for f in fixed}
    report = write_report(
        outp / "report.md",
        cells,
        readings=list(readings),
        by_depth=by_depth,
        curl_ratios=ratios,
        suction_ratios=_suction_ratios(runs, readings, v),
        sinking=sinking if head.row(0.25) in rows_w else {},
    )
    _say(f"wrote {report}", quiet)
    _say(f"done in {_time.perf_counter() - t0:.1f} s ({len(todo)} gait runs)", quiet)
    return rows


def _suction_ratios(
    runs: _Runs, readings: Sequence[Reading], speed: float
) -> list[tuple[float, float | None]]:
    """The semi-cylinder's suction over the flat foot's [-] in the gait and with the
    load-carrying stance (None where not run), for each reading that ran both feet."""
    feet = ("semi-cylinder", "flat")
    out = []
    for rd in readings:
        curved, flat = (runs.metrics(rd, f, speed, rd.row(0.25)) for f in feet)
        if curved is not None and flat is not None:
            held_curved, held_flat = (runs.loaded(rd, f, speed) for f in feet)
            held = None
            if held_curved is not None and held_flat is not None:
                held = held_curved["max_suction"] / held_flat["max_suction"]
            out.append((curved["max_suction"] / flat["max_suction"], held))
    return out


def _summary_rows(
    runs: _Runs,
    head: Reading,
    feet: Sequence[str],
    speeds: Sequence[float],
    rows_w: Sequence[float],
) -> list[dict[str, Any]]:
    out = []
    for w in rows_w:
        for f in feet:
            sinking = runs.sinking(head, f, w)
            for v in speeds:
                m = runs.numbers[runs.key(head, f, v, w)]  # every headline run was made
                ratio = -m["min_ns"] / m["peak_ns"] if m["peak_ns"] > 0 else 0.0
                # each column's number by the column's name up to its unit
                numbers = m | {"peak_normalized_sz": m["peak_ns"], "min_normalized_sz": m["min_ns"]}
                numbers |= {"sinking": sinking, "normalized_suction_ratio": ratio}
                row = {"foot": f, "speed [m/s]": float(v), "water_content": head.label(w)}
                out.append(row | {c: numbers[c.split(" ")[0]] for c in SUMMARY_COLUMNS[3:]})
    return out


def write_rows(path: Path, rows: list[dict[str, Any]], columns: Sequence[str]) -> None:
    """Write ``rows`` to the CSV file ``path`` under ``columns``, floats to 6 digits."""
    with open(path, "w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=list(columns))
        wr.writeheader()
        for r in rows:
            wr.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def read_summary(path: str | Path) -> list[dict[str, Any]]:
    """Read a ``summary.csv`` written by :func:`reproduce` (numbers as floats)."""
    with open(path, newline="") as fh:
        return [
            {k: (v if k == "foot" else float(v)) for k, v in r.items()} for r in csv.DictReader(fh)
        ]
