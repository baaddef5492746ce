"""``mudrft params``: the built-in parameter sets, as a table in SI units."""

from __future__ import annotations

import argparse

from ._parser import add_subcommand


def add_parser(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    add_subcommand(
        subparsers,
        "params",
        run,
        help="list the built-in parameter sets",
        description="List the parameter sets of Chen et al. (2026), Tables S1 (vertical) and "
        "S2 (horizontal), converted to SI units, one row per tabulated water content. Rows "
        "whose yield stress sigma_y does not satisfy the paper's own relation "
        "sigma_y = (eta_m - eta_inf) * gamma_dot_c are flagged.",
    )


def run(args: argparse.Namespace) -> int:
    """Print the parameter tables to stdout."""
    from ..parameters import DIRECTIONS, PARAMETER_UNITS, sigma_y_consistency, table_rows
    from ..parameters.chen2026 import TABLE_NAME

    names = list(PARAMETER_UNITS)[:10]
    for d in DIRECTIONS:
        print(f"Chen et al. 2026, {TABLE_NAME[d]} -- SI units")
        head = ["W"] + [f"{n} [{PARAMETER_UNITS[n]}]" for n in names]
        print("  " + "  ".join(f"{h:>14s}" for h in head))
        checks = {c["water_content"]: c for c in sigma_y_consistency(d)}
        for w, row in table_rows(d).items():
            vals = [f"{w * 100:>13g}%"] + [f"{row[n]:>14.6g}" for n in names]
            if not checks[w]["consistent"]:
                rel = checks[w]["sigma_y_relation"]
                vals.append(f" (sigma_y violates (eta_m-eta_inf)*gamma_dot_c = {rel:.4g} Pa)")
            print("  " + "  ".join(vals))
        print()
    print("Between rows the sets are interpolated (log-linear); see docs/model.md, decision D7.")
    print(
        "W is labelled as the tables print it; the paper's text calls the same rows 15, 25 and "
        "35 % (errata E6/E7): paper_mud(W, labels='text'), mudrft simulate --labels text."
    )
    print("nu = 0.01 1/s and k_a = 1/lam are model choices (decisions D5, D8), not table values.")
    return 0
