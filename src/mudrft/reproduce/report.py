"""``report.md``, ``claims.csv`` and ``depths.csv`` of ``mudrft reproduce``: the matrix of
readings x claims and the claims against the stance depth."""

from __future__ import annotations

import csv
import itertools
from collections.abc import Sequence
from pathlib import Path

from .claims import (
    AGREES,
    CLAIMS,
    LOAD,
    NOT_EVALUATED,
    PCT_TOL,
    RATIO_TOL,
    REQUIRED_RATIO,
    SPEED_AGREE,
    SPEED_PARTLY,
    Cell,
)
from .readings import Reading

#: Columns of ``claims.csv``: one row per claim and reading.
CLAIMS_COLUMNS = ("claim", "reading", "paper", "mudrft", "verdict", "summary", "headline")
#: Columns of ``depths.csv``: one row per claim and stance depth (the headline reading).
DEPTHS_COLUMNS = ("claim", "reading", "stance_depth [m]", "mudrft", "verdict", "summary")
#: The depth table's mark of each verdict.
MARKS = {AGREES: "+", "partly": "~", "differs": "-", NOT_EVALUATED: "."}


def count(cells: Sequence[Cell], verdict: str = AGREES) -> int:
    """How many of ``cells`` have the ``verdict``."""
    return sum(c.verdict == verdict for c in cells)


def headline_count(cells: Sequence[Cell]) -> str:
    """The headline sentence: "N of 9 claims" with the failed ones."""
    agrees, skipped = count(cells), count(cells, NOT_EVALUATED)
    failed = len(cells) - agrees - skipped
    text = f"{agrees} of {len(cells)} claims reproduced; {failed} not reproduced"
    if skipped:
        text += f"; {skipped} not evaluated (runs not asked for)"
    return text


def write_claims_csv(path: Path, cells: dict[str, list[Cell]]) -> Path:
    """Write ``claims.csv`` (:data:`CLAIMS_COLUMNS`) and return its path."""
    first = next(iter(cells), None)
    with open(path, "w", newline="") as fh:
        wr = csv.writer(fh)
        wr.writerow(CLAIMS_COLUMNS)
        wr.writerows(
            [c.claim, c.reading, c.paper, c.mudrft, c.verdict, c.short, key == first]
            for key, row in cells.items()
            for c in row
        )
    return path


def write_depths_csv(path: Path, reading: Reading, by_depth: dict[float, list[Cell]]) -> Path:
    """Write ``depths.csv`` (:data:`DEPTHS_COLUMNS`) and return its path."""
    with open(path, "w", newline="") as fh:
        wr = csv.writer(fh)
        wr.writerow(DEPTHS_COLUMNS)
        for depth, row in by_depth.items():
            for c in row:
                wr.writerow([c.claim, reading.key, f"{depth:.6g}", c.mudrft, c.verdict, c.short])
    return path


def depth_ranges(by_depth: dict[float, list[Cell]]) -> str:
    """The counts over the stance depths as ranges: "6 of 9 at 10-17 mm, 5 of 9 at 18-26 mm"."""
    counts = [(count(by_depth[d]), d) for d in sorted(by_depth)]
    groups = [(n, [d for _, d in g]) for n, g in itertools.groupby(counts, key=lambda t: t[0])]
    total = len(CLAIMS)
    return ", ".join(
        f"{n} of {total} at {_mm(ds[0])}" + (f"-{_mm(ds[-1])}" if len(ds) > 1 else "") + " mm"
        for n, ds in groups
    )


def _mm(depth: float) -> str:
    return f"{depth * 1e3:g}"


def _esc(text: str) -> str:
    return text.replace("|", "/")


