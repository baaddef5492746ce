"""Parameter and fit JSON files: what the file says about itself is read, not ignored.

A fuzz of the file inputs found files that loaded wrong numbers without a word: a
``"units"`` block in MPa read as Pa, a misspelled field left at its default, a file of
another tool or of a future version accepted, a fit whose per-parameter tables lack
entries failing later inside ``summary``.
"""

from __future__ import annotations

import json

import pytest

import mudrft
from mudrft import MudrftError
from mudrft.calibration import FitResult, load_parameters
from mudrft.parameters.base import PARAMETER_UNITS


def write(tmp_path, data, name="p.json"):
    p = tmp_path / name
    p.write_text(json.dumps(data))
    return p


@pytest.fixture
def plain():
    return mudrft.paper_parameters(0.25).as_dict()


@pytest.fixture
def fit_dict(vertical_fit):
    return vertical_fit.to_dict()


def test_a_plain_file_with_its_si_units_loads(tmp_path, plain):
    p = write(tmp_path, {**plain, "units": dict(PARAMETER_UNITS), "direction": "vertical"})
    assert load_parameters(p).alpha == plain["alpha"]


@pytest.mark.parametrize("where", ["plain", "fit"])
def test_a_unit_other_than_si_is_refused(tmp_path, plain, fit_dict, where):
    """alpha in MPa would have loaded as 0.024 Pa: 10^6 times too soft."""
    data = {**plain, "alpha": plain["alpha"] / 1e6, "units": {"alpha": "MPa"}}
    if where == "fit":
        data = {**fit_dict, "units": {**fit_dict["units"], "alpha": "MPa"}}
    with pytest.raises(MudrftError, match=r"alpha is given in 'MPa'.*SI \('Pa'\)"):
        load_parameters(write(tmp_path, data))


def test_a_misspelled_field_is_named_with_the_likely_one(tmp_path, plain):
    """'Nu' was dropped and nu kept its default, without a word."""
    del plain["nu"]
    with pytest.raises(MudrftError, match=r"unknown parameter 'Nu' \(did you mean 'nu'\?\)"):
        load_parameters(write(tmp_path, {**plain, "Nu": 5.0}))


def test_a_misspelled_field_in_a_fit_file_is_refused(tmp_path, fit_dict):
    fit_dict["parameters"]["sigmaY"] = fit_dict["parameters"].pop("sigma_y")
    with pytest.raises(MudrftError, match=r"'sigmaY' \(did you mean 'sigma_y'\?\)"):
        load_parameters(write(tmp_path, fit_dict))


@pytest.mark.parametrize(
    ("meta", "match"),
    [
        ({"format": "other-tool"}, "format 'other-tool' is not a mudrft"),
        ({"version": 99}, "version 99 was written by a newer mudrft"),
        ({"version": "1"}, "version must be a positive integer, got '1'"),
    ],
)
def test_another_format_or_a_newer_version_is_refused(tmp_path, fit_dict, meta, match):
    p = write(tmp_path, {**fit_dict, **meta})
    with pytest.raises(MudrftError, match=match):
        load_parameters(p)
    with pytest.raises(MudrftError, match=match):
        FitResult.from_json(p)


def test_a_list_where_one_number_belongs_is_refused(tmp_path, plain):
    """A file holds one set; a list made a batched set that a sweep then failed on."""
    with pytest.raises(MudrftError, match=r"alpha must be one number \[Pa\], got \[1.0, 2.0\]"):
        load_parameters(write(tmp_path, {**plain, "alpha": [1.0, 2.0]}))


@pytest.mark.parametrize(
    "key", ["identifiability", "relative_standard_error", "standard_error", "confidence_interval"]
)
def test_a_fit_whose_tables_lack_a_parameter_is_refused(tmp_path, fit_dict, key):
    """Loaded, then ``summary()`` failed with a KeyError."""
    fit_dict[key] = {k: v for k, v in fit_dict[key].items() if k != "alpha"}
    with pytest.raises(MudrftError, match=f"{key} must have one entry per parameter"):
        FitResult.from_json(write(tmp_path, fit_dict))


def test_the_overwrite_hint_names_the_cli_flag(tmp_path, vertical_fit):
    p = vertical_fit.to_json(tmp_path / "fit.json")
    with pytest.raises(MudrftError, match="CLI: --force"):
        vertical_fit.to_json(p)


def test_a_byte_order_mark_is_read_as_csv_logs_allow(tmp_path, plain):
    p = tmp_path / "bom.json"
    p.write_bytes(b"\xef\xbb\xbf" + json.dumps(plain).encode())
    assert load_parameters(p).alpha == plain["alpha"]


def test_free_as_a_string_is_named(tmp_path, fit_dict):
    """'cannot reshape array of size 100 into shape (5,5)' did not say what was wrong."""
    fit_dict["free"] = "alpha"
    with pytest.raises(MudrftError, match="free must be a list of names, got 'alpha'"):
        FitResult.from_json(write(tmp_path, fit_dict))
