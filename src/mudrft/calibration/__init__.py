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

Modules, one concept each:

* :mod:`.fit`: :func:`calibrate`, the driver: checked inputs, stages, the result;
* :mod:`.stages`: start, phase-by-phase and joint stages, uncertainty at the optimum;
* :mod:`._engine`: bounded least squares in log-parameters with variable projection;
* :mod:`._problem`: trials packed for batched simulation, phases of a trial;
* :mod:`._options`: parameter groups, bounds, accepted datasets, decimation;
* :mod:`.sensors`: a saturated or unzeroed force sensor in a log (D153, D154);
* :mod:`.uncertainty`: covariance, intervals, identifiability verdicts (D44);
* :mod:`.result`, :mod:`.persistence`, :mod:`._plot`: :class:`FitResult`, JSON files, figure;
* :mod:`.online`, :mod:`._rls`: the recursive estimator (D46);
* :mod:`.classification`: which known mud the data resemble (D47);
* :mod:`.synthetic`: the synthetic example data.
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
from ._options import DEFAULT_BOUNDS, GROUPS
from .classification import Classification, StreamClassifier, classify
from .fit import calibrate
from .online import OnlineEstimate, OnlineEstimator
from .persistence import load_parameters
from .result import FitResult, StageReport
from .synthetic import EXAMPLE_FILES, example_dataset, synthetic_dataset

RecursiveEstimator = OnlineEstimator

__all__ = [
    "DEFAULT_BOUNDS",
    "EXAMPLE_FILES",
    "GROUPS",
    "CalibrationWarning",
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
