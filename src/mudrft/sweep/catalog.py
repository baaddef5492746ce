"""What a sweep can vary and measure: the parameters of the foot, the mud and the motion,
each with its type, SI unit and allowed range, and the metrics.

A parameter's name is its key in the spec and its coordinate in the result; a spec value
outside its range is refused before anything runs.

>>> PARAMETERS["radius"].unit, PARAMETERS["water_content"].section
('m', 'mud')
>>> PARAMETERS["width"].check("[foot] width", -0.05)
Traceback (most recent call last):
...
mudrft._validation.MudrftError: [foot] width must be > 0 [m], got -0.05
"""

from __future__ import annotations

import math
import operator
from dataclasses import dataclass
from typing import Any

from .._validation import MudrftError
from ..parameters.registry import EXTRAPOLATION_RANGE

_INT_LIMIT = 2**53  # integers an int64 coordinate and a float64 both hold exactly
_OPS = {">": operator.gt, ">=": operator.ge, "<=": operator.le}


@dataclass(frozen=True)
class Parameter:
    """A named input of ``section`` ("foot", "mud", "motion") a sweep may fix or vary.

    Its ``kind`` is "float", "int", "str" or "bool" (numbers only take ranges); its values
    are ``> gt``, ``>= ge``, ``<= le`` [``unit``] where given, or one of ``choices``;
    ``doc`` is the result's ``long_name``; options such as ``extrapolate`` are not
    ``sweepable``.
    """

    name: str
    section: str
    kind: str
    unit: str
    doc: str
    gt: float | None = None
    ge: float | None = None
    le: float | None = None
    choices: tuple[str, ...] = ()
    sweepable: bool = True

    def check(self, where: str, v: object) -> Any:
        """``v`` as a plain Python value of this parameter, or a MudrftError naming ``where``."""
        if self.kind == "bool":
            if not isinstance(v, bool):
                raise MudrftError(f"{where} must be true or false, got {v!r}")
            return v
        if self.kind == "str":
            if not isinstance(v, str) or (self.choices and v not in self.choices):
                expected = f"one of {', '.join(self.choices)}" if self.choices else "a string"
                raise MudrftError(f"{where} must be {expected}, got {v!r}")
            return v
        if isinstance(v, bool) or not isinstance(v, int | float):
            what = "an integer" if self.kind == "int" else "a number"
            raise MudrftError(f"{where} must be {what} [{self.unit}], a list of them or a table {{low, high, num}}, got {v!r}")  # fmt: skip
        if self.kind == "int" and not isinstance(v, int):
            raise MudrftError(f"{where} must be an integer, got {v!r}")
        if self.kind == "int" and abs(v) > _INT_LIMIT:
            raise MudrftError(f"{where} must be an integer of magnitude at most 2**53, got {v!r}")
        if not math.isfinite(v):
            raise MudrftError(f"{where} must be finite [{self.unit}], got {v!r}")
        for op, bound in ((">", self.gt), (">=", self.ge), ("<=", self.le)):
            if bound is not None and not _OPS[op](v, bound):
                raise MudrftError(f"{where} must be {op} {bound:g} [{self.unit}], got {v!r}")
        return int(v) if self.kind == "int" else float(v)


def _p(section: str, name: str, unit: str, doc: str, kind: str = "float", **kw: Any) -> Parameter:
    return Parameter(name, section, kind, unit, doc, **kw)


