"""Every foot on the same mud: the biped's walk metrics side by side, with the paper's claims
(``mudrft walk --compare``, D69a)."""

from __future__ import annotations

import csv
import math
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..feet import by_name
from ..io.atomic import json_text

if TYPE_CHECKING:
    from ..parameters.base import Mud
    from ..terrains import MudTerrain

__all__ = [
    "COMPARE_COLUMNS", "FEET", "UNDETERMINED", "compare_claims", "compare_feet", "write_compare",
]  # fmt: skip

#: The feet compared, by :func:`mudrft.feet.by_name`.
FEET = ("flat", "semi-cylinder", "semi-sphere", "morphing")
#: Columns of ``compare.csv`` (keys of the walk summary), with units.
COMPARE_COLUMNS = (
    "foot", "fell", "distance [m]", "mean_speed [m/s]", "steps", "energy_per_step [J]",
    "absolute_work_per_step [J]", "mean_sinking [m]", "max_suction [N]", "max_suction_over_weight",
    "mean_slip [m]", "shank_in_mud_steps",
)  # fmt: skip
#: The paper's claims on the feet: (morphing vs reference, suction lower by [%], energy
#: lower by [%]) from Fig. 13.
_FIG13 = (("flat", 32.0, 26.0), ("semi-cylinder", 57.0, 44.0))


def compare_feet(
    mud: Mud | MudTerrain,
    *,
    seconds: float = 10.0,
    dt: float = 1e-3,
    feet: Sequence[str] = FEET,
    progress: Callable[[str], None] | None = None,
    **walk_options: Any,
) -> dict[str, dict[str, Any]]:
    """Walk the biped with each foot on the same mud; ``{foot: WalkResult.summary}``.

    Parameters
    ----------
    mud : Mud or MudTerrain
        The mud, the same for every foot.
    seconds, dt : float, keyword-only
        Simulated time and physics step [s].
    feet : sequence of str, keyword-only
        Foot names (:func:`mudrft.feet.by_name`).
    progress : callable or None, keyword-only
        Called with each foot's name before its walk.
    **walk_options
        Passed to :func:`~mudrft.integrations.walk.walk`.
    """
    from .walk import walk

    out = {}
    for name in feet:
        if progress is not None:
            progress(name)
        out[name] = walk(by_name(name), mud, seconds=seconds, dt=dt, **walk_options).summary
    return out


def _reduction(a: float, b: float) -> float:
    """How much lower ``a`` is than ``b`` [%]."""
    return (1.0 - a / b) * 100.0 if b > 0 and math.isfinite(a) and math.isfinite(b) else math.nan


#: The verdict of a claim whose numbers are undefined (no complete gait step).
UNDETERMINED = "undetermined"


def _finite(*values: float) -> bool:
    return all(math.isfinite(v) for v in values)


