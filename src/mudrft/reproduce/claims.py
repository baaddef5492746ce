"""The paper's nine comparative claims, each evaluated on the quantity the paper plots.

:data:`CLAIMS` lists them with the figure or section they come from. :func:`evaluate`
returns one :class:`Cell` per claim for a reading: the paper's value, mudrft's number
and a verdict. Verdicts: ``agrees``; ``partly`` and ``differs`` (not reproduced);
``not evaluated`` when the runs it needs were not asked for. Tolerances are fixed here,
before any reading is evaluated.
"""

from __future__ import annotations

import functools
import itertools
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from ..feet import by_name
from ..feet.base import Foot
from .readings import Reading

#: Tolerance on the paper's percentages [percentage points]: its numbers come from three
#: trials with visible scatter (Table II: relative RMSEs of 4-18 %).
PCT_TOL = 10.0
#: "Almost as large as": suction / support within 100 +- 25 %.
RATIO_TOL = 25.0
#: Speed spread of the peak normalized stress [%]: "did not change" below 15 %, partly below 30 %.
SPEED_AGREE, SPEED_PARTLY = 15.0, 30.0

AGREES = "agrees"
NOT_EVALUATED = "not evaluated"

FIXED = ("flat", "semi-cylinder", "semi-sphere")
#: The morphing-foot reductions of Sec. IV-B (Fig. 13): foot -> (suction, energy) [%].
REDUCTIONS = {"semi-cylinder": (57.0, 44.0), "flat": (32.0, 26.0)}
#: The semi-cylinder's suction over the flat foot's that the two reductions need together
#: [-]: s_m = 0.43 s_c = 0.68 s_f.
REQUIRED_RATIO = (1 - REDUCTIONS["flat"][0] / 100) / (1 - REDUCTIONS["semi-cylinder"][0] / 100)
#: Load for the sinking depth and the load-carrying stance [N]: half the weight of a 10 kg
#: biped on one foot (decision D13).
LOAD = 49.0


@dataclass(frozen=True)
class Claim:
    """One comparative claim of the paper: its ``key`` (``claims.csv``), ``text`` (close to
    the paper's words, with its source), the ``paper``'s value, and the ``quantity``
    mudrft compares."""

    key: str
    text: str
    paper: str
    quantity: str


@dataclass(frozen=True)
class Cell:
    """One claim under one reading: ``claims.csv`` row."""

    claim: str
    reading: str
    paper: str
    mudrft: str
    verdict: str
    short: str = ""


_VS = (
    "max suction force of one gait cycle in two experiments: the gait at the reading's "
    "stance, and a load-carrying stance (each foot's gait at its own static depth under "
    f"{LOAD:g} N, as a walking robot's feet carry its weight); agrees within "
    f"+-{PCT_TOL:g} points in either. The energy is given, not compared: Fig. 13's is the "
    "whole robot's joint energy while walking"
)