_FOOT = [
    _p("foot", "length", "m", "flat foot length L (along y)", gt=0.0),
    _p("foot", "width", "m", "flat or semi-cylinder foot width W", gt=0.0),
    _p("foot", "radius", "m", "semi-cylinder or semi-sphere radius R", gt=0.0),
    _p("foot", "height", "m", "foot height above its tip", gt=0.0),
    _p("foot", "mode", "-", "morphing foot mode", "str", choices=("morphing", "expanded", "retracted")),
    _p("foot", "seal_length", "m", "morphing foot rim lift that breaks the seal", gt=0.0),
]  # fmt: skip
#: The morphing foot's geometry and springs (fields of MorphingFootGeometry, TwoStageSpring).
_MORPHING = [
    _p("foot", "n_pads", "-", "morphing foot number of pads", "int", ge=1),
    *(_p("foot", k, "m", f"morphing foot {k.replace('_', ' ')}", gt=0.0) for k in (
        "base_radius", "pivot_height", "column_radius", "pad_length", "pad_inner_width",
        "pad_outer_width", "crank_length", "coupler_length", "soft_travel")),
    _p("foot", "pole_radius", "m", "morphing foot pole radius", ge=0.0),
    _p("foot", "crank_offset", "rad", "morphing foot crank offset"),
    _p("foot", "retracted_angle", "rad", "morphing foot retracted angle", ge=0.0, le=math.pi / 2),
    _p("foot", "expanded_angle", "rad", "morphing foot expanded angle", ge=0.0, le=math.pi / 2),
    _p("foot", "soft_stiffness", "N/m", "morphing foot soft stiffness", gt=0.0),
    _p("foot", "hard_stiffness", "N/m", "morphing foot hard stiffness", gt=0.0),
]  # fmt: skip

_MUD_FIELDS = {
    "alpha": "stiffness alpha of the immediate resistance",
    "n": "exponent n of the immediate resistance",
    "lam": "relaxation time lambda",
    "eta_m": "structural viscosity eta_m",
    "eta_inf": "shear viscosity eta_inf",
    "gamma_dot_c": "critical rate gamma_dot_c",
    "tau_build": "suction build-up time tau_build",
    "tau_leak": "suction leak time tau_leak",
    "epsilon": "sealing width epsilon",
    "sigma_y": "yield stress sigma_y (limit of suction)",
    "nu": "switch width nu",
}
_W_LOW, _W_HIGH = EXTRAPOLATION_RANGE  # paper_mud's widest range
_MUD = [
    _p("mud", "water_content", "-", "water content W of the paper's mud", ge=_W_LOW, le=_W_HIGH),
    _p("mud", "mud_set", "-", "a calibrated parameter set named in [mud.sets]", "str"),
    *(_p("mud", f"{k}_scale", "-", f"factor on the {doc} (both directions)", gt=0.0) for k, doc in _MUD_FIELDS.items()),
    _p("mud", "thixotropy", "-", "evaluation of eqs. (3), (5)", "str", choices=("ode", "quasi-static")),
    _p("mud", "clock", "-", "quasi-static clock", "str", choices=("contact", "retraction")),
    _p("mud", "xi0", "-", "initial structure xi(0)", ge=0.0, le=1.0),
    _p("mud", "extrapolate", "-", "allow water contents outside the tables", "bool", sweepable=False),
    _p("mud", "labels", "-", "water content labels of the table rows", "str", choices=("table", "text"), sweepable=False),
]  # fmt: skip

#: The motions and their parameters: ``gait`` (one stepping cycle, :func:`mudrft.gait`),
#: ``load`` (a foot under a load, :class:`mudrft.LoadControl`) and ``walk`` (the MuJoCo
#: biped; needs mudrft[mujoco]).
MOTIONS: dict[str, dict[str, Parameter]] = {
    kind: {p.name: p for p in params}
    for kind, params in {
        "gait": [
            _p("motion", "speed", "m/s", "gait speed", gt=0.0),
            _p("motion", "depth", "m", "deepest tip depth of the gait (default: mudrft.trajectories.STANCE_DEPTH, 0.02 m)", gt=0.0),
            _p("motion", "stride", "m", "stride length", gt=0.0),
            _p("motion", "slip", "-", "forward slip as a fraction of the stride", ge=0.0, le=1.0),
            _p("motion", "sway", "-", "lateral sway as a fraction of the stride", ge=0.0, le=1.0),
            _p("motion", "lift", "m", "tip height at the end of the swing", ge=0.0),
            _p("motion", "dt", "s", "time step", gt=0.0),
        ],
        "load": [
            _p("motion", "weight", "N", "load pressing the foot into the mud", gt=0.0),
            _p("motion", "mass", "kg", "mass of the loaded body", gt=0.0),
            _p("motion", "leg_stiffness", "N/m", "stiffness of a spring leg", gt=0.0),
            _p("motion", "leg_damping", "N s/m", "damping of the spring leg", ge=0.0),
            _p("motion", "foot_mass", "kg", "mass of the foot below a spring leg", gt=0.0),
            _p("motion", "duration", "s", "simulated time", gt=0.0),
            _p("motion", "dt", "s", "time step", gt=0.0),
            _p("motion", "ramp", "s", "time over which the load rises", ge=0.0),
        ],
        "walk": [
            _p("motion", "seconds", "s", "simulated walking time", gt=0.0),
            _p("motion", "dt", "s", "physics time step", gt=0.0),
            _p("motion", "speed", "m/s", "walking speed command", ge=0.0),
            _p("motion", "step_time", "s", "duration of a step", gt=0.0),
            _p("motion", "bottom", "m", "depth of the rigid bed under the mud", gt=0.0),
        ],
    }.items()
}  # fmt: skip
MOTION_KINDS = tuple(MOTIONS)