def compare_claims(summaries: dict[str, dict[str, Any]]) -> list[dict[str, str]]:
    """The paper's claims on the feet beside the walking results (the paper's are plate and
    gait experiments, Sec. IV-B, Figs. 12-13: the verdict is about direction and size).

    One dict per claim with ``claim``, ``paper``, ``mudrft`` and ``verdict``: ``agrees``
    (same ordering, or a reduction within 15 points of the paper's), ``same direction``,
    ``differs``, or ``undetermined`` (a walk too short for one complete gait step).
    """
    rows: list[dict[str, str]] = []

    def add(claim: str, paper: str, mudrft: str, verdict: str) -> None:
        rows.append({"claim": claim, "paper": paper, "mudrft": mudrft, "verdict": verdict})

    if "morphing" in summaries:
        m = summaries["morphing"]
        for ref, ps, pe in _FIG13:
            if ref not in summaries:
                continue
            r = summaries[ref]
            ds = _reduction(m["max_suction [N]"], r["max_suction [N]"])
            de = _reduction(m["energy_per_step [J]"], r["energy_per_step [J]"])
            close = abs(ds - ps) <= 15 and abs(de - pe) <= 15
            same = ds > 0 and de > 0
            verdict = "agrees" if close else ("same direction" if same else "differs")
            add(
                f"morphing foot: less suction and energy than the {ref} foot (Fig. 13)",
                f"suction {ps:.0f} % lower, energy {pe:.0f} % lower",
                f"suction {ds:.0f} % lower, energy {de:.0f} % lower",
                verdict if _finite(ds, de) else UNDETERMINED,
            )
        sink = {f: s["mean_sinking [m]"] for f, s in summaries.items()}
        verdict = "agrees" if min(sink, key=lambda f: sink[f]) == "morphing" else "differs"
        add(
            "the morphing foot sinks least (Fig. 12)",
            "morphing sinks least",
            ", ".join(f"{f} {1e3 * v:.1f} mm" for f, v in sink.items()),
            verdict if _finite(*sink.values()) else UNDETERMINED,
        )
    fixed = [f for f in ("flat", "semi-cylinder", "semi-sphere") if f in summaries]
    if len(fixed) == 3:
        suc = {f: summaries[f]["max_suction [N]"] for f in fixed}
        order = sorted(fixed, key=lambda f: -suc[f])
        add(
            "flat foot: largest suction, semi-sphere: least (Sec. IV-B)",
            "flat > semi-cylinder > semi-sphere",
            " > ".join(f"{f} {suc[f]:.0f} N" for f in order),
            "agrees" if order[0] == "flat" and order[-1] == "semi-sphere" else "differs",
        )
    return rows


def write_compare(
    directory: Path, summaries: dict[str, dict[str, Any]], *, mud_name: str = ""
) -> list[Path]:
    """Write ``compare.csv``, ``claims.csv``, ``compare.json`` and ``compare.png`` in a
    directory; their paths.

    Parameters
    ----------
    directory : Path
        Existing directory.
    summaries : dict
        From :func:`compare_feet`.
    mud_name : str, keyword-only
        Shown in the figure's title.
    """
    d = Path(directory)
    claims = compare_claims(summaries)
    paths = [d / "compare.csv", d / "claims.csv", d / "compare.json", d / "compare.png"]
    with open(paths[0], "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(COMPARE_COLUMNS)
        for foot, s in summaries.items():
            w.writerow([foot] + [s.get(c) for c in COMPARE_COLUMNS[1:]])
    with open(paths[1], "w", newline="") as fh:
        dw = csv.DictWriter(fh, fieldnames=("claim", "paper", "mudrft", "verdict"))
        dw.writeheader()
        dw.writerows(claims)
    paths[2].write_text(json_text({"feet": summaries, "claims": claims}))
    _plot(paths[3], summaries, claims, mud_name)
    return paths


def _plot(
    path: Path, summaries: dict[str, dict[str, Any]], claims: list[dict[str, str]], title: str
) -> None:
    from ..plotting import require_matplotlib

    plt = require_matplotlib()

    feet = list(summaries)
    panels = (
        ("energy_per_step [J]", 1.0, "positive joint work\nper step [J]"),
        ("absolute_work_per_step [J]", 1.0, "absolute joint work\nper step [J]"),
        ("mean_sinking [m]", 1e3, "stance sinking [mm]"),
        ("max_suction_over_weight", 1.0, "max suction /\nbody weight [-]"),
        ("mean_slip [m]", 1e3, "stance slip\nper step [mm]"),
    )
    fig, ax = plt.subplots(1, len(panels) + 1, figsize=(17, 4.2))
    colors = [f"C{i}" for i in range(len(feet))]
    for a, (key, scale, label) in zip(ax, panels, strict=False):
        vals = [scale * float(summaries[f].get(key, math.nan)) for f in feet]
        a.bar(range(len(feet)), vals, color=colors)
        a.set_xticks(range(len(feet)), feet, rotation=30, ha="right", fontsize=8)
        a.set_ylabel(label)
    ax[-1].axis("off")
    text = "\n\n".join(
        f"{c['claim']}\npaper: {c['paper']}\nmudrft: {c['mudrft']}\n-> {c['verdict']}"
        for c in claims
    )
    ax[-1].text(0.0, 1.0, text, va="top", ha="left", fontsize=7, wrap=True)
    fig.suptitle(f"biped walking in mud, every foot on the same mud {title}".strip(), fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
