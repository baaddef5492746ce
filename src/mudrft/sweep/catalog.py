"""What a sweep can vary and measure: the named parameters of the foot, the mud and the
motion, and the metrics, each with its type and SI unit.

A parameter's name is its key in the spec file (``[foot] radius = ...``) and its dimension
(or coordinate) in the result; names are unique across the three sections, so a result
reads ``ds.sel(radius=0.045, water_content=0.25)``.

>>> PARAMETERS["radius"].unit, PARAMETERS["water_content"].section
('m', 'mud')
>>> foot_parameters("semi-sphere")
('radius', 'height')
>>> metric_names("gait")[:2]
('peak_support', 'max_suction')
"""

from __future__ import annotations

from dataclasses import dataclass, fields

from ..feet.morphing.linkage import MorphingFootGeometry
from ..feet.morphing.springs import TwoStageSpring

__all__ = [
    "FOOT_KINDS",
    "METRICS",
    "MOTION_KINDS",
    "PARAMETERS",
    "SECTIONS",
    "Metric",
    "Parameter",
    "foot_parameters",
    "metric_names",
    "motion_parameters",
]

#: The sections of a spec that hold parameters.
SECTIONS = ("foot", "mud", "motion")


@dataclass(frozen=True)
class Parameter:
    """A named input a sweep may fix or vary.

    Attributes
    ----------
    name : str
        Key in the spec and dimension name in the result.
    section : {"foot", "mud", "motion"}
        Where it belongs.
    kind : {"float", "int", "str", "bool"}
        Its type; only numbers can be ranges or sampled.
    unit : str
        SI unit (``"-"`` for none).
    doc : str
        One line for the documentation and the result's ``long_name``.
    choices : tuple of str
        Allowed values of a string parameter (empty: any).
    sweepable : bool
        False for options that must stay fixed over a sweep (``extrapolate``, ``labels``).
    """

    name: str
    section: str
    kind: str
    unit: str
    doc: str
    choices: tuple[str, ...] = ()
    sweepable: bool = True


def _p(section: str, name: str, kind: str, unit: str, doc: str, **kw: object) -> Parameter:
    return Parameter(name, section, kind, unit, doc, **kw)  # type: ignore[arg-type]


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

_FOOT = [
    _p("foot", "length", "float", "m", "flat foot length L (along y)"),
    _p("foot", "width", "float", "m", "flat or semi-cylinder foot width W"),
    _p("foot", "radius", "float", "m", "semi-cylinder or semi-sphere radius R"),
    _p("foot", "height", "float", "m", "foot height above its tip"),
    _p(
        "foot",
        "mode",
        "str",
        "-",
        "morphing foot mode",
        choices=("morphing", "expanded", "retracted"),
    ),
    _p("foot", "seal_length", "float", "m", "morphing foot rim lift that breaks the seal"),
]
_MORPHING_UNITS = {"n_pads": "-", "crank_offset": "rad", "retracted_angle": "rad", "expanded_angle": "rad"}  # fmt: skip


def _morphing_fields() -> list[Parameter]:
    # the morphing foot's geometry and springs, by their dataclass fields (D30, D31)

    out = []
    for cls in (MorphingFootGeometry, TwoStageSpring):
        for f in fields(cls):
            if f.name in ("height",):
                continue  # shared with the closed-form feet, listed above
            unit = _MORPHING_UNITS.get(f.name, "N/m" if "stiffness" in f.name else "m")
            kind = "int" if f.name == "n_pads" else "float"
            out.append(_p("foot", f.name, kind, unit, f"morphing foot {f.name.replace('_', ' ')}"))
    return out


_MORPHING = _morphing_fields()

_MUD = [
    _p("mud", "water_content", "float", "-", "water content W of the paper's mud"),
    _p("mud", "mud_set", "str", "-", "a calibrated parameter set named in [mud.sets]"),
    *(
        _p("mud", f"{k}_scale", "float", "-", f"factor on the {doc} (both directions)")
        for k, doc in _MUD_FIELDS.items()
    ),
    _p("mud", "thixotropy", "str", "-", "evaluation of eqs. (3), (5) (D15)", choices=("ode", "quasi-static")),
    _p("mud", "clock", "str", "-", "quasi-static clock (D15)", choices=("contact", "retraction")),
    _p("mud", "xi0", "float", "-", "initial structure xi(0)"),
    _p("mud", "extrapolate", "bool", "-", "allow water contents outside the tables", sweepable=False),
    _p("mud", "labels", "str", "-", "water content labels of the table rows", choices=("table", "text"), sweepable=False),
]  # fmt: skip