CLAIMS: tuple[Claim, ...] = (
    Claim(
        "shape-order",
        "Flat foot gives the largest normalized vertical resistance, then semi-cylindrical, "
        "then semi-spherical (Sec. IV-B, Fig. 10a)",
        "flat > semi-cylinder > semi-sphere",
        "peak F_z/A_z over the cycle (Fig. 10 plots force over cross-section area)",
    ),
    Claim(
        "suction-order",
        "Flat foot suffers the largest suction force, semi-spherical the least (Sec. IV-B)",
        "flat largest, semi-sphere least",
        "max suction force [N] (the text says 'suction force'; Fig. 13a compares it too)",
    ),
    Claim(
        "speed",
        "Intrusion speed does not change the resistance (Sec. IV-B, Fig. 10b)",
        "no change",
        f"spread (max - min)/mean of peak F_z/A_z over the speeds, each fixed foot; agrees "
        f"below {SPEED_AGREE:g} %, partly below {SPEED_PARTLY:g} %",
    ),
    Claim(
        "water-content",
        "Mud strength falls as water content rises (Sec. IV-B, Fig. 10c)",
        "falls",
        "peak F_z/A_z of each fixed foot over the three table rows",
    ),
    Claim(
        "fixed-suction-ratio",
        "For the fixed feet the suction is almost as large as the support (Sec. IV-B, Fig. 11c)",
        "~100 %",
        f"|min F_z/A_z| / max F_z/A_z (Fig. 11c plots the stress), each fixed foot, within "
        f"100 +- {RATIO_TOL:g} %",
    ),
    Claim(
        "morphing-suction-ratio",
        "The morphing foot's suction is only about 40 % of its intrusion resistance "
        "(Sec. IV-B, Fig. 11c)",
        "40 %",
        "max suction / peak support: the morphing foot's stress is its force over its whole "
        "spread footprint (D38), so the force ratio (over the part of it in the mud, not 40 % "
        f"either: docs/model.md Sec. 12); within +-{PCT_TOL:g} points",
    ),
    Claim(
        "morphing-vs-semi-cylinder",
        "Morphing foot: suction 57 % and energy 44 % lower than the semi-cylindrical foot "
        "(Sec. IV-B, Fig. 13, the walking tests)",
        "suction -57 %, energy -44 %",
        _VS,
    ),
    Claim(
        "morphing-vs-flat",
        "Morphing foot: suction 32 % and energy 26 % lower than the flat foot (Sec. IV-B, "
        "Fig. 13, the walking tests)",
        "suction -32 %, energy -26 %",
        _VS,
    ),
    Claim(
        "sinking",
        "The morphing foot sinks least (Sec. IV-B, Fig. 12)",
        "morphing least",
        f"depth where a slowly applied {LOAD:g} N (half the weight of a 10 kg biped; the "
        "paper gives no load, D13) meets the relaxed mud's support (static_sinking, the limit a ramped "
        "load creeps to)",
    ),
)


def shape_factor(foot: Foot, depth: float) -> float:
    """Normalized vertical force of ``foot`` under a uniform unit stress [-].

    :math:`F_z/A_z` at tip depth ``depth`` [m] when every channel stress is 1 Pa: the
    factor that the closed forms (eqs. 12, 13c, 14b, with errata E20-E21) put between the
    stress at the tip's depth and the normalized stress the paper's Fig. 10 plots. The flat
    foot's is 1.

    Examples
    --------
    >>> from mudrft.feet import Flat
    >>> shape_factor(Flat(), 0.02)
    1.0
    """
    f = foot.force(depth, [1.0, 1.0, 1.0], 0.0)[2]
    return float(f / foot.projected_areas(depth)[2])


def shape_crossovers(a: Foot, b: Foot, *, points: int = 400) -> list[float]:
    """Depths [m] where the shape factors of feet ``a`` and ``b`` cross, between 0 and
    the lower of their heights: sign changes on ``points`` depths, refined with
    :func:`scipy.optimize.brentq` to 1e-9 m."""
    from scipy.optimize import brentq

    def gap(d: float) -> float:
        return shape_factor(a, d) - shape_factor(b, d)

    top = min(float(getattr(a, "height", 1.0)), float(getattr(b, "height", 1.0)))
    grid = np.linspace(top / points, top, points)
    diff = np.array([gap(d) for d in grid])
    cuts = np.flatnonzero(np.sign(diff[:-1]) * np.sign(diff[1:]) < 0)
    return [float(brentq(gap, grid[i], grid[i + 1], xtol=1e-9)) for i in cuts]


@functools.lru_cache(maxsize=1)
def _paper_feet() -> tuple[dict[str, Foot], tuple[float, ...]]:
    """The paper's three fixed feet and where the curved feet's shape factors cross [m]."""
    feet = {f: by_name(f) for f in FIXED}
    return feet, tuple(shape_crossovers(feet["semi-cylinder"], feet["semi-sphere"]))


