"""HDF5 intrusion logs that the loader used to misread without a word, or answer with a
traceback or an error that names no file: each is now read as written or refused with a
MudrftError naming the file and the dataset, link or attribute."""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from mudrft._validation import MudrftError
from mudrft.io import load_intrusion_hdf5

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
