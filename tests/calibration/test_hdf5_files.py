"""HDF5 intrusion logs that the loader used to misread without a word, or answer with a
traceback or an error that names no file: each is now read as written or refused with a
MudrftError naming the file and the dataset, link or attribute."""

from __future__ import annotations

import re
import sys
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mudrft._validation import MudrftError, PlausibilityWarning
from mudrft.io import load_dataset, load_intrusion_hdf5

h5py = pytest.importorskip("h5py")

T = np.linspace(0.0, 1.0, 100)
DEPTH = 0.02 * T
STRESS = 1e4 * T


def _h5(tmp_path: Path, fill: Callable[[Any], None], name: str = "log.h5") -> Path:
    p = tmp_path / name
    with h5py.File(p, "w") as fh:
        fill(fh)
    return p


def _trial(g: Any, *, stress: Any = STRESS, time: Any = T) -> None:
    g["time [s]"] = time
    g["depth [m]"] = DEPTH
    g["stress [Pa]"] = stress


def _refused(p: Path, pattern: str, **kw: Any) -> str:
    with pytest.raises(MudrftError) as info:
        load_intrusion_hdf5(p, **kw)
    msg = str(info.value)
    assert msg.startswith(str(p)), msg
    assert re.search(pattern, msg), msg
    assert "\n" not in msg, msg
    return msg


# --- 1. a unit in the name and a unit attribute ---------------------------------------
def test_a_unit_attribute_that_contradicts_the_name_is_refused(tmp_path):
    def fill(fh):
        _trial(fh.create_group("a"), time=1000 * T)
        fh["a/time [s]"].attrs["unit"] = "ms"

    # it loaded as seconds: a 1 s test became a 1000 s one
    _refused(_h5(tmp_path, fill), r"dataset 'a/time \[s\]'.*'s'.*'ms'")


def test_a_unit_attribute_that_agrees_with_the_name_is_fine(tmp_path):
    def fill(fh):
        _trial(fh)
        fh["time [s]"].attrs["unit"] = "s"
        fh["depth [m]"].attrs["units"] = b"m"

    np.testing.assert_allclose(load_intrusion_hdf5(_h5(tmp_path, fill))[0].time, T)


def test_unit_and_units_attributes_that_disagree_are_refused(tmp_path):
    def fill(fh):
        g = fh.create_group("a")
        _trial(g)
        del g["time [s]"]
        ds = g.create_dataset("time", data=T)
        ds.attrs["unit"] = "s"
        ds.attrs["units"] = "ms"

    _refused(_h5(tmp_path, fill), r"dataset 'a/time'.*'unit'.*'units'")


# --- 2. datasets that are not 1-D ------------------------------------------------------
@pytest.mark.parametrize(
    "shape", [(50, 2), (100, 1), (1, 100), ()], ids=["50x2", "100x1", "1x100", "scalar"]
)
def test_a_dataset_that_is_not_one_dimensional_is_refused(tmp_path, shape):
    stress = np.float64(1.0) if shape == () else STRESS.reshape(shape)
    p = _h5(tmp_path, lambda fh: _trial(fh, stress=stress))
    # (50, 2) loaded with the two columns interleaved as one
    _refused(p, rf"dataset 'stress \[Pa\]'.*1-D.*shape {re.escape(str(shape))}")


# --- 3. links that lead nowhere --------------------------------------------------------
def test_a_dangling_soft_link_is_named(tmp_path):
    def fill(fh):
        g = fh.create_group("a")
        _trial(g)
        g["stress2"] = h5py.SoftLink("/nowhere")

    _refused(_h5(tmp_path, fill), r"link 'a/stress2'.*soft link to '/nowhere'")


def test_a_broken_external_link_is_named(tmp_path):
    def fill(fh):
        _trial(fh)
        fh["extra"] = h5py.ExternalLink("missing.h5", "/data")

    _refused(_h5(tmp_path, fill), r"link 'extra'.*external link to 'missing\.h5'")


def test_a_working_external_link_is_followed(tmp_path):
    _h5(tmp_path, lambda fh: fh.create_dataset("s", data=STRESS), "other.h5")

    def fill(fh):
        fh["time [s]"] = T
        fh["depth [m]"] = DEPTH
        fh["stress [Pa]"] = h5py.ExternalLink("other.h5", "/s")

    np.testing.assert_allclose(load_intrusion_hdf5(_h5(tmp_path, fill))[0].stress, STRESS)


# --- 4. inputs that were ignored -------------------------------------------------------
def test_root_datasets_beside_groups_are_refused(tmp_path):
    def fill(fh):
        _trial(fh)  # a trial in the root ...
        _trial(fh.create_group("b"))  # ... and one in a group: the root's was dropped

    _refused(
        _h5(tmp_path, fill), r"root group: holds the datasets .*'time \[s\]' beside the group 'b'"
    )


