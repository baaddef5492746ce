"""``mudrft reproduce``: the runs, the summary, the matrix of readings x claims.

Runs every foot (flat, semi-cylinder, semi-sphere, morphing) through one stepping cycle
(:func:`mudrft.gait`) at the paper's three gait speeds and the tabulated water contents
under the headline reading (:data:`~mudrft.reproduce.readings.HEADLINE`), then the runs
each other reading needs for the nine claims (runs are shared where two readings give the
same physics), and writes

* ``summary.csv``: the headline reading, one row per foot x speed x water content
  (columns in DESIGN.md);
* ``claims.csv``: one row per claim and reading (``claim,reading,paper,mudrft,verdict``);
* ``report.md``: the headline's "N of 9 claims", the matrix and every reading's derivation;
* figures like the paper's Figs. 9, 10, 12 and 13 (PNG), for the headline reading.
"""

from __future__ import annotations

import csv
import functools
import time as _time
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeAlias

import numpy as np

from .._progress import logger, make_progress
from .._validation import MudrftError
from ..feet import by_name
from ..simulation import Result, simulate, static_sinking
from ..trajectories import GAIT_SPEEDS, gait
from .claims import FIXED, Cell, evaluate
from .readings import READINGS, Reading

if TYPE_CHECKING:
    from ..feet.base import Foot

__all__ = [
    "FEET",
    "FIGURES",
    "LOAD",
    "SUMMARY_COLUMNS",
    "TABLES",
    "WATER_CONTENTS",
    "read_summary",
    "reproduce",
]

FEET = ("flat", "semi-cylinder", "semi-sphere", "morphing")
WATER_CONTENTS = (0.25, 0.35, 0.45)
#: Load used for the sinking depth [N]: half the weight of a 10 kg biped on one foot (decision D13).
LOAD = 49.0

#: The tables :func:`reproduce` writes in its directory.
TABLES = ("summary.csv", "claims.csv", "report.md")
#: The figures it writes there (``figures=True``).
FIGURES = (
    "fig09_forces.png",
    "fig10_normalized.png",
    "fig12_hysteresis.png",
    "fig13_suction_energy.png",
)

SUMMARY_COLUMNS = (
    "foot",
    "speed [m/s]",
    "water_content",
    "peak_support [N]",
    "max_suction [N]",
    "impulse_x [N s]",
    "impulse_y [N s]",
    "impulse_z [N s]",
    "energy [J]",
    "sinking [m]",
    "suction_ratio",
    "peak_normalized_sz [Pa]",
    "min_normalized_sz [Pa]",
    "normalized_suction_ratio",
)


def _say(msg: str, quiet: bool) -> None:
    """A progress note on the ``mudrft`` logger, shown as ``progress=True`` shows progress."""
    if not quiet:
        make_progress(True, "reproduce")  # a stderr handler if logging is not configured
        logger.info("%s", msg)


def _prepare_out(out: Path, force: bool, names: Sequence[str]) -> None:
    """Check that ``out`` can take the files ``names``: every one that exists is refused
    without ``force`` (a report.md of one's own is not replaced because summary.csv is
    missing)."""
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


#: A gait run: (the reading's run key, foot, speed [m/s], table row).
RunKey: TypeAlias = tuple[tuple[object, ...], str, float, float]


class _Runs:
    """Gait runs and sinking depths, computed once and shared by every reading."""

    def __init__(self, feet: dict[str, Foot], dt: float) -> None:
        self.feet, self.dt = feet, dt
        self.results: dict[RunKey, Result] = {}
        self.numbers: dict[RunKey, dict[str, float]] = {}
        self._sinking: dict[tuple[str, float], float] = {}

    @staticmethod
    def key(reading: Reading, foot: str, speed: float, row: float) -> RunKey:
        return (reading.run_key, foot, float(speed), float(row))

    def run(self, reading: Reading, foot: str, speed: float, row: float) -> None:
        res = simulate(
            self.feet[foot], reading.terrain(row), gait(speed, depth=reading.depth, dt=self.dt)
        )
        m = res.metrics()
        ns = res.normalized_stress()[:, 2] if res.areas is not None else np.zeros(len(res))
        m.update(
            peak_ns=float(ns.max()),
            min_ns=float(ns.min()),
            peak_ns_depth=float(res.depth[int(np.argmax(ns))]),
        )
        key = self.key(reading, foot, speed, row)
        self.results[key], self.numbers[key] = res, m

    def metrics(
        self, reading: Reading, foot: str, speed: float, row: float
    ) -> dict[str, float] | None:
        """The numbers of a run, or None if it was not run."""
        return self.numbers.get(self.key(reading, foot, speed, row))

    def sinking(self, reading: Reading, foot: str, row: float) -> float:
        """Sinking under :data:`LOAD` on the row's relaxed mud [m] (independent of the
        evaluation and the gait: the limit a ramped load creeps to, decision D13)."""
        key = (foot, float(row))
        if key not in self._sinking:
            self._sinking[key] = static_sinking(self.feet[foot], reading.mud(row), LOAD)
        return self._sinking[key]


