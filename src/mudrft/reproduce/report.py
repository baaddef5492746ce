"""``report.md`` and ``claims.csv`` of ``mudrft reproduce``: the matrix of readings x claims."""

from __future__ import annotations

import csv
from collections.abc import Sequence
from pathlib import Path

from .claims import CLAIMS, INCONSISTENT, Cell, count
from .readings import Reading

__all__ = ["CLAIMS_COLUMNS", "headline_count", "write_claims_csv", "write_report"]

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
        f"Headline reading **{head.key}**: {head.title}.",
        "",
        f"**{headline_count(hc)}.**",
        "",
        "| claim | paper | mudrft | verdict |",
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
            "the largest suction force', s_c / s_f < 1. No model can meet the three claims; "
            "every reading below reproduces the ordering (claim suction-order), and the cells "
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
        "| claim | paper | " + " | ".join(rd.key for rd in readings) + " |",
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
    lines += [
        "",
        "Figures (headline reading): `fig09_forces.png`, `fig10_normalized.png`,",
        "`fig12_hysteresis.png`, `fig13_suction_energy.png`; numbers in `summary.csv`.",
        "",
    ]
    path.write_text("\n".join(lines))
    return path
