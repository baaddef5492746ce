"""The paper's parameter sets, interpolated between table rows (decision D7): linearly in
the logarithm of each constant, ``n`` linearly."""

from __future__ import annotations

import math
import warnings

import numpy as np

from .._validation import MudrftError, check_choice, check_finite
from ..citations import register
from . import chen2026
from .base import Mud, MudParameters, check_water_content

__all__ = [
    "DIRECTIONS", "EXTRAPOLATION_RANGE", "LABELLINGS", "WATER_CONTENT_RANGE", "paper_mud",
    "paper_parameters", "sigma_y_consistency", "table_rows",
]  # fmt: skip

DIRECTIONS = ("vertical", "horizontal")
WATER_CONTENT_RANGE = (0.25, 0.45)
EXTRAPOLATION_RANGE = (0.15, 0.50)
#: The two labellings of the table rows and what each adds to a printed water content to
#: give its label [-] (errata E6/E7): the tables' own, and the text's (15/25/35 %).
LABELLINGS = {"table": 0.0, "text": -0.10}


def _table(direction: str) -> dict[float, tuple[float, ...]]:
    check_choice("direction", direction, DIRECTIONS)
    return chen2026.VERTICAL if direction == "vertical" else chen2026.HORIZONTAL


def table_rows(direction: str) -> dict[float, dict[str, float]]:
    """The printed rows of one table, in SI, keyed by water content [-]."""
    units = chen2026.PRINTED_UNITS
    return {
        w: {c: v * units[c][1] for c, v in zip(chen2026.COLUMNS, row, strict=True)}
        for w, row in _table(direction).items()
    }


def _check_water_content(water_content: object, extrapolate: bool, shift: float = 0.0) -> float:
    """The printed water content of a label (``label - shift``), checked against the rows."""
    if not isinstance(extrapolate, (bool, np.bool_)):  # "no" is true: it extrapolated
        raise MudrftError(f"extrapolate must be True or False, got {extrapolate!r}")
    label = check_water_content(check_finite("water_content", water_content))
    assert label is not None  # check_finite refused None
    w = label - shift
    lo, hi = WATER_CONTENT_RANGE
    if abs(w - round(w, 2)) < 1e-12:  # 0.25 - (-0.10) is not exactly 0.35 in floats
        w = round(w, 2)
    if lo - 1e-12 <= w <= hi + 1e-12:
        return min(max(w, lo), hi)
    elo, ehi = EXTRAPOLATION_RANGE
    lo, hi, elo, ehi = (round(x + shift, 2) for x in (lo, hi, elo, ehi))  # as labelled
    if not extrapolate:
        raise MudrftError(
            f"water_content must lie in the tabulated range [{lo}, {hi}], got {label!r}; "
            f"pass extrapolate=True to extend the table to [{elo}, {ehi}] (with a warning)"
        )
    if not (elo <= label <= ehi):
        raise MudrftError(
            f"water_content must lie in [{elo}, {ehi}] even with extrapolate=True, got {label!r}"
        )
    warnings.warn(
        f"water_content={label} lies outside the tabulated rows [{lo}, {hi}]; the parameters are "
        "extrapolated from the nearest table segment and are not measured values",
        UserWarning,
        stacklevel=3,
    )
    return w


def _interpolate(direction: str, w: float) -> dict[str, float]:
    rows = table_rows(direction)
    ws = sorted(rows)
    if w in rows:
        return dict(rows[w])
    # segment containing w (or the nearest end segment, for extrapolation)
    i = int(np.clip(np.searchsorted(ws, w) - 1, 0, len(ws) - 2))
    w0, w1 = ws[i], ws[i + 1]
    t = (w - w0) / (w1 - w0)
    out = {}
    for c in chen2026.COLUMNS:  # n linearly, kept valid when extrapolating; the rest in log
        a, b = rows[w0][c], rows[w1][c]
        if c == "n":
            out[c] = min(max(a + t * (b - a), 0.02), 1.0)
        else:
            out[c] = math.exp(math.log(a) + t * (math.log(b) - math.log(a)))
    return out


