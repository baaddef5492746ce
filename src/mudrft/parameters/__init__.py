"""Parameter sets of the mud model: typed, frozen, in SI units, with their sources."""

from .base import PARAMETER_UNITS, Mud, MudParameters
from .registry import (
    DIRECTIONS,
    EXTRAPOLATION_RANGE,
    LABELLINGS,
    WATER_CONTENT_RANGE,
    paper_mud,
    paper_parameters,
    sigma_y_consistency,
    table_rows,
)

__all__ = [
    "DIRECTIONS", "EXTRAPOLATION_RANGE", "LABELLINGS", "PARAMETER_UNITS", "WATER_CONTENT_RANGE",
    "Mud", "MudParameters", "paper_mud", "paper_parameters", "sigma_y_consistency", "table_rows",
]  # fmt: skip
