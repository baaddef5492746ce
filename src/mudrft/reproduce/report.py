"""``report.md`` and ``claims.csv`` of ``mudrft reproduce``: the matrix of readings x claims."""

from __future__ import annotations

import csv
from collections.abc import Sequence
from pathlib import Path

from .claims import (
    CLAIMS,
    INCONSISTENT,
    PCT_TOL,
    RATIO_TOL,
    SPEED_AGREE,
    SPEED_PARTLY,
    Cell,
    count,
    suction_area_bound,
)
from .readings import Reading

__all__ = [
    "CLAIMS_COLUMNS",
    "claims_block",
    "headline_count",
    "write_claims_csv",
    "write_report",
]

#: Columns of ``claims.csv``: one row per claim and reading.
CLAIMS_COLUMNS = ("claim", "reading", "paper", "mudrft", "verdict", "summary", "headline")


def headline_count(cells: Sequence[Cell]) -> str:
    """The headline sentence: "N of 9 claims" with the inconsistent and failed ones."""
    n = count(cells)
    text = f"{n['agrees']} of {n['total']} claims reproduced"
    if n["inconsistent"]:
        text += (
            f"; {n['inconsistent']} inconsistent within the paper (not counted as failures of "
            "the model)"
        )
    text += f"; {n['failed']} not reproduced"
    if n["not evaluated"]:
        text += f"; {n['not evaluated']} not evaluated (runs not asked for)"
    return text


def write_claims_csv(path: Path, cells: dict[str, list[Cell]]) -> Path:
    """Write ``claims.csv`` (:data:`CLAIMS_COLUMNS`) and return its path."""
    first = next(iter(cells), None)
    with open(path, "w", newline="") as fh:
        wr = csv.writer(fh)
        wr.writerow(CLAIMS_COLUMNS)
        for key, row in cells.items():
            for c in row:
                wr.writerow(
                    [c.claim, c.reading, c.paper, c.mudrft, c.verdict, c.short, key == first]
                )
    return path


def _esc(text: str) -> str:
    return text.replace("|", "/")


def write_report(path: Path, cells: dict[str, list[Cell]], *, readings: list[Reading]) -> Path:
    """Write ``report.md``: headline, its claims, the inconsistency, the matrix, the readings."""
    head = readings[0]
    hc = cells[head.key]
    claims = {c.key: c for c in CLAIMS}
    lines = [
        "# mudrft reproduce: the paper's claims",
        "",
        "Model: Chen et al. (2026) as implemented by mudrft (decisions and errata in",
        "docs/model.md). These are model predictions on documented reconstructions (gait path,",
        "plate size, morphing-foot dimensions), not measurements: the paper's data are not public.",
        "",
        *_how_to_read(head),
        "",
        f"## Headline reading: {head.key}",
        "",
        f"**{head.key}**: {head.title}.",
        "",
        f"**{headline_count(hc)}.**",
        "",
        "| claim | the paper says | mudrft | verdict |",
        "|---|---|---|---|",
    ]
    for c in hc:
        lines.append(
            f"| {_esc(claims[c.claim].text)} | {_esc(c.paper)} | {_esc(c.mudrft)} | {c.verdict} |"
        )
    incon = [c for c in hc if c.verdict == INCONSISTENT]
    if incon:
        lines += [
            "",
            "## Two morphing-foot percentages contradict the paper's own suction ordering",
            "",
            "Sec. IV-B gives the morphing foot's suction as 57 % below the semi-cylindrical "
            "foot's and 32 % below the flat foot's, so s_m = 0.43 s_c = 0.68 s_f, which needs "
            "s_c / s_f = 0.68 / 0.43 = 1.58: the semi-cylindrical foot would suffer 58 % more "
            "suction than the flat foot. The same section says 'the flat foot ... suffered from "
            "the largest suction force', s_c / s_f < 1. That sentence describes Fig. 10a, "
            "which plots F_z/A_z; read as suction stress it still forbids 1.58: the flat "
            "foot's footprint A_f is constant, so s_c / s_f <= A_c / A_f <= "
            f"{suction_area_bound():.2f} (the semi-cylinder's cross-section at its full "
            "height). No model can meet the three claims; "
            "every reading below gives the flat foot the largest suction, by force and by "
            "stress (claim suction-order), and the cells "
            "give each run's s_c / s_f and what matching one percentage does to the other. "
            "Fig. 13's energies are the whole robot's joint energy while walking (Sec. IV-A: "
            "'joint torques were recorded to calculate the energy consumption during walking'; "
            "supplementary Sec. III-D), not the work of one foot on mud along a prescribed "
            "path, so they are not comparable with the energies here either.",
            "",
        ]
        for c in incon:
            lines.append(f"* {c.claim}: {_esc(c.mudrft)}.")
    lines += [
        "",
        "## Matrix: readings x claims",
        "",
        "Each cell: mudrft's number, then the verdict (feet in the order flat / semi-cylinder /",
        "semi-sphere). Numbers and full texts are in `claims.csv`.",
        "",
        "| claim | the paper says | "
        + " | ".join(rd.key + (" (headline)" if rd is head else "") for rd in readings)
        + " |",
        "|---|---|" + "---|" * len(readings),
    ]
    for i, claim in enumerate(CLAIMS):
        row = [f"{claim.key}", _esc(claim.paper)]
        for rd in readings:
            c = cells[rd.key][i]
            row.append(f"{_esc(c.short)}: **{c.verdict}**")
        lines.append("| " + " | ".join(row) + " |")
    lines.append(
        "| **reproduced** | | "
        + " | ".join(f"**{count(cells[rd.key])['agrees']} of 9**" for rd in readings)
        + " |"
    )
    lines += ["", "## The readings and where the paper supports them", ""]
    for rd in readings:
        lines.append(f"* **{rd.key}** ({headline_count(cells[rd.key])}): {rd.title}. ")
        lines.append(f"  {rd.derivation}")
    lines += [
        "",
        "## What each claim compares",
        "",
    ]
    for claim in CLAIMS:
        lines.append(f"* **{claim.key}**: {claim.text}. mudrft compares: {claim.quantity}.")
    lines += ["", *_files()]
    path.write_text("\n".join(lines))
    return path