def paper_parameters(
    water_content: float = 0.25, direction: str = "vertical", *, extrapolate: bool = False,
    labels: str = "table",
) -> MudParameters:  # fmt: skip
    """One parameter set of Chen et al. (2026), frozen and in SI units; its ``source`` names
    table and row.

    Parameters
    ----------
    water_content : float
        Volumetric water content [-] in [0.25, 0.45] (rows 0.25, 0.35, 0.45).
    direction : {"vertical", "horizontal"}
        Which table: vertical (S1) or horizontal (S2) intrusion.
    extrapolate : bool, keyword-only
        Allow water contents in [0.15, 0.50] outside the tabulated rows (warns).
    labels : {"table", "text"}, keyword-only
        Name the rows as the tables print them, or as the text does (errata E6/E7).

    Examples
    --------
    >>> p = paper_parameters(0.35, "horizontal")
    >>> round(p.lam, 3), p.sigma_y
    (17.0, 9400.0)
    >>> paper_parameters(0.25, labels="text").source
    "Chen et al. 2026, supplementary Table S1 (vertical intrusion), row W = 35 % (the text's W = 25 %, errata E6/E7)"
    """
    check_choice("direction", direction, DIRECTIONS)
    check_choice("labels", labels, LABELLINGS)
    shift = LABELLINGS[labels]
    w = _check_water_content(water_content, extrapolate, shift)
    values = _interpolate(direction, w)
    table = chen2026.TABLE_NAME[direction]
    row = "row" if w in _table(direction) else "interpolated at"
    source = f"Chen et al. 2026, {table}, {row} W = {w * 100:g} %"
    label = w if shift == 0.0 else round(w + shift, 10)
    if labels != "table":
        source += f" (the text's W = {label * 100:g} %, errata E6/E7)"
    register(chen2026.CITATION_KEY)
    return MudParameters(**values, source=source, water_content=label, direction=direction)


def paper_mud(
    water_content: float = 0.25, *, extrapolate: bool = False, labels: str = "table"
) -> Mud:
    """The paper's mud at one water content: vertical and horizontal sets (SI).

    Parameters
    ----------
    water_content : float
        Volumetric water content as a fraction [-], in [0.25, 0.45].
    extrapolate, labels : keyword-only
        As :func:`paper_parameters`.

    Examples
    --------
    >>> mud = paper_mud(0.25)
    >>> mud.vertical.alpha > mud.horizontal.alpha
    True
    >>> paper_mud(0.25, labels="text").vertical.alpha == paper_mud(0.35).vertical.alpha
    True
    """
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        v = paper_parameters(water_content, "vertical", extrapolate=extrapolate, labels=labels)
        h = paper_parameters(water_content, "horizontal", extrapolate=extrapolate, labels=labels)
    if caught:
        warnings.warn(str(caught[0].message), UserWarning, stacklevel=2)
    name = f"Chen 2026 mud, W = {float(water_content) * 100:g} %"
    name += "" if labels == "table" else f" ({labels} labels)"
    return Mud(vertical=v, horizontal=h, water_content=v.water_content, name=name)


def sigma_y_consistency(direction: str) -> list[dict[str, float | bool]]:
    """Check every printed row against eq. (4), sigma_Y = (eta_m - eta_inf) gamma_dot_c: a
    row is *consistent* when the two sides' rounding intervals (half a last digit) meet.

    Returns
    -------
    list of dict
        One entry per row: water_content, sigma_y_printed [Pa], sigma_y_relation [Pa],
        ratio printed/relation, relation_low/high [Pa] and ``consistent``.
    """
    out: list[dict[str, float | bool]] = []
    for w, row in _table(direction).items():
        r = dict(zip(chen2026.COLUMNS, row, strict=True))

        def half_ulp(x: float) -> float:
            s = f"{x:g}"
            decimals = len(s.split(".")[1]) if "." in s else 0
            return 0.5 * 10.0 ** (-decimals)

        em, ei, gc, sy = r["eta_m"], r["eta_inf"], r["gamma_dot_c"], r["sigma_y"]
        lo = (em - half_ulp(em) - (ei + half_ulp(ei))) * (gc - half_ulp(gc))
        hi = (em + half_ulp(em) - (ei - half_ulp(ei))) * (gc + half_ulp(gc))
        rel = (em - ei) * gc
        sy_lo, sy_hi = sy - half_ulp(sy), sy + half_ulp(sy)
        out.append(
            {
                "water_content": w,
                "sigma_y_printed": sy * 1e6,
                "sigma_y_relation": rel * 1e6,
                "ratio": sy / rel,
                "relation_low": lo * 1e6,
                "relation_high": hi * 1e6,
                "consistent": bool(sy_hi >= lo and sy_lo <= hi),
            }
        )
    return out
