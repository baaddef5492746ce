"""Parameter tables: transcription, units, interpolation, the sigma_Y relation, bad input."""

from __future__ import annotations

import dataclasses
import re
import warnings

import numpy as np
import pytest

import mudrft
from mudrft._validation import MudrftError
from mudrft.parameters import chen2026, sigma_y_consistency, table_rows


def _tex_rows(tex: str, label: str) -> dict[float, list[float]]:
    block = tex[tex.index(f"\\label{{{label}}}") :]
    block = block[: block.index("\\end{tabular}")]
    rows = {}
    for m in re.finditer(r"\$W=(\d+)\\%\$\s*&(.*?)\\\\", block):
        rows[int(m.group(1)) / 100] = [float(x) for x in m.group(2).split("&")]
    return rows


@pytest.mark.parametrize(
    ("label", "table"),
    [("tab:mdlPara_Z", chen2026.VERTICAL), ("tab:mdlPara_XY", chen2026.HORIZONTAL)],
)
def test_tables_are_transcribed_exactly_as_printed(paper_tex, label, table):
    rows = _tex_rows(paper_tex, label)
    assert set(rows) == set(table) == {0.25, 0.35, 0.45}
    for w, printed in rows.items():
        assert list(table[w]) == printed


def test_si_conversion():
    p = mudrft.paper_parameters(0.25, "vertical")
    assert (
        p.alpha == 0.024e6 and p.eta_m == 0.067e6 and p.eta_inf == 0.014e6 and p.sigma_y == 0.0071e6
    )
    assert p.lam == 1.9 and p.gamma_dot_c == 0.14 and p.tau_build == 0.32 and p.epsilon == 0.016
    assert "Table S1" in p.source and "25" in p.source
    mud = mudrft.paper_mud(0.35)
    assert mud.horizontal.lam == 17.0 and mud.vertical.n == 0.20


def test_sigma_y_relation_vertical_rows_hold_horizontal_rows_do_not():
    """Erratum E2: within printed rounding the vertical rows satisfy (4); no horizontal row does."""
    assert all(r["consistent"] for r in sigma_y_consistency("vertical"))
    hor = sigma_y_consistency("horizontal")
    assert not any(r["consistent"] for r in hor)
    w25 = next(r for r in hor if r["water_content"] == 0.25)
    assert w25["sigma_y_relation"] / w25["sigma_y_printed"] == pytest.approx(10.73, rel=1e-3)


def test_interpolation_hits_rows_and_stays_between_them():
    rows = table_rows("vertical")
    for w in rows:
        p = mudrft.paper_parameters(w)
        assert p.alpha == pytest.approx(rows[w]["alpha"])
    ws = np.linspace(0.25, 0.45, 41)
    alphas = np.array([mudrft.paper_parameters(w).alpha for w in ws])
    # alpha falls monotonically between the rows (24, 13, 10 kPa), log-linear segments
    assert np.all(np.diff(alphas) < 0)
    mid = mudrft.paper_parameters(0.30).alpha
    assert mid == pytest.approx(np.sqrt(24e3 * 13e3), rel=1e-12)
    # n is interpolated linearly
    assert mudrft.paper_parameters(0.30).n == pytest.approx(0.5 * (0.53 + 0.20))


def test_extrapolation_needs_permission_and_warns():
    with pytest.raises(MudrftError, match="extrapolate=True"):
        mudrft.paper_parameters(0.15)
    with pytest.warns(UserWarning, match="extrapolated"):
        p = mudrft.paper_parameters(0.15, extrapolate=True)
    # 15 % is drier than 25 %: stiffer mud
    assert p.alpha > mudrft.paper_parameters(0.25).alpha
    with pytest.raises(MudrftError, match="water_content"):
        mudrft.paper_parameters(0.9, extrapolate=True)


@pytest.mark.parametrize("bad", [-0.1, 25, float("nan"), "0.25", None, True])
def test_bad_water_content(bad):
    with pytest.raises(MudrftError, match="water_content"):
        mudrft.paper_parameters(bad)


def test_unknown_direction():
    with pytest.raises(MudrftError, match="direction"):
        mudrft.paper_parameters(0.25, "sideways")


