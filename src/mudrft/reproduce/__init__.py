"""``mudrft reproduce``: the paper's comparisons, as the paper computes them, under several
readings (:mod:`.readings`), as nine claims (:mod:`.claims`), run by :func:`reproduce`
(:mod:`.runner`) into tables (:mod:`.report`) and figures (:mod:`.figures`)."""

from .claims import CLAIMS, LOAD, REQUIRED_RATIO, Cell, Claim, evaluate
from .readings import CURL_DELAYS, HEADLINE, READINGS, STANCE_DEPTHS, Reading
from .runner import FEET, SUMMARY_COLUMNS, WATER_CONTENTS, read_summary, reproduce

__all__ = [
    "CLAIMS", "CURL_DELAYS", "FEET", "HEADLINE", "LOAD", "READINGS", "REQUIRED_RATIO",
    "STANCE_DEPTHS", "SUMMARY_COLUMNS", "WATER_CONTENTS", "Cell", "Claim", "Reading", "evaluate",
    "read_summary", "reproduce",
]  # fmt: skip
