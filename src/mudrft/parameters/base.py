"""Typed, frozen parameter sets of the mud model (SI units): :class:`MudParameters` holds
the constants of eqs. (1)-(5) for one direction (array fields: a batch), :class:`Mud` pairs
the vertical and horizontal sets of one mud."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .._typing import FloatOrArray
from .._validation import MudrftError, check_broadcast, check_finite, check_number, check_positive

__all__ = ["PARAMETER_UNITS", "POSITIVE_FIELDS", "Mud", "MudParameters"]

#: SI unit of every field of :class:`MudParameters`.
PARAMETER_UNITS: dict[str, str] = {
    "alpha": "Pa", "n": "-", "lam": "s", "eta_m": "Pa s", "eta_inf": "Pa s", "gamma_dot_c": "1/s",
    "tau_build": "s", "tau_leak": "s", "epsilon": "-", "sigma_y": "Pa", "nu": "1/s", "k_a": "1/s",
}  # fmt: skip

#: Fields that must be strictly positive: every field of :class:`MudParameters`.
POSITIVE_FIELDS = tuple(PARAMETER_UNITS)


def check_water_content(value: ArrayLike | None) -> float | None:
    """``water_content`` [-]: None, or one volume fraction in [0, 1] as a float."""
    if value is None:
        return None
    w = check_number("water_content", check_finite("water_content", value))
    if not 0.0 <= w <= 1.0:
        hint = " (give a fraction: 25 % is 0.25)" if 1 < w <= 100 else ""
        raise MudrftError(f"water_content must be a volume fraction in [0, 1], got {w!r}{hint}")
    return w


@dataclass(frozen=True, eq=False)
class MudParameters:
    r"""Constants of the mud constitutive model for one direction, in SI units.

    Parameters
    ----------
    alpha : float
        Stiffness of the immediate resistance :math:`\sigma_b=\alpha\gamma^n` [Pa].
    n : float
        Exponent of the immediate resistance, in (0, 1] [-].
    lam : float
        Relaxation time :math:`\lambda=\eta_m/G_m` of the thixotropic stress [s].
    eta_m : float
        Structural viscosity :math:`\eta_m` [Pa s].
    eta_inf : float
        Shear (infinite-rate) viscosity :math:`\eta_\infty` [Pa s].
    gamma_dot_c : float
        Critical rate :math:`\dot\gamma_c=k_a/k_r` at which the mud fluidizes [1/s].
    tau_build : float
        Time scale of suction build-up while the cavity is sealed [s].
    tau_leak : float
        Time scale of suction leak while the cavity is open [s].
    epsilon : float
        Width of the sealing function :math:`\phi_\varepsilon` in dimensionless displacement [-].
    sigma_y : float
        Yield stress :math:`\sigma_Y`, the limit of suction [Pa].
    nu : float, optional
        Width of the switch :math:`H_\nu` [1/s] (the paper gives none; decision D5).
    k_a : float or None, optional
        Aging rate of the structure [1/s]; ``None``: :math:`1/\lambda` (decision D3).
    source : str, optional
        Where the numbers come from.
    water_content : float or None, optional
        Volumetric water content [-], if known.
    direction : str, optional
        ``"vertical"``, ``"horizontal"`` or ``""``.

    Examples
    --------
    >>> import mudrft
    >>> p = mudrft.paper_parameters(water_content=0.25, direction="vertical")
    >>> p.alpha, p.eta_m
    (24000.0, 67000.0)
    """

    alpha: FloatOrArray
    n: FloatOrArray
    lam: FloatOrArray
    eta_m: FloatOrArray
    eta_inf: FloatOrArray
    gamma_dot_c: FloatOrArray
    tau_build: FloatOrArray
    tau_leak: FloatOrArray
    epsilon: FloatOrArray
    sigma_y: FloatOrArray
    nu: FloatOrArray = 0.01
    k_a: Any = None  # None asks for 1/lam, which __post_init__ puts in its place
    source: str = field(default="", compare=False)
    water_content: float | None = field(default=None, compare=False)
    direction: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        for name in POSITIVE_FIELDS:
            if name == "k_a" and self.k_a is None:
                continue  # follows lam, once lam is known to be > 0
            arr = check_positive(name, getattr(self, name), unit=PARAMETER_UNITS[name])
            object.__setattr__(self, name, float(arr) if arr.ndim == 0 else arr)
        if self.k_a is None:
            object.__setattr__(self, "k_a", 1.0 / self.lam)  # lam is a float or an array here
        # a batch: fields of one broadcastable shape with at least one set
        shapes = {k: np.shape(getattr(self, k)) for k in PARAMETER_UNITS}
        shape = check_broadcast(**shapes)
        if 0 in shape:
            empty = next(k for k, v in shapes.items() if 0 in v)
            raise MudrftError(
                f"{empty} must hold at least one value, got an array of shape {shapes[empty]}"
            )
        if np.any(np.asarray(self.n) > 1.0):
            raise MudrftError(f"n must lie in (0, 1], got {float(np.max(self.n))!r}")
        object.__setattr__(self, "water_content", check_water_content(self.water_content))
        if self.direction not in ("", "vertical", "horizontal"):
            raise MudrftError(
                f"direction must be 'vertical', 'horizontal' or '', got {self.direction!r}"
            )

    @property
    def k_r(self) -> FloatOrArray:
        """Rejuvenation coefficient :math:`k_r = k_a/\\dot\\gamma_c` [-]."""
        return self.k_a / self.gamma_dot_c

    @property
    def G_m(self) -> FloatOrArray:
        """Elastic modulus :math:`G_m=\\eta_m/\\lambda` [Pa]."""
        return self.eta_m / self.lam

    def replace(self, **changes: Any) -> MudParameters:
        """A copy with some fields changed (validated); a new ``lam`` moves a default ``k_a``."""
        default_k_a = np.all(np.isclose(np.asarray(self.k_a), 1.0 / np.asarray(self.lam)))
        if "lam" in changes and "k_a" not in changes and default_k_a:
            changes["k_a"] = None
        return dataclasses.replace(self, **changes)

    def as_dict(self) -> dict[str, Any]:
        """The numeric fields as a dict of floats or lists (SI), for JSON."""
        return {name: np.asarray(getattr(self, name)).tolist() for name in PARAMETER_UNITS}

    @classmethod
    def from_dict(cls, data: dict[str, Any], **meta: Any) -> MudParameters:
        """Build a set from a dict with the field names of :data:`PARAMETER_UNITS` (SI)."""
        if not isinstance(data, Mapping):
            raise MudrftError(
                f"data must be a dict of the fields {list(PARAMETER_UNITS)}, got "
                f"{type(data).__name__}"
            )
        missing = [k for k in PARAMETER_UNITS if k not in data and k not in ("nu", "k_a")]
        if missing:
            raise MudrftError(f"parameter dict is missing the fields {missing}")
        unknown = [k for k in data if k not in PARAMETER_UNITS]
        if unknown:
            raise MudrftError(
                f"parameter dict has unknown fields {unknown}; expected {list(PARAMETER_UNITS)}"
            )
        return cls(**data, **meta)

    @property
    def shape(self) -> tuple[int, ...]:
        """Broadcast shape of the fields (``()`` for a single set)."""
        return np.broadcast_shapes(*(np.shape(getattr(self, k)) for k in PARAMETER_UNITS))

    @classmethod
    def stack(cls, sets: list[MudParameters]) -> MudParameters:
        """Stack several sets into one batched set with fields of shape ``(len(sets),)``."""
        if not sets:
            raise MudrftError("sets must contain at least one MudParameters, got an empty list")
        for i, one in enumerate(sets):
            if not isinstance(one, MudParameters):
                raise MudrftError(f"sets[{i}] must be a MudParameters, got {type(one).__name__}")
            if one.shape != ():
                raise MudrftError(
                    f"sets[{i}] must be a single parameter set, got a batch of shape {one.shape}"
                )
        fields: dict[str, Any] = {
            k: np.array([np.asarray(getattr(s, k), dtype=float) for s in sets])
            for k in PARAMETER_UNITS
        }
        return cls(**fields, source="stack")

    def __repr__(self) -> str:
        body = ", ".join(f"{k}={np.asarray(getattr(self, k)).tolist()!r}" for k in PARAMETER_UNITS)
        tag = f", source={self.source!r}" if self.source else ""
        return f"MudParameters({body}{tag})"


@dataclass(frozen=True, eq=False)
class Mud:
    """One mud, a terrain for :func:`mudrft.simulate`: the ``vertical`` set drives the z
    channel, the ``horizontal`` set x and y (Sec. II-C); ``water_content`` [-] if known,
    and a ``name`` for reports."""

    vertical: MudParameters
    horizontal: MudParameters
    water_content: float | None = None
    name: str = "mud"

    def __post_init__(self) -> None:
        object.__setattr__(self, "water_content", check_water_content(self.water_content))
        if not isinstance(self.name, str):
            raise MudrftError(f"name must be a string, got {self.name!r}")
        for attr in ("vertical", "horizontal"):
            value = getattr(self, attr)
            if not isinstance(value, MudParameters):
                raise MudrftError(f"{attr} must be a MudParameters, got {type(value).__name__}")
            if value.direction not in ("", attr):  # a set fitted to the other direction
                raise MudrftError(
                    f"{attr} must be a {attr} parameter set (or one with no direction), got a "
                    f"{value.direction} one ({value.source or 'no source'}): were vertical and "
                    f"horizontal swapped? To use it anyway, pass "
                    f"{attr}=params.replace(direction='')"
                )
        # a batch of muds: both sets of one broadcastable shape
        check_broadcast(vertical=self.vertical.shape, horizontal=self.horizontal.shape)

    def __repr__(self) -> str:
        w = "" if self.water_content is None else f", water_content={self.water_content:g}"
        return f"Mud(name={self.name!r}{w})"
