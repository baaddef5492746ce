"""Parameter tables of Chen et al. (2026), supplementary Tables S1 and S2, transcribed as
printed, in the units of :data:`PRINTED_UNITS` (converted to SI when a parameter set is built;
the viscosities' "MPa/s" read as MPa s, erratum E1).
"""

from __future__ import annotations

from typing import Final

from ..units import MPA

__all__ = ["CITATION_KEY", "COLUMNS", "HORIZONTAL", "PRINTED_UNITS", "TABLE_NAME", "VERTICAL"]

CITATION_KEY: Final = "chen2026mud"

#: Unit of each column as printed (in the order printed), and the factor to SI.
PRINTED_UNITS: Final = {
    "alpha": ("MPa", MPA),
    "n": ("-", 1.0),
    "lam": ("(none; read s)", 1.0),
    "eta_m": ("MPa/s (read MPa s)", MPA),
    "eta_inf": ("MPa/s (read MPa s)", MPA),
    "gamma_dot_c": ("1/s", 1.0),
    "tau_build": ("s", 1.0),
    "tau_leak": ("s", 1.0),
    "epsilon": ("-", 1.0),
    "sigma_y": ("MPa", MPA),
}

#: Column names of the tables, in the order printed.
COLUMNS: Final = tuple(PRINTED_UNITS)

TABLE_NAME: Final = {
    "vertical": "supplementary Table S1 (vertical intrusion)",
    "horizontal": "supplementary Table S2 (horizontal intrusion)",
}

# water content -> row, as printed, in the order of COLUMNS
VERTICAL: Final[dict[float, tuple[float, ...]]] = {
    0.25: (0.024, 0.53, 1.9, 0.067, 0.014, 0.14, 0.32, 0.17, 0.016, 0.0071),
    0.35: (0.013, 0.20, 3.2, 0.27, 0.0031, 0.042, 0.49, 0.089, 0.054, 0.011),
    0.45: (0.010, 0.18, 2.6, 0.31, 0.0026, 0.027, 0.58, 0.052, 0.040, 0.0086),
}

HORIZONTAL: Final[dict[float, tuple[float, ...]]] = {
    0.25: (0.018, 0.12, 1.8, 0.46, 0.010, 0.31, 0.63, 0.99, 0.027, 0.013),
    0.35: (0.011, 0.32, 17.0, 0.41, 0.021, 0.019, 0.25, 0.67, 0.14, 0.0094),
    0.45: (0.0078, 0.95, 8.7, 0.63, 0.065, 0.028, 0.21, 0.022, 0.12, 0.0061),
}
