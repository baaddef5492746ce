"""Calibrate the mud model to your own mud: offline fits with uncertainty, online estimation.

>>> from mudrft.calibration import calibrate, example_dataset
>>> data = example_dataset("vertical")        # synthetic, shipped with mudrft
>>> data.synthetic
True

Offline: :func:`calibrate` returns a :class:`FitResult`. Online: :class:`OnlineEstimator`
and :class:`StreamClassifier`. Data: :mod:`mudrft.io`.
"""

from .._validation import CalibrationWarning
from ..io import (
    IntrusionDataset,
    Trial,
    load_dataset,
    load_intrusion_csv,
    load_intrusion_hdf5,
    save_intrusion_csv,
    save_intrusion_hdf5,
)
from ._problem import DEFAULT_BOUNDS, GROUPS
from .classification import Classification, StreamClassifier, classify
from .fit import calibrate
from .online import OnlineEstimate, OnlineEstimator
from .persistence import load_parameters
from .result import FitResult
from .stages import StageReport
from .synthetic import EXAMPLE_FILES, example_dataset, synthetic_dataset

RecursiveEstimator = OnlineEstimator

__all__ = [
    "DEFAULT_BOUNDS", "EXAMPLE_FILES", "GROUPS", "CalibrationWarning", "Classification",
    "FitResult", "IntrusionDataset", "OnlineEstimate", "OnlineEstimator", "RecursiveEstimator",
    "StageReport", "StreamClassifier", "Trial", "calibrate", "classify", "example_dataset",
    "load_dataset", "load_intrusion_csv", "load_intrusion_hdf5", "load_parameters",
    "save_intrusion_csv", "save_intrusion_hdf5", "synthetic_dataset",
]  # fmt: skip