#: The foot and mud parameters by name, and each motion parameter as ``gait`` (or the first
#: motion that has it) documents it.
PARAMETERS: dict[str, Parameter] = {p.name: p for p in (*_FOOT, *_MORPHING, *_MUD)} | {
    name: p for kind in reversed(MOTION_KINDS) for name, p in MOTIONS[kind].items()
}

#: The foot kinds and the parameters each accepts (a mesh file path accepts none).
FOOT_KINDS: dict[str, tuple[str, ...]] = {
    "flat": ("length", "width", "height"),
    "semi-cylinder": ("radius", "width", "height"),
    "semi-sphere": ("radius", "height"),
    "morphing": ("mode", "seal_length", "height", *(p.name for p in _MORPHING)),
}


@dataclass(frozen=True)
class Metric:
    """A number a sweep measures at every point: variable ``name`` [``unit``], read from
    ``Result.metrics()`` (or the walk's summary) under ``key``."""

    name: str
    unit: str
    doc: str
    key: str


_CYCLE = (
    Metric("peak_support", "N", "peak support force (largest Fz)", "peak_support"),
    Metric("max_suction", "N", "largest suction (magnitude of the most negative Fz)", "max_suction"),
    Metric("impulse_x", "N s", "impulse of Fx", "impulse_x"),
    Metric("impulse_y", "N s", "impulse of Fy", "impulse_y"),
    Metric("impulse_z", "N s", "impulse of Fz", "impulse_z"),
    Metric("energy", "J", "work of the foot against the mud", "energy"),
    Metric("max_depth", "m", "deepest tip depth (a gait's prescribed stance depth)", "max_depth"),
    Metric("suction_ratio", "-", "max suction / peak support", "suction_ratio"),
)  # fmt: skip
_SINKING = Metric("sinking", "m", "sinking: the settled (final) depth under the load", "sinking")
_WALK = (
    Metric("fell", "-", "1 if the biped fell, else 0", "fell"),
    Metric("distance", "m", "distance walked", "distance [m]"),
    Metric("energy_per_step", "J", "positive joint work per step", "energy_per_step [J]"),
    Metric("absolute_work_per_step", "J", "absolute joint work per step", "absolute_work_per_step [J]"),
    Metric("mean_slip", "m", "mean foot slip per step", "mean_slip [m]"),
    Metric("mean_sinking", "m", "mean sinking of the feet", "mean_sinking [m]"),
    Metric("max_suction", "N", "largest suction on a foot", "max_suction [N]"),
    Metric("max_suction_over_weight", "-", "largest suction over the robot's weight", "max_suction_over_weight"),
    Metric("mean_speed", "m/s", "mean walking speed", "mean_speed [m/s]"),
    Metric("min_torso_height", "m", "lowest torso height", "min_torso_height [m]"),
)  # fmt: skip

#: The metrics of each motion kind, in their documented order.
METRICS: dict[str, dict[str, Metric]] = {
    "gait": {m.name: m for m in _CYCLE},
    "load": {m.name: m for m in (*_CYCLE, _SINKING)},
    "walk": {m.name: m for m in _WALK},
}