def write_report(
    path: Path,
    cells: dict[str, list[Cell]],
    *,
    readings: list[Reading],
    by_depth: dict[float, list[Cell]] | None = None,
    curl_ratios: dict[float, float] | None = None,
    suction_ratios: list[tuple[float, float | None]] | None = None,
    sinking: dict[str, float] | None = None,
) -> Path:
    """Write ``report.md`` and return its path: ``cells`` by reading key (the first of
    ``readings`` is the headline); ``by_depth``: stance depth [m] -> the headline's cells;
    ``curl_ratios``: pad-curl delay [s] -> the headline's morphing foot's suction / support
    [-]; ``suction_ratios``: per reading, the semi-cylinder's suction over the flat foot's [-]
    in the gait and with the load-carrying stance (None if not run); ``sinking``: fixed foot
    -> static sinking under :data:`~.claims.LOAD` [m] (headline)."""
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
    ]
    if by_depth:
        lines += [
            f"**Over the stance depth, which the paper does not give: {depth_ranges(by_depth)}.**",
            "",
            _default_stance(head, sinking or {}),
            "",
        ]
    lines += ["| claim | the paper says | mudrft | verdict |", "|---|---|---|---|"]
    for c in hc:
        lines.append(
            f"| {_esc(claims[c.claim].text)} | {_esc(c.paper)} | {_esc(c.mudrft)} | {c.verdict} |"
        )
    if by_depth:
        lines += ["", *_depth_section(by_depth)]
    lines += ["", *_morphing_section(head, suction_ratios or [], curl_ratios or {})]
    titles = " | ".join(rd.key + (" (headline)" if rd is head else "") for rd in readings)
    lines += [
        "",
        "## Matrix: readings x claims",
        "",
        "Each cell: mudrft's number, then the verdict (feet in the order flat / semi-cylinder /",
        "semi-sphere). Numbers and full texts are in `claims.csv`.",
        "",
        f"| claim | the paper says | {titles} |",
        "|---|---|" + "---|" * len(readings),
    ]
    for i, claim in enumerate(CLAIMS):
        row = (cells[rd.key][i] for rd in readings)
        marks = " | ".join(f"{_esc(c.short)}: **{c.verdict}**" for c in row)
        lines.append(f"| {claim.key} | {_esc(claim.paper)} | {marks} |")
    counts = " | ".join(f"**{count(cells[rd.key])} of 9**" for rd in readings)
    lines.append(f"| **reproduced** | | {counts} |")
    lines += ["", "## The readings and where the paper supports them", ""]
    for rd in readings:
        lines.append(f"* **{rd.key}** ({headline_count(cells[rd.key])}): {rd.title}. ")
        lines.append(f"  {rd.derivation}")
    lines += ["", "## What each claim compares", ""]
    for claim in CLAIMS:
        lines.append(f"* **{claim.key}**: {claim.text}. mudrft compares: {claim.quantity}.")
    lines += ["", *_files()]
    path.write_text("\n".join(lines))
    return path


def _default_stance(head: Reading, sinking: dict[str, float]) -> str:
    """What the headline's stance rests on."""
    text = (
        f"The headline's stance, {_mm(head.depth)} mm (decision D10), rests on the feet and "
        "the mud, not on any verdict: the paper's fixed feet are 26 mm tall and eqs. "
        "(12)-(14) describe a foot that is not buried"
    )
    if sinking:
        lo, hi = min(sinking.values()), max(sinking.values())
        text += (
            f", and under {LOAD:g} N each fixed foot settles {lo * 1e3:.1f}-{hi * 1e3:.1f} mm "
            "deep (claim sinking), so a stepping foot pushed into the mud goes deeper than that"
        )
    return text + "."


def _depth_section(by_depth: dict[float, list[Cell]]) -> list[str]:
    """The claims of the headline reading at every stance depth: a table of marks."""
    depths = sorted(by_depth)
    changes = [
        claim.key
        for i, claim in enumerate(CLAIMS)
        if len({by_depth[d][i].verdict for d in depths}) > 1
    ]
    lines = [
        "## The claims against the stance depth",
        "",
        "The paper gives the gait speeds but not how deep the foot goes. The headline "
        "reading at every stance depth up to the feet's 26 mm (`depths.csv`, figure "
        "`fig_depth_verdicts.png`): + agrees, ~ partly, - differs, . not evaluated. "
        + (
            "The verdicts that change with the depth: " + ", ".join(changes) + "."
            if changes
            else "No verdict changes with the depth."
        ),
        "",
        "| claim | " + " | ".join(_mm(d) for d in depths) + " |",
        "|---|" + "---|" * len(depths),
    ]
    for i, claim in enumerate(CLAIMS):
        marks = " | ".join(MARKS.get(by_depth[d][i].verdict, "?") for d in depths)
        lines.append(f"| {claim.key} | {marks} |")
    counts = " | ".join(str(count(by_depth[d])) for d in depths)
    lines.append(f"| **reproduced** | {counts} |")
    return lines


