"""``mudrft reproduce``: the paper's comparisons on the built-in parameter sets and feet.

Runs every foot (flat, semi-cylinder, semi-sphere, morphing) through one stepping
cycle (:func:`mudrft.gait`) at the paper's three gait speeds and the tabulated water
contents, plus a load-controlled settle for the sinking depth, and writes

* ``summary.csv``: one row per foot x speed x water content (columns in DESIGN.md);
* figures like the paper's Figs. 9, 10, 12 and 13 (PNG);
* ``report.md``: each result beside the paper's claim, with a plain verdict.
"""

from __future__ import annotations

import csv
import time as _time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ._progress import logger, make_progress
from ._validation import MudrftError
from .parameters import paper_mud
from .simulation import LoadControl, Result, simulate
from .trajectories import GAIT_SPEEDS, gait

__all__ = ["FEET", "LOAD", "SUMMARY_COLUMNS", "reproduce"]

FEET = ("flat", "semi-cylinder", "semi-sphere", "morphing")
WATER_CONTENTS = (0.25, 0.35, 0.45)
#: Load used for the sinking depth [N]: half the weight of a 10 kg biped on one foot (decision D13).
LOAD = 49.0

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
)


def _say(msg: str, quiet: bool) -> None:
    """A progress note on the ``mudrft`` logger, shown as ``progress=True`` shows progress."""
    if not quiet:
        make_progress(True, "reproduce")  # a stderr handler if logging is not configured
        logger.info("%s", msg)


def _prepare_out(out: Path, force: bool) -> None:
    if out.exists() and not out.is_dir():
        raise MudrftError(f"--out {str(out)!r} exists and is not a directory")
    if (out / "summary.csv").exists() and not force:
        raise MudrftError(
            f"--out {str(out)!r} already holds results (summary.csv); pass --force to overwrite them"
        )
    try:
        out.mkdir(parents=True, exist_ok=True)
        probe = out / ".mudrft_write_test"
        probe.write_text("")
        probe.unlink()
    except OSError as exc:
        raise MudrftError(f"--out {str(out)!r} is not writable: {exc.strerror or exc}") from exc


def _make_foot(name: str) -> Any:
    from .feet import by_name

    return by_name(name)


def reproduce(
    out: str | Path,
    *,
    force: bool = False,
    feet: Sequence[str] = FEET,
    speeds: Sequence[float] = tuple(GAIT_SPEEDS.values()),
    water_contents: Sequence[float] = WATER_CONTENTS,
    figures: bool = True,
    quiet: bool = False,
    dt: float = 1e-3,
) -> list[dict[str, Any]]:
    """Reproduce the paper's foot comparisons and write results to ``out``.

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
        Water contents [-] (tabulated range 0.25-0.45).
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
    _prepare_out(outp, force)
    for s in speeds:
        if not (isinstance(s, (int, float)) and s > 0):
            raise MudrftError(f"speeds must be > 0 m/s, got {s!r}")
    t0 = _time.perf_counter()
    feet_objs = {name: _make_foot(name) for name in feet}
    rows: list[dict[str, Any]] = []
    runs: dict[tuple[str, float, float], Result] = {}
    total = len(feet) * len(speeds) * len(water_contents)
    i = 0
    for w in water_contents:
        mud = paper_mud(w)
        for name, foot in feet_objs.items():
            settle = simulate(foot, mud, LoadControl(weight=LOAD, duration=4.0, dt=2e-3))
            sinking = float(settle.depth[-1])
            for v in speeds:
                i += 1
                _say(f"[{i:2d}/{total}] {name:13s} speed {v:.2f} m/s  W = {w * 100:.0f} %", quiet)
                res = simulate(foot, mud, gait(v, dt=dt))
                runs[(name, float(v), float(w))] = res
                m = res.metrics()
                ns = res.normalized_stress() if res.areas is not None else np.zeros_like(res.force)
                rows.append(
                    {
                        "foot": name,
                        "speed [m/s]": float(v),
                        "water_content": float(w),
                        "peak_support [N]": m["peak_support"],
                        "max_suction [N]": m["max_suction"],
                        "impulse_x [N s]": m["impulse_x"],
                        "impulse_y [N s]": m["impulse_y"],
                        "impulse_z [N s]": m["impulse_z"],
                        "energy [J]": m["energy"],
                        "sinking [m]": sinking,
                        "suction_ratio": m["suction_ratio"],
                        "peak_normalized_sz [Pa]": float(ns[:, 2].max()),
                        "min_normalized_sz [Pa]": float(ns[:, 2].min()),
                    }
                )
    with open(outp / "summary.csv", "w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=list(SUMMARY_COLUMNS))
        wr.writeheader()
        for r in rows:
            wr.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    _say(f"wrote {outp / 'summary.csv'} ({len(rows)} rows)", quiet)
    if figures:
        from .reproduce_figures import make_figures

        for path in make_figures(
            outp,
            runs,
            rows,
            feet=list(feet),
            speeds=list(speeds),
            water_contents=list(water_contents),
        ):
            _say(f"wrote {path}", quiet)
    # sensitivity to decision D6: the same fixed feet without the acceleration term
    sens = _acceleration_sensitivity(feet_objs, speeds, quiet=quiet, dt=dt)
    from .reproduce_report import write_report

    rep = write_report(
        outp / "report.md",
        rows,
        sensitivity=sens,
        feet=list(feet),
        speeds=list(speeds),
        water_contents=list(water_contents),
    )
    _say(f"wrote {rep}", quiet)
    _say(f"done in {_time.perf_counter() - t0:.1f} s", quiet)
    return rows


def _acceleration_sensitivity(
    feet_objs: dict[str, Any], speeds: Sequence[float], *, quiet: bool, dt: float
) -> dict[str, dict[str, float]]:
    """Speed spread of the normalized resistance and suction ratio without the gamma-ddot term."""
    from .terrains import MudTerrain

    terrain = MudTerrain(paper_mud(0.25), acceleration=False)
    out: dict[str, dict[str, float]] = {}
    for name, foot in feet_objs.items():
        if name == "morphing":
            continue
        _say(f"       {name:13s} sensitivity run without the acceleration term (D6)", quiet)
        peaks, ratios = [], []
        for v in speeds:
            res = simulate(foot, terrain, gait(v, dt=dt))
            peaks.append(float(res.normalized_stress()[:, 2].max()))
            ratios.append(res.metrics()["suction_ratio"])
        pk = np.array(peaks)
        out[name] = {
            "speed_spread_pct": float((pk.max() - pk.min()) / pk.mean() * 100),
            "suction_ratio_pct": float(np.mean(ratios) * 100),
        }
    return out


def read_summary(path: str | Path) -> list[dict[str, Any]]:
    """Read a ``summary.csv`` written by :func:`reproduce` (numbers as floats)."""
    with open(path, newline="") as fh:
        out = []
        for r in csv.DictReader(fh):
            out.append({k: (v if k == "foot" else float(v)) for k, v in r.items()})
    return out


ProgressFn = Callable[[str], None]