def test_other_root_datasets_beside_groups_are_still_allowed(tmp_path):
    def fill(fh):
        fh["comment"] = np.arange(3)
        _trial(fh.create_group("b"))

    assert [t.name for t in load_intrusion_hdf5(_h5(tmp_path, fill))] == ["b"]


@pytest.mark.parametrize("key", ["area", "characteristic_length", "direction", "synthetic"])
def test_plate_attributes_on_a_group_are_refused(tmp_path, key):
    def fill(fh):
        g = fh.create_group("a")
        _trial(g)
        g.attrs[key] = "horizontal" if key == "direction" else 0.03

    # a per-group 0.03 m plate was fitted as the 50 mm default
    _refused(_h5(tmp_path, fill), rf"group 'a', attribute '{key}'.*root", area=0.01)


def test_a_nested_group_with_a_log_is_refused(tmp_path):
    def fill(fh):
        g = fh.create_group("a")
        _trial(g)
        _trial(g.create_group("repeat"))  # a second trial, dropped

    _refused(_h5(tmp_path, fill), r"group 'a/repeat'.*nested")


def test_a_trial_dataset_is_refused(tmp_path):
    def fill(fh):
        fh["trial"] = np.array([b"slow"] * 50 + [b"fast"] * 50)
        _trial(fh)

    # the labels were ignored: the two trials were read as one
    _refused(_h5(tmp_path, fill), r"dataset 'trial'.*group per trial")


@pytest.mark.parametrize("value", [[0.03, 0.05], np.zeros((2, 2))])
def test_an_array_attribute_is_refused(tmp_path, value):
    def fill(fh):
        _trial(fh)
        fh.attrs["characteristic_length"] = value

    # only the first element was used
    _refused(_h5(tmp_path, fill), r"attribute 'characteristic_length'.*one number.*shape")


def test_a_one_element_attribute_and_one_with_a_unit_are_read(tmp_path):
    def fill(fh):
        _trial(fh)
        fh.attrs["characteristic_length [mm]"] = [40.0]

    # the unit in the key was ignored and the default 50 mm used
    tr = load_intrusion_hdf5(_h5(tmp_path, fill))[0]
    assert tr.characteristic_length == pytest.approx(0.04, rel=1e-12)

    def both(fh):
        fill(fh)
        fh.attrs["characteristic_length"] = 0.04

    _refused(_h5(tmp_path, both, "both.h5"), "characteristic_length.*keep one")


# --- 5. non-real datasets ---------------------------------------------------------------
@pytest.mark.parametrize(
    "data",
    [STRESS + 1j * STRESS, (STRESS > 0), np.array([b"1.0"] * 100)],
    ids=["complex", "bool", "text"],
)
def test_a_dataset_that_is_not_real_numbers_is_refused(tmp_path, data):
    p = _h5(tmp_path, lambda fh: _trial(fh, stress=data))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # numpy's ComplexWarning was all the user got
        _refused(p, r"dataset 'stress \[Pa\]'.*real numbers.*dtype")


# --- 6. messages ------------------------------------------------------------------------
def test_time_errors_name_the_dataset_and_row_not_a_csv_line(tmp_path):
    p = _h5(tmp_path, lambda fh: _trial(fh.create_group("g"), time=T[::-1].copy()))
    msg = _refused(p, r"dataset 'g/time \[s\]', row 1: time must increase")
    assert "line" not in msg and "column" not in msg


def test_a_never_positive_depth_names_the_dataset(tmp_path):
    def fill(fh):
        _trial(fh)
        fh["depth [m]"][...] = -DEPTH

    msg = _refused(_h5(tmp_path, fill), r"dataset 'depth \[m\]'.*never positive")
    assert "column" not in msg


@pytest.mark.parametrize("n", [0, 1])
def test_empty_datasets_name_the_file(tmp_path, n):
    def fill(fh):
        fh["time [s]"] = T[:n]
        fh["depth [m]"] = DEPTH[:n]
        fh["stress [Pa]"] = STRESS[:n]

    # "trials must hold at least one Trial, got none", without a file name
    said = r"dataset 'time \[s\]': holds no samples" if n == 0 else r"row 0: trial .* has 1 sample"
    _refused(_h5(tmp_path, fill), said + "; a trial needs at least 2")


def test_an_empty_file_says_what_it_expected(tmp_path):
    _refused(_h5(tmp_path, lambda fh: None), "holds no datasets.*'time \\[s\\]'")