def _morphing_section(
    head: Reading,
    suction_ratios: list[tuple[float, float | None]],
    curl_ratios: dict[float, float],
) -> list[str]:
    """The morphing foot's claims and what they rest on."""
    lines = [
        "## The morphing foot's claims and their assumptions",
        "",
        "*-57 % and -32 % (Fig. 13).* Sec. IV-B gives the morphing foot's suction as 57 % "
        "below the semi-cylindrical foot's and 32 % below the flat foot's, so s_m = 0.43 s_c "
        f"= 0.68 s_f: together they need s_c / s_f = {REQUIRED_RATIO:.2f}, the "
        "semi-cylindrical foot suffering 58 % more suction than the flat foot. The paper "
        "places them in the walking tests (Fig. 13: the biped's feet carry its weight, and "
        "its energies are the whole robot's joint energy), while its 'the flat foot ... "
        "suffered from the largest suction force' describes the position-controlled tests "
        "of Fig. 10a; so they are not a contradiction within the paper, but the model does "
        "not reproduce them",
    ]
    gait = [g for g, _ in suction_ratios]
    held = [x for _, x in suction_ratios if x is not None]
    if gait:
        text = f": its s_c / s_f is {min(gait):.2f}-{max(gait):.2f} in the gait"
        if held:
            text += (
                f" and {min(held):.2f}-{max(held):.2f} with a load-carrying stance (each foot "
                f"at its own static depth under {LOAD:g} N)"
            )
        lines[-1] += text + f" over the readings, never {REQUIRED_RATIO:.2f}"
    lines[-1] += ". Each cell gives the two experiments' numbers."
    if curl_ratios:
        ratios = " | ".join(f"{r * 100:.0f}" for r in curl_ratios.values())
        lines += [
            "",
            "*The 40 % (Fig. 11).* It rests on when the pads curl, which the paper does not "
            "time (it says the suction comes before the pads break the seal). The headline "
            "lets them curl the moment the retraction begins (decision D35); held spread for "
            "a while (the morphing foot's `curl_delay`), the suction builds first. The "
            f"headline's morphing foot ({_mm(head.depth)} mm stance), suction / support "
            f"against the delay (agrees within 40 +- {PCT_TOL:g} points):",
            "",
            "| pad-curl delay [ms] | " + " | ".join(f"{x * 1e3:g}" for x in curl_ratios) + " |",
            "|---|" + "---|" * len(curl_ratios),
            f"| suction / support [%] | {ratios} |",
        ]
    return lines


def _how_to_read(head: Reading) -> list[str]:
    """What a reading, a verdict and the units are, for a reader without docs/model.md."""
    return [
        "## How to read this report",
        "",
        "* **Readings.** The paper leaves some choices open: how eqs. (3) and (5) are "
        "evaluated (its quasi-static solutions (9)-(11) or the ODEs themselves), when the clock "
        "of eq. (9) starts, how deep the foot goes in the stepping gait (the paper gives "
        "the gait speeds, not the path), which water content each row of Tables S1-S2 "
        "is, and when the morphing foot's pads curl. A *reading* fixes each choice, citing "
        "the paper's text (section 'The readings' "
        f"below). The headline reading, **{head.key}**, is the paper's own evaluation: it was "
        "fixed from the text before any of its verdicts was computed and has not been "
        "changed since. Every other reading changes one choice of it (or restores mudrft's "
        "former defaults), so the matrix shows which choice decides which claim. The "
        "stance depth is also a dimension of its own: the headline at every depth of "
        "10-26 mm.",
        "* **Verdicts**, with tolerances fixed before any reading was evaluated: *agrees* "
        f"(orderings strictly met; the paper's percentages within +-{PCT_TOL:g} points; "
        f"'almost as large' within 100 +- {RATIO_TOL:g} %; 'did not change' a spread below "
        f"{SPEED_AGREE:g} %), *partly* (that spread below {SPEED_PARTLY:g} %), *differs* "
        "(not met), *not evaluated* (the runs it needs were not asked for); 'not reproduced' "
        "counts *partly* and *differs*. No model parameter is tuned to any claim (the one "
        "reading set after its verdicts were seen, paper-curl-50ms, says so).",
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
        "* `depths.csv`: one row per claim and stance depth, under the headline reading. "
        "Columns: `claim`; `reading`; `stance_depth [m]`, the gait's deepest tip depth; "
        "`mudrft`; `verdict`; `summary`, as in `claims.csv`.",
        "* Figures of the headline reading, like the paper's: `fig09_forces.png`, "
        "`fig10_normalized.png`, `fig12_hysteresis.png`, `fig13_suction_energy.png`; and "
        "`fig_depth_verdicts.png`, its verdicts against the stance depth.",
        "",
    ]


def claims_block(report: str) -> str:
    """The part of a ``report.md`` text that docs/model.md quotes: the headline's count,
    range and table, the claims against the depth, and the matrix."""
    lines = report.splitlines()
    head = lines.index(next(x for x in lines if x.startswith("**") and "of 9 claims" in x))
    table = lines.index("| claim | the paper says | mudrft | verdict |", head)
    table_end = lines.index("", table)
    body = [*lines[head:table_end], ""]
    for title in ("## The claims against the stance depth", "## Matrix: readings x claims"):
        if title in lines:
            start = lines.index(title) + 2
            end = next(i for i in range(start, len(lines)) if lines[i].startswith("## "))
            body += lines[start:end]
    return "\n".join(x.replace("## ", "#### ") for x in body).rstrip()