def _shape_argument(fixed: dict[str, dict[str, float]]) -> str:
    """The curved feet's shape factors at the peaks' depths and where they cross (empty
    when the runs did not record the peaks' depths)."""
    if not all("peak_ns_depth" in m for m in fixed.values()):
        return ""
    feet, cross = _paper_feet()
    at = {f: fixed[f]["peak_ns_depth"] for f in FIXED}
    depths = ", ".join(f"{at[f] * 1e3:.1f}" for f in FIXED)
    factors = "/".join(f"{shape_factor(feet[f], at[f]):.3f}" for f in FIXED)
    text = (
        f"; at the peaks ({depths} mm deep) a uniform stress gives F_z/A_z = {factors} of it "
        "(eqs. 12, 13c, 14b; E20-E21)"
    )
    if cross:
        crossings = ", ".join(f"{z * 1e3:.1f}" for z in cross)
        text += (
            f", and the semi-sphere's factor passes the semi-cylinder's at {crossings} mm: at "
            "equal stress the paper's order needs the peaks shallower"
        )
    return text


def medium_speed(speeds: Sequence[float]) -> float:
    """The speed of the claims [m/s]: the one nearest the paper's medium 0.2 m/s."""
    return min(speeds, key=lambda s: abs(s - 0.2))


def evaluate(
    reading: Reading,
    metrics: Callable[[str, float, float], dict[str, float] | None],
    sinking: Callable[[str, float], float | None],
    *,
    feet: Sequence[str],
    speeds: Sequence[float],
    rows: Sequence[float],
    loaded: Callable[[str], dict[str, float] | None] | None = None,
) -> list[Cell]:
    """Evaluate the nine claims under ``reading``; one :class:`Cell` per claim.

    Parameters
    ----------
    reading : Reading
        The reading.
    metrics : callable
        ``metrics(foot, speed, row)``: the gait run's numbers (``peak_support``,
        ``max_suction``, ``energy`` [N, J], ``peak_ns``, ``min_ns`` [Pa]), or None if not run.
    sinking : callable
        ``sinking(foot, row)``: sinking depth under :data:`LOAD` [m], or None.
    feet, speeds, rows : sequence, keyword-only
        The feet, gait speeds [m/s] and printed table rows [-] that were run.
    loaded : callable, optional, keyword-only
        ``loaded(foot)``: the numbers (``max_suction`` [N], ``max_depth`` [m]) of the
        load-carrying stance, the gait at the foot's own static depth under :data:`LOAD`
        (medium speed, the reading's "25 %" row), or None.
    """
    v = medium_speed(speeds)
    w = reading.row(0.25)  # the reading's "25 %" mud
    cells: list[Cell] = []

    def cell(key: str, mudrft: str, verdict: str, short: str = "") -> None:
        paper = next(c.paper for c in CLAIMS if c.key == key)
        cells.append(Cell(key, reading.key, paper, mudrft, verdict, short or mudrft))

    def skip(key: str, needs: str) -> None:
        cell(key, f"{NOT_EVALUATED}: needs {needs}", NOT_EVALUATED)

    def at(foot: str, speed: float = v, row: float = w) -> dict[str, float] | None:
        return metrics(foot, speed, row) if foot in feet else None

    base = {f: at(f) for f in (*FIXED, "morphing")}
    fixed = {f: m for f, m in base.items() if f in FIXED and m is not None}
    all_fixed = len(fixed) == len(FIXED)
    missing = "the three fixed feet at W = 25 %"

    # shape-order (Fig. 10a)
    if all_fixed:
        ns = {f: fixed[f]["peak_ns"] for f in FIXED}
        text = ", ".join(f"{f} {ns[f] / 1e3:.1f} kPa" for f in FIXED) + _shape_argument(fixed)
        ok = ns["flat"] > ns["semi-cylinder"] > ns["semi-sphere"]
        short = "/".join(f"{ns[f] / 1e3:.1f}" for f in FIXED) + " kPa"
        cell("shape-order", text, _ok(ok), short)
        su = {f: fixed[f]["max_suction"] for f in FIXED}
        ok = max(su, key=su.__getitem__) == "flat" and min(su, key=su.__getitem__) == "semi-sphere"
        text = ", ".join(f"{f} {su[f]:.0f} N" for f in FIXED)
        # the sentence stands in the paragraph on Fig. 10a, which plots F_z/A_z: the same
        # order by stress, for the reader to judge (the verdict is on the force, as printed)
        ss = {f: -fixed[f]["min_ns"] for f in FIXED}
        stresses = ", ".join(f"{f} {ss[f] / 1e3:.2f} kPa" for f in FIXED)
        text += (
            f"; by suction stress |min F_z/A_z| (Fig. 10a): {stresses}, the "
            f"{max(ss, key=ss.__getitem__)} largest, the {min(ss, key=ss.__getitem__)} least"
        )
        cell("suction-order", text, _ok(ok), "/".join(f"{su[f]:.0f}" for f in FIXED) + " N")
    else:
        skip("shape-order", missing)
        skip("suction-order", missing)

    # speed (Fig. 10b)
    spreads = {}
    for f in FIXED:
        vals = [at(f, s) for s in speeds]
        if len(speeds) > 1 and all(m is not None for m in vals):
            pk = [m["peak_ns"] for m in vals if m is not None]
            spreads[f] = (max(pk) - min(pk)) / (sum(pk) / len(pk)) * 100
    if len(spreads) == len(FIXED):
        worst = max(spreads.values())
        verdict = AGREES if worst < SPEED_AGREE else "partly" if worst < SPEED_PARTLY else "differs"
        text = "spread " + ", ".join(f"{f} {s:.0f} %" for f, s in spreads.items())
        cell("speed", text, verdict, f"spread <= {worst:.0f} %")
    else:
        skip("speed", "two speeds or more")

    # water content (Fig. 10c)
    order = sorted(rows)
    series = {f: [at(f, v, r) for r in order] for f in FIXED}
    if len(order) > 1 and all(m is not None for ms in series.values() for m in ms):
        parts, ok = [], True
        for f, ms in series.items():
            pk = [m["peak_ns"] for m in ms if m is not None]
            ok &= all(a > b for a, b in itertools.pairwise(pk))
            parts.append(f"{f}: " + " > ".join(f"{x / 1e3:.1f}" for x in pk))
        labels = "/".join(f"{reading.label(r) * 100:g}" for r in order)
        text = f"W = {labels} %: " + "; ".join(parts) + " kPa"
        short = "falls for every foot" if ok else "does not fall for every foot"
        cell("water-content", text, _ok(ok), short)
    else:
        skip("water-content", "two rows or more")

    # fixed-suction-ratio (Fig. 11c)
    if all_fixed:
        ratios = {f: -m["min_ns"] / m["peak_ns"] * 100 for f, m in fixed.items()}
        ok = all(abs(r - 100) <= RATIO_TOL for r in ratios.values())
        text = ", ".join(f"{f} {r:.0f} %" for f, r in ratios.items())
        if all("max_suction" in m and m.get("peak_support") for m in fixed.values()):
            # the same ratio by force (over a constant area): the curved feet's submerged
            # area shrinks as they leave the mud, so the verdict rests on the stress
            by_force = [fixed[f]["max_suction"] / fixed[f]["peak_support"] * 100 for f in FIXED]
            forces = "/".join(f"{r:.0f}" for r in by_force)
            text += f" of the peak stress; by force {forces} % (docs/model.md Sec. 12)"
        short = "/".join(f"{r:.0f}" for r in ratios.values()) + " %"
        cell("fixed-suction-ratio", text, _ok(ok), short)
    else:
        skip("fixed-suction-ratio", missing)

    morph = base["morphing"]
    if morph is not None:
        r = morph["max_suction"] / morph["peak_support"] * 100  # over its whole footprint (D38)
        text = f"{r:.0f} %"
        if morph.get("peak_ns"):  # over its spread pads' part in the mud at each depth
            by_stress = -morph["min_ns"] / morph["peak_ns"] * 100
            text += f" (over the part of its spread pads in the mud: {by_stress:.0f} %)"
        cell("morphing-suction-ratio", text, _ok(abs(r - 40) <= PCT_TOL), f"{r:.0f} %")
    else:
        skip("morphing-suction-ratio", "the morphing foot")

    # morphing-vs-* (Fig. 13, the walking tests): the gait and the load-carrying stance
    held = {f: loaded(f) if loaded else None for f in ("flat", "semi-cylinder", "morphing")}
    for ref in ("semi-cylinder", "flat"):
        if morph is not None and "flat" in fixed and "semi-cylinder" in fixed:
            cell(f"morphing-vs-{ref}", *_versus(ref, morph, fixed, held))
        else:
            skip(f"morphing-vs-{ref}", "the morphing, flat and semi-cylindrical feet")

    # sinking (Fig. 12)
    sink = {f: sinking(f, w) for f in feet}
    if "morphing" in feet and len(feet) > 1 and all(s is not None for s in sink.values()):
        depth = {f: s for f, s in sink.items() if s is not None}
        ok = depth["morphing"] <= min(depth.values())
        text = ", ".join(f"{f} {d * 1e3:.1f} mm" for f, d in depth.items())
        others = min(d for f, d in depth.items() if f != "morphing")
        short = f"morphing {depth['morphing'] * 1e3:.1f}, others >= {others * 1e3:.1f} mm"
        cell("sinking", text, _ok(ok), short)
    else:
        skip("sinking", "the morphing foot and another")
    return cells