def _plan(
    reading: Reading, feet: Sequence[str], speeds: Sequence[float], rows: Sequence[float]
) -> list[tuple[str, float, float]]:
    """The (foot, speed, row) runs the nine claims need under ``reading``."""
    v = min(speeds, key=lambda s: abs(s - 0.2))
    w = reading.row(0.25)
    if not any(abs(w - r) < 1e-9 for r in rows):
        return []
    fixed = [f for f in feet if f in FIXED]
    out = [(f, v, w) for f in feet]
    out += [(f, s, w) for f in fixed for s in speeds]
    out += [(f, v, r) for f in fixed for r in rows]
    return list(dict.fromkeys(out))


def reproduce(
    out: str | Path,
    *,
    force: bool = False,
    feet: Sequence[str] = FEET,
    speeds: Sequence[float] = tuple(GAIT_SPEEDS.values()),
    water_contents: Sequence[float] = WATER_CONTENTS,
    readings: Sequence[Reading] = READINGS,
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
        Readings of the matrix (:data:`~mudrft.reproduce.readings.READINGS`); the first is
        the headline, which also makes ``summary.csv`` and the figures.
    figures : bool, keyword-only
        Write the PNG figures (needs matplotlib).
    quiet : bool, keyword-only
        Do not print progress.
    dt : float, keyword-only
        Time step of the gait runs [s].

    Returns
    -------
    list of dict
        The rows of ``summary.csv``.
    """
    outp = Path(out)
    _prepare_out(outp, force, TABLES + (FIGURES if figures else ()))
    for s in speeds:
        if not (isinstance(s, (int, float)) and s > 0):
            raise MudrftError(f"speeds must be > 0 m/s, got {s!r}")
    if not readings:
        raise MudrftError("readings must name at least one reading (the headline)")
    t0 = _time.perf_counter()

    runs = _Runs({name: by_name(name) for name in feet}, dt)
    rows_w = [float(w) for w in water_contents]
    head = readings[0]
    tasks = [(head, f, float(v), w) for w in rows_w for f in feet for v in speeds]
    for rd in readings:
        tasks += [(rd, *t) for t in _plan(rd, feet, speeds, rows_w)]
    todo: dict[RunKey, tuple[Reading, str, float, float]] = {}
    for t in tasks:  # each physics once, in order, named by the first reading that needs it
        todo.setdefault(runs.key(*t), t)
    width = max(2, len(str(len(todo))))
    for i, (rd, f, v, w) in enumerate(todo.values(), 1):
        _say(
            f"[{i:{width}d}/{len(todo)}] {rd.key:17s} {f:13s} {v:.2f} m/s  "
            f"W = {rd.label(w) * 100:g} %",
            quiet,
        )
        runs.run(rd, f, v, w)
    rows = _summary_rows(runs, head, feet, speeds, rows_w)
    _write_summary(outp / "summary.csv", rows)
    _say(f"wrote {outp / 'summary.csv'} ({len(rows)} rows)", quiet)
    if figures:
        from .figures import make_figures

        head_runs = {
            (f, float(v), w): runs.results[runs.key(head, f, v, w)]
            for w in rows_w
            for f in feet
            for v in speeds
        }
        for path in make_figures(
            outp, head_runs, rows, feet=list(feet), speeds=list(speeds), water_contents=rows_w
        ):
            _say(f"wrote {path}", quiet)
    cells: dict[str, list[Cell]] = {}
    for rd in readings:
        cells[rd.key] = evaluate(
            rd,
            functools.partial(runs.metrics, rd),
            functools.partial(runs.sinking, rd),
            feet=list(feet),
            speeds=[float(s) for s in speeds],
            rows=rows_w,
        )
    from .report import write_claims_csv, write_report

    _say(f"wrote {write_claims_csv(outp / 'claims.csv', cells)}", quiet)
    _say(f"wrote {write_report(outp / 'report.md', cells, readings=list(readings))}", quiet)
    _say(f"done in {_time.perf_counter() - t0:.1f} s", quiet)
    return rows


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
                out.append(
                    {
                        "foot": f,
                        "speed [m/s]": float(v),
                        "water_content": head.label(w),
                        "peak_support [N]": m["peak_support"],
                        "max_suction [N]": m["max_suction"],
                        "impulse_x [N s]": m["impulse_x"],
                        "impulse_y [N s]": m["impulse_y"],
                        "impulse_z [N s]": m["impulse_z"],
                        "energy [J]": m["energy"],
                        "sinking [m]": sinking,
                        "suction_ratio": m["suction_ratio"],
                        "peak_normalized_sz [Pa]": m["peak_ns"],
                        "min_normalized_sz [Pa]": m["min_ns"],
                        "normalized_suction_ratio": -m["min_ns"] / m["peak_ns"]
                        if m["peak_ns"] > 0
                        else 0.0,
                    }
                )
    return out


def _write_summary(path: Path, rows: list[dict[str, Any]]) -> None:
    with open(path, "w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=list(SUMMARY_COLUMNS))
        wr.writeheader()
        for r in rows:
            wr.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def read_summary(path: str | Path) -> list[dict[str, Any]]:
    """Read a ``summary.csv`` written by :func:`reproduce` (numbers as floats)."""
    with open(path, newline="") as fh:
        out = []
        for r in csv.DictReader(fh):
            out.append({k: (v if k == "foot" else float(v)) for k, v in r.items()})
    return out