#: Motions: ``gait`` (one stepping cycle, :func:`mudrft.gait`), ``load`` (a foot under a
#: load, :class:`mudrft.LoadControl`) and ``walk`` (the MuJoCo biped; needs mudrft[mujoco]).
MOTION_KINDS = ("gait", "load", "walk")

_MOTION = {
    "gait": [
        _p("motion", "speed", "float", "m/s", "gait speed"),
        _p("motion", "depth", "float", "m", "deepest tip depth of the gait"),
        _p("motion", "stride", "float", "m", "stride length"),
        _p("motion", "slip", "float", "-", "forward slip as a fraction of the stride"),
        _p("motion", "sway", "float", "-", "lateral sway as a fraction of the stride"),
        _p("motion", "lift", "float", "m", "tip height at the end of the swing"),
        _p("motion", "dt", "float", "s", "time step"),
    ],
    "load": [
        _p("motion", "weight", "float", "N", "load pressing the foot into the mud"),
        _p("motion", "mass", "float", "kg", "mass of the loaded body"),
        _p("motion", "leg_stiffness", "float", "N/m", "stiffness of a spring leg"),
        _p("motion", "leg_damping", "float", "N s/m", "damping of the spring leg"),
        _p("motion", "foot_mass", "float", "kg", "mass of the foot below a spring leg"),
        _p("motion", "duration", "float", "s", "simulated time"),
        _p("motion", "dt", "float", "s", "time step"),
        _p("motion", "ramp", "float", "s", "time over which the load rises"),
    ],
    "walk": [
        _p("motion", "seconds", "float", "s", "simulated walking time"),
        _p("motion", "dt", "float", "s", "physics time step"),
        _p("motion", "speed", "float", "m/s", "walking speed command"),
        _p("motion", "step_time", "float", "s", "duration of a step"),
        _p("motion", "bottom", "float", "m", "depth of the rigid bed under the mud"),
    ],
}


def _catalog() -> dict[str, Parameter]:
    out: dict[str, Parameter] = {}
    for p in (*_FOOT, *_MORPHING, *_MUD, *(q for v in _MOTION.values() for q in v)):
        if p.name in out and out[p.name] != p and p.section != "motion":
            raise AssertionError(f"parameter {p.name} is defined twice")  # pragma: no cover
        out.setdefault(p.name, p)
    return out


#: Every parameter by name (a motion parameter such as ``dt`` or ``speed`` appears once,
#: with the documentation of the first motion that has it).
PARAMETERS: dict[str, Parameter] = _catalog()

#: The foot kinds and the parameters each accepts (a mesh file path accepts none).
FOOT_KINDS: dict[str, tuple[str, ...]] = {
    "flat": ("length", "width", "height"),
    "semi-cylinder": ("radius", "width", "height"),
    "semi-sphere": ("radius", "height"),
    "morphing": (
        "mode",
        "seal_length",
        "height",
        *(p.name for p in _MORPHING),
    ),
}


def foot_parameters(kind: str) -> tuple[str, ...]:
    """The parameters of a foot kind (none for a mesh file)."""
    return FOOT_KINDS.get(kind, ())


def motion_parameters(kind: str) -> tuple[str, ...]:
    """The parameters of a motion kind (``gait``, ``load``, ``walk``)."""
    return tuple(p.name for p in _MOTION[kind])


def motion_parameter(kind: str, name: str) -> Parameter:
    """The parameter ``name`` as the motion ``kind`` documents it."""
    return next(p for p in _MOTION[kind] if p.name == name)


@dataclass(frozen=True)
class Metric:
    """A number a sweep measures at every point.

    Attributes
    ----------
    name : str
        Variable name in the result.
    unit : str
        SI unit.
    doc : str
        One line (the result's ``long_name``).
    key : str
        Key of the metric in ``Result.metrics()`` or the walk summary.
    """

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
    Metric("sinking", "m", "sinking (deepest depth; final depth under a load)", "sinking"),
    Metric("suction_ratio", "-", "max suction / peak support", "suction_ratio"),
)  # fmt: skip
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

#: The metrics of each motion kind.
METRICS: dict[str, dict[str, Metric]] = {
    "gait": {m.name: m for m in _CYCLE},
    "load": {m.name: m for m in _CYCLE},
    "walk": {m.name: m for m in _WALK},
}


def metric_names(motion: str) -> tuple[str, ...]:
    """The metrics a motion kind measures, in their documented order."""
    return tuple(METRICS[motion])
