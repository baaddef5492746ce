"""
The paper's claims under its readings
=====================================

The evidence tables of the model chapter, section 12: ``mudrft reproduce`` evaluates the
paper's nine claims as the paper computes them, under seven other readings of the paper and
at every stance depth of 10-26 mm.

Run from the repository root: ``python examples/make_claims_matrix.py [--quick]``.
It runs ``mudrft reproduce`` (no figures) into a temporary directory and replaces, between
the markers in ``docs/model.md``,

* ``claims``: the headline's claims and their range over the stance depths, the claims
  against the depth and the matrix of readings x claims (from report.md);
* ``sinking``: the flat foot under 49 N, applied at once or ramped over 1 s, in each
  evaluation, beside the static depth (decision D13).

With ``--quick`` (the docs build) it prints the tables instead of writing them.
Progress goes to stderr.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import mudrft
from mudrft.reproduce import reproduce
from mudrft.reproduce.report import claims_block as quoted_block
from mudrft.simulation import LoadControl, simulate, static_sinking
from mudrft.terrains import MudTerrain

LOAD = 49.0  # [N], as mudrft reproduce (D13)


def say(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def replace_between(text: str, tag: str, body: str) -> str:
    start, end = f"<!-- {tag}:start -->", f"<!-- {tag}:end -->"
    i, j = text.index(start) + len(start), text.index(end)
    return text[:i] + "\n" + body + "\n" + text[j:]


def claims_block() -> str:
    with tempfile.TemporaryDirectory() as tmp:
        reproduce(tmp, figures=False, quiet=False)
        report = (Path(tmp) / "report.md").read_text()
    return quoted_block(report)


def sinking_block() -> str:
    mud = mudrft.paper_mud(0.25)
    foot = mudrft.feet.Flat()
    rows = [
        "| evaluation | 49 N at once: depth at 8 s [mm] | ramped over 1 s: at 2 / 4 / 8 s [mm] |",
        "|---|---|---|",
    ]
    for title, options in (
        ("ODE with the acceleration term", {}),
        ("ODE without it", {"acceleration": False}),
        ("quasi-static (eqs. 9-11)", {"thixotropy": "quasi-static"}),
    ):
        terrain = MudTerrain(mud, **options)
        at_once = simulate(foot, terrain, LoadControl(weight=LOAD, duration=8.0, dt=1e-3))
        ramped = simulate(foot, terrain, LoadControl(weight=LOAD, ramp=1.0, duration=8.0, dt=1e-3))
        d = ramped.depth * 1e3
        rows.append(
            f"| {title} | {at_once.depth[-1] * 1e3:.1f} | "
            + " / ".join(f"{d[round(s / 1e-3)]:.1f}" for s in (2, 4, 8))
            + " |"
        )
        say(f"sinking: {title}")
    rows.append(
        f"| static (`static_sinking`: relaxed mud, no suction) | "
        f"{static_sinking(foot, mud, LOAD) * 1e3:.1f} | the limit of every ramped run |"
    )
    return "\n".join(rows)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="The claims tables of docs/model.md, section 12.")
    ap.add_argument("--quick", action="store_true", help="print the tables, write nothing")
    ap.add_argument("--out", default=None, help="accepted for the docs build (no figures)")
    args = ap.parse_args([] if argv is None else argv)  # None: the defaults
    claims, sinking = claims_block(), sinking_block()
    if args.quick:
        print(claims, sinking, sep="\n\n")
        return 0
    fragment = Path(__file__).resolve().parents[1] / "docs" / "model.md"
    text = fragment.read_text()
    text = replace_between(text, "claims", claims)
    text = replace_between(text, "sinking", sinking)
    fragment.write_text(text)
    say(f"updated tables in {fragment}")
    return 0


if __name__ == "__main__":
    main(sys.argv[1:])