def _how_to_read(head: Reading) -> list[str]:
    """What a reading, a verdict and the units are, for a reader without docs/model.md."""
    return [
        "## How to read this report",
        "",
        "* **Readings.** The paper leaves some choices open: how eqs. (3) and (5) are "
        "evaluated (its quasi-static solutions (9)-(11) or the ODEs themselves), when the clock "
        "of eq. (9) starts, how deep the foot goes in the stepping gait (the paper gives "
        "the gait speeds, not the path), and which water content each row of Tables S1-S2 "
        "is. A *reading* fixes each choice, citing the paper's text (section 'The readings' "
        f"below). The headline reading, **{head.key}**, is the paper's own evaluation: it was "
        "fixed from the text before any of its verdicts was computed and has not been "
        "changed since. Every other reading changes one choice of it (or restores mudrft's "
        "former defaults), so the matrix shows which choice decides which claim.",
        "* **Verdicts**, with tolerances fixed before any reading was evaluated: *agrees* "
        f"(orderings strictly met; the paper's percentages within +-{PCT_TOL:g} points; "
        f"'almost as large' within 100 +- {RATIO_TOL:g} %; 'did not change' a spread below "
        f"{SPEED_AGREE:g} %), *partly* (that spread below {SPEED_PARTLY:g} %), *differs* "
        "(not met), *inconsistent in the paper* (the two morphing-foot percentages, which "
        "contradict the paper's own suction ordering: not counted as failures of the "
        "model), *not evaluated* (the runs it needs were not asked for). No model parameter "
        "is tuned to any claim.",
        "* **Units.** Forces in N; energies in J, the work the foot does against the mud over "
        "one gait cycle; depths in mm; F_z/A_z in kPa is the vertical force over the foot's "
        "cross-section area in the mud at its current depth, the paper's normalised stress "
        "(Sec. IV-B; the morphing foot's over its spread footprint, D38). The claims are "
        "evaluated at the medium gait speed, 0.2 m/s, and W = 25 %, unless they vary them; "
        "a percentage change is the morphing foot's against the other foot's.",
        "* **References.** Sections, equations, figures and tables are the paper's (S: "
        "supplementary materials). Equation numbers are the manuscript's, as the "
        "supplementary materials cite them ('(9) in the manuscript'); the LaTeX source shows "
        "F_mud = integral of dF inline, so its own counter is one lower from there on (its "
        "(8)-(13) are (9)-(14) here). D and E numbers are mudrft's decisions and the "
        "paper's errata, in docs/model.md.",
    ]


def _files() -> list[str]:
    """The output files and the units of their columns."""
    return [
        "## Files",
        "",
        "* `summary.csv`: the headline reading, one row per foot x speed x water content. "
        "Columns: `foot`; `speed [m/s]`; `water_content` [-], a fraction (0.25 = 25 %); "
        "`peak_support [N]`; `max_suction [N]`, the magnitude of the most negative F_z; "
        "`impulse_x [N s]`, `impulse_y [N s]`, `impulse_z [N s]`; `energy [J]`; "
        "`sinking [m]`, under a slowly applied 49 N (claim sinking); `suction_ratio` [-], "
        "max_suction / peak_support; `peak_normalized_sz [Pa]` and `min_normalized_sz [Pa]`, "
        "the extremes of F_z/A_z; `normalized_suction_ratio` [-], their magnitudes' ratio.",
        "* `claims.csv`: one row per claim and reading. Columns: `claim`; `reading`; "
        "`paper`, what the paper says; `mudrft`, the run's numbers with their units; "
        "`verdict`; `summary`, the matrix cell; `headline`, True on the headline reading's "
        "rows.",
        "* Figures of the headline reading, like the paper's: `fig09_forces.png`, "
        "`fig10_normalized.png`, `fig12_hysteresis.png`, `fig13_suction_energy.png`.",
        "",
    ]


def claims_block(report: str) -> str:
    """The part of a ``report.md`` that docs/model.md quotes (Sec. 12, between its
    ``claims`` markers): the headline's count and table, and the matrix.

    Parameters
    ----------
    report : str
        The text of a ``report.md`` written by :func:`write_report`.
    """
    lines = report.splitlines()
    head = lines.index(next(x for x in lines if x.startswith("**") and "of 9 claims" in x))
    table_end = lines.index("", head + 2)
    m0 = lines.index("## Matrix: readings x claims")
    m1 = lines.index("## The readings and where the paper supports them")
    body = [lines[head], "", *lines[head + 2 : table_end], "", *lines[m0 + 2 : m1]]
    return "\n".join(x.replace("## ", "#### ") for x in body).rstrip()