def test_a_length_mismatch_names_both_datasets(tmp_path):
    p = _h5(tmp_path, lambda fh: _trial(fh, stress=STRESS[:50]))
    _refused(p, r"dataset 'stress \[Pa\]' has 50 values but dataset 'time \[s\]' has 100")


def test_a_directory_is_named_as_one(tmp_path):
    d = tmp_path / "x.h5"
    d.mkdir()
    for load in (load_intrusion_hdf5, load_dataset):
        with pytest.raises(MudrftError) as info:
            load(d)
        assert str(info.value) == f"{d}: is a directory, expected an HDF5 file"


def test_a_file_that_is_not_hdf5_gets_a_one_line_reason(tmp_path):
    p = tmp_path / "fake.h5"
    p.write_bytes(b"\x00" * 4096)
    _refused(p, "is not a readable HDF5 file")


def test_the_round_trip_and_groups_still_load(tmp_path):
    def fill(fh):
        fh.attrs["characteristic_length"] = 0.04
        fh.attrs["direction"] = "horizontal"
        fh.attrs["notes"] = "from a test"
        for name in ("b", "a"):
            g = fh.create_group(name)
            _trial(g)
            g.attrs["notes"] = "free text on a group is fine"

    ds = load_intrusion_hdf5(_h5(tmp_path, fill))
    assert [t.name for t in ds] == ["a", "b"] and ds.direction == "horizontal"
    assert all(t.characteristic_length == 0.04 for t in ds)


# --- a fuzz of the file's structure: a dataset in SI, or a one-line MudrftError -----------
_NAMES = ["time [s]", "time", "depth [mm]", "depth", "stress [kPa]", "Fz [N]", "trial", "x"]
_MEMBER = st.tuples(
    st.sampled_from(["", "g/", "h/", "g/sub/"]),
    st.sampled_from(_NAMES),
    st.sampled_from(["f8", "i4", "c16", "S3", "?", "link", "external", "2d", "empty"]),
    st.sampled_from([None, "s", "ms", "mm", "parsec", "m"]),
    st.integers(min_value=0, max_value=4),
)


def _fill(fh: Any, members: list[tuple[str, str, str, str | None, int]]) -> None:
    for where, name, kind, unit, n in members:
        path = where + name
        if path in fh:
            continue
        if kind == "link":
            fh[path] = h5py.SoftLink("/nowhere")
            continue
        if kind == "external":
            fh[path] = h5py.ExternalLink("absent.h5", "/x")
            continue
        values = np.arange(float(n)) * 0.5
        if kind == "2d":
            values = np.stack([values, values], axis=1)
        elif kind == "empty":
            values = values[:0]
        elif kind == "S3":
            values = values.astype("S3")
        elif kind not in ("f8",):
            values = values.astype(kind)
        fh.create_dataset(path, data=values)
        if unit is not None:
            fh[path].attrs["unit"] = unit


@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(st.lists(_MEMBER, max_size=8), st.sampled_from([None, 0.01, [0.01, 0.02], "big"]))
def test_fuzzed_hdf5_structure_never_tracebacks(tmp_path_factory, members, area):
    p = tmp_path_factory.mktemp("fuzz") / "f.h5"
    with h5py.File(p, "w") as fh:
        _fill(fh, members)
        if area is not None:
            fh.attrs["area"] = area
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlausibilityWarning)
        warnings.simplefilter("error", np.exceptions.ComplexWarning)
        try:
            ds = load_intrusion_hdf5(p)
        except MudrftError as exc:
            assert str(exc).startswith(str(p)) and "\n" not in str(exc), str(exc)
        else:
            for tr in ds:
                assert tr.time.ndim == 1 and np.all(np.diff(tr.time) > 0)
                assert np.all(np.isfinite(tr.stress)) and tr.stress.shape == tr.time.shape


def test_without_h5py_both_ends_name_the_extra(monkeypatch, tmp_path):
    """Without h5py, loading and saving an HDF5 log say which extra to install, as every
    optional package does (it was an ImportError of the loader's own wording)."""
    from mudrft.calibration import example_dataset
    from mudrft.io import save_intrusion_hdf5

    path = _h5(tmp_path, lambda fh: fh.create_dataset("depth", data=DEPTH))
    monkeypatch.setitem(sys.modules, "h5py", None)  # import h5py -> ImportError
    with pytest.raises(MudrftError, match=r"load_intrusion_hdf5 needs .*h5py.*mudrft\[hdf5\]"):
        load_intrusion_hdf5(path)
    with pytest.raises(MudrftError, match=r"save_intrusion_hdf5 needs .*h5py.*mudrft\[hdf5\]"):
        save_intrusion_hdf5(example_dataset(), tmp_path / "out.h5")
    assert not (tmp_path / "out.h5").exists()
