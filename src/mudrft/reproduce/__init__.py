"""``mudrft reproduce``: the paper's comparisons, as the paper computes them, under several readings.

* :mod:`~mudrft.reproduce.readings`: the readings of the paper (:data:`READINGS`), each
  justified by its text; :data:`HEADLINE` is the paper's own quasi-static evaluation;
* :mod:`~mudrft.reproduce.claims`: the nine claims and their evaluation (:data:`CLAIMS`);
* :mod:`~mudrft.reproduce.runner`: :func:`reproduce`, the runs, ``summary.csv``;
* :mod:`~mudrft.reproduce.report`: ``report.md`` and ``claims.csv``;
* :mod:`~mudrft.reproduce.figures`: the PNG figures.
"""

from .claims import CLAIMS, Cell, Claim, evaluate, inconsistency
from .readings import HEADLINE, READINGS, Reading
from .runner import FEET, LOAD, SUMMARY_COLUMNS, WATER_CONTENTS, read_summary, reproduce

__all__ = [
    "CLAIMS",
    "FEET",
    "HEADLINE",
    "LOAD",
    "READINGS",
    "SUMMARY_COLUMNS",
    "WATER_CONTENTS",
    "Cell",
    "Claim",
    "Reading",
    "evaluate",
    "inconsistency",
    "read_summary",
    "reproduce",
]