def _ok(ok: bool) -> str:
    return AGREES if ok else "differs"


def _versus(
    ref: str,
    morph: dict[str, float],
    fixed: dict[str, dict[str, float]],
    held: dict[str, dict[str, float] | None],
) -> tuple[str, str, str]:
    """``(text, verdict, short)`` of a morphing-vs-``ref`` claim, in the gait and, where
    run, with a load-carrying stance."""
    target = REDUCTIONS[ref][0]
    ratio = fixed["semi-cylinder"]["max_suction"] / fixed["flat"]["max_suction"]
    ds = (1 - morph["max_suction"] / fixed[ref]["max_suction"]) * 100
    de = (1 - morph["energy"] / fixed[ref]["energy"]) * 100
    found = [ds]
    text = f"gait: suction {_change(ds)}, s_c/s_f = {ratio:.2f}"
    short = f"{_change(ds)}, s_c/s_f {ratio:.2f}"
    if all(m is not None for m in held.values()):
        h = {f: m for f, m in held.items() if m is not None}
        dl = (1 - h["morphing"]["max_suction"] / h[ref]["max_suction"]) * 100
        ratio_l = h["semi-cylinder"]["max_suction"] / h["flat"]["max_suction"]
        found.append(dl)
        depths = ", ".join(f"{f} {m['max_depth'] * 1e3:.1f}" for f, m in h.items())
        text += (
            f"; load-carrying stance ({depths} mm): suction {_change(dl)}, s_c/s_f = {ratio_l:.2f}"
        )
        short += f"; loaded {_change(dl)}, {ratio_l:.2f}"
    text += (
        f". Both percentages together need s_c/s_f = {REQUIRED_RATIO:.2f}. Energy in the "
        f"gait {_change(de)} (foot-on-mud work; Fig. 13's is the whole robot's joint energy "
        "while walking, not compared)"
    )
    return text, _ok(any(abs(x - target) <= PCT_TOL for x in found)), short


def _change(reduction: float) -> str:
    """A reduction [%] as the signed change the paper prints: 71 -> '-71 %', -5 -> '+5 %'."""
    pct = round(-reduction)
    return f"{pct:+d} %" if pct else "0 %"
