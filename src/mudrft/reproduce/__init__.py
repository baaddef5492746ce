"""``mudrft reproduce``: the paper's comparisons, as the paper computes them, under several readings.

* :mod:`~mudrft.reproduce.readings`: the readings of the paper (:data:`READINGS`), each
  justified by its text; :data:`HEADLINE` is the paper's own quasi-static evaluation; the
  stance depths (:data:`STANCE_DEPTHS`) and pad-curl delays it is also evaluated at;
* :mod:`~mudrft.reproduce.claims`: the nine claims and their evaluation (:data:`CLAIMS`);
* :mod:`~mudrft.reproduce.runner`: :func:`reproduce`, the runs, ``summary.csv``;
* :mod:`~mudrft.reproduce.report`: ``report.md``, ``claims.csv`` and ``depths.csv``;
* :mod:`~mudrft.reproduce.figures`: the PNG figures.
"""

from .claims import CLAIMS, LOAD, REQUIRED_RATIO, Cell, Claim, evaluate
from .readings import CURL_DELAYS, HEADLINE, READINGS, STANCE_DEPTHS, Reading
from .runner import FEET, SUMMARY_COLUMNS, WATER_CONTENTS, read_summary, reproduce

__all__ = [
    "CLAIMS", "CURL_DELAYS", "FEET", "HEADLINE", "LOAD", "READINGS", "REQUIRED_RATIO",
    "STANCE_DEPTHS", "SUMMARY_COLUMNS", "WATER_CONTENTS", "Cell", "Claim", "Reading", "evaluate",
    "read_summary", "reproduce",
]  # fmt: skip
