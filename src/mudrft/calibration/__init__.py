"""Calibrate the mud model to your own mud: offline fits with uncertainty, online estimation.

>>> from mudrft.calibration import calibrate, example_dataset
>>> data = example_dataset("vertical")        # synthetic, shipped with mudrft
>>> data.synthetic
True

Offline: :func:`calibrate` returns a :class:`FitResult` (parameters, standard errors,
confidence intervals, correlation, identifiability verdicts, RMSE, status, trace).
Online: :class:`OnlineEstimator` (recursive least squares with forgetting of the
paper's linear-in-parameter combinations) and :class:`StreamClassifier` (which
known parameter set a stream resembles). Data: :mod:`mudrft.io`.
"""

from ..io import (
    IntrusionDataset,
    Trial,
    load_dataset,
    load_intrusion_csv,
    load_intrusion_hdf5,
    save_intrusion_csv,
    save_intrusion_hdf5,
)
from .fit import DEFAULT_BOUNDS, GROUPS, FitResult, StageReport, calibrate, load_parameters
from .online import Classification, OnlineEstimate, OnlineEstimator, StreamClassifier, classify
from .synthetic import EXAMPLE_FILES, example_dataset, synthetic_dataset

RecursiveEstimator = OnlineEstimator

__all__ = [
    "DEFAULT_BOUNDS",
    "EXAMPLE_FILES",
    "GROUPS",
    "Classification",
    "FitResult",
    "IntrusionDataset",
    "OnlineEstimate",
    "OnlineEstimator",
    "RecursiveEstimator",
    "StageReport",
    "StreamClassifier",
    "Trial",
    "calibrate",
    "classify",
    "example_dataset",
    "load_dataset",
    "load_intrusion_csv",
    "load_intrusion_hdf5",
    "load_parameters",
    "save_intrusion_csv",
    "save_intrusion_hdf5",
    "synthetic_dataset",
]