def test_parameters_validate_fields():
    p = mudrft.paper_parameters(0.25)
    with pytest.raises(MudrftError, match="alpha"):
        p.replace(alpha=-1.0)
    with pytest.raises(MudrftError, match="tau_leak"):
        p.replace(tau_leak=float("inf"))
    with pytest.raises(MudrftError, match="n must"):
        p.replace(n=1.5)
    q = mudrft.MudParameters.from_dict(p.as_dict())
    assert q.as_dict() == p.as_dict()
    with pytest.raises(MudrftError, match="unknown fields"):
        mudrft.MudParameters.from_dict({**p.as_dict(), "beta": 1.0})


@pytest.mark.parametrize("name", list(mudrft.parameters.PARAMETER_UNITS))
def test_every_field_must_be_strictly_positive(name):
    """POSITIVE_FIELDS is every field of MudParameters: a zero is refused, by name."""
    with pytest.raises(MudrftError, match=rf"^{name} must be > 0"):
        mudrft.paper_parameters(0.25).replace(**{name: 0.0})


def test_citation_registered():
    from mudrft.citations import reset

    reset()
    mudrft.paper_parameters(0.25)
    assert mudrft.citations(bibtex=False) == ["chen2026mud"]
    assert mudrft.citations()[0].startswith("@article{chen2026mud")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mudrft.paper_mud(0.3)


@pytest.mark.parametrize(("text_label", "printed_row"), [(0.15, 0.25), (0.25, 0.35), (0.35, 0.45)])
def test_text_labelling_names_the_printed_rows_errata_E6_E7(text_label, printed_row):
    """The text says 15/25/35 % three times; the tables print 25/35/45 %. labels="text"
    reads a water content as the text does; the default stays the table's."""
    text = mudrft.paper_mud(text_label, labels="text")
    table = mudrft.paper_mud(printed_row)
    for d in ("vertical", "horizontal"):
        a, b = getattr(text, d), getattr(table, d)
        for k in chen2026.COLUMNS:
            assert getattr(a, k) == getattr(b, k), (d, k)
        assert a.water_content == text_label
        assert f"row W = {printed_row * 100:g} %" in a.source and "E6/E7" in a.source
    assert mudrft.paper_mud(0.25).vertical.alpha == 24e3  # paper_mud(0.25) is the table's row


def test_text_labelling_range_and_errors():
    with pytest.raises(MudrftError, match=r"\[0.15, 0.35\]"):
        mudrft.paper_mud(0.45, labels="text")
    with pytest.raises(MudrftError, match="labels"):
        mudrft.paper_mud(0.25, labels="figure")
    between = mudrft.paper_parameters(0.3, labels="text")  # interpolated like the table's 40 %
    assert between.alpha == mudrft.paper_parameters(0.4).alpha


def test_a_mud_refuses_sets_fitted_to_the_other_direction():
    """Mud(vertical, horizontal) with the sets swapped is an error that says so; a set
    without a direction is taken in either place."""
    mud = mudrft.paper_mud(0.25)
    with pytest.raises(MudrftError, match=r"vertical must be a vertical parameter set.*swapped"):
        mudrft.Mud(mud.horizontal, mud.vertical)
    with pytest.raises(MudrftError, match="horizontal must be a horizontal parameter set"):
        mudrft.Mud(mud.vertical, mud.vertical)
    either = mudrft.Mud(mud.vertical, mud.vertical.replace(direction=""))
    assert either.horizontal.alpha == mud.vertical.alpha


def test_replace_moves_a_default_k_a_with_lam_and_keeps_an_explicit_one():
    # D3: k_a = 1/lam unless given. replace() knows whether k_a was derived;
    # dataclasses.replace cannot, and keeps the old value (docstring of replace)
    v = mudrft.paper_parameters(0.25)
    moved = v.replace(lam=2.0 * v.lam)
    assert moved.k_a == pytest.approx(1.0 / (2.0 * v.lam), rel=1e-15)
    assert dataclasses.replace(v, lam=2.0 * v.lam).k_a == v.k_a
    explicit = v.replace(k_a=0.5).replace(lam=3.0)
    assert explicit.k_a == 0.5
