"""Matplotlib figures (optional extra ``plot``), drawn from a run's arrays by attribute, so
that :mod:`mudrft.simulation` and :mod:`mudrft.plate` call this module and not back."""

from __future__ import annotations

from collections.abc import Sequence
from types import ModuleType
from typing import TYPE_CHECKING, Protocol, TypeAlias

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: The caller's axes: a sequence or object array of at least two matplotlib ``Axes``, or
#: None for a new figure (the type of :meth:`mudrft.Result.plot`'s ``axes``).
AxesArg: TypeAlias = "Sequence[Axes] | NDArray[np.object_] | None"

__all__ = ["PlateArrays", "RunArrays", "plot_plate", "plot_result", "require_matplotlib"]


class RunArrays(Protocol):
    """What :func:`plot_result` draws, as :class:`mudrft.Result` has it: ``time`` (n,) [s],
    ``force`` (n, 3) [N], ``depth`` (n,) [m] and the ``foot`` and ``terrain`` names."""

    @property
    def time(self) -> np.ndarray: ...
    @property
    def force(self) -> np.ndarray: ...
    @property
    def depth(self) -> np.ndarray: ...
    @property
    def foot(self) -> str: ...
    @property
    def terrain(self) -> str: ...


class PlateArrays(Protocol):
    """What :func:`plot_plate` draws, as :class:`mudrft.PlateResult` has it: ``time`` [s],
    ``displacement`` [m], the ``stress`` [Pa] and its terms ``elastic``, ``thixotropic``,
    ``suction`` [Pa], each (n,)."""

    @property
    def time(self) -> np.ndarray: ...
    @property
    def displacement(self) -> np.ndarray: ...
    @property
    def stress(self) -> np.ndarray: ...
    @property
    def elastic(self) -> np.ndarray: ...
    @property
    def thixotropic(self) -> np.ndarray: ...
    @property
    def suction(self) -> np.ndarray: ...


def require_matplotlib() -> ModuleType:
    """``matplotlib.pyplot``, with the Agg backend when no display is set."""
    try:
        import matplotlib

        if not matplotlib.get_backend().lower().startswith(("qt", "tk", "gtk", "wx", "macosx")):
            matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError("plotting needs matplotlib: pip install 'mudrft[plot]'") from exc
    return plt


def _two_panels(axes: AxesArg) -> tuple[Figure, Axes, Axes]:
    """``(figure, left, right)``: a new figure, or the first two of the caller's ``axes``."""
    if axes is None:
        fig, axes = require_matplotlib().subplots(1, 2, figsize=(9, 3.4), constrained_layout=True)
    else:
        fig = np.asarray(axes, dtype=object).ravel()[0].figure
    a0, a1 = np.asarray(axes, dtype=object).ravel()[:2]
    return fig, a0, a1


def plot_plate(result: PlateArrays, ax: AxesArg = None) -> Figure:
    """Stress against time and against displacement for a plate test (kPa, mm), new or in
    the first two of the caller's axes ``ax``."""
    fig, a0, a1 = _two_panels(ax)
    a0.plot(result.time, result.stress / 1e3, "k", lw=1.6, label=r"$\sigma_{tot}$")
    a0.plot(result.time, result.elastic / 1e3, "--", lw=1, label=r"$\sigma_b$")
    a0.plot(result.time, result.thixotropic / 1e3, "--", lw=1, label=r"$\sigma_{th}$")
    a0.plot(result.time, result.suction / 1e3, "--", lw=1, label=r"$H_\nu\sigma_s$")
    a0.axhline(0, color="0.7", lw=0.6)
    a0.set_xlabel("time [s]")
    a0.set_ylabel("stress [kPa]")
    a0.legend(fontsize=8, ncol=2)
    a1.plot(result.displacement * 1e3, result.stress / 1e3, "k", lw=1.4)
    a1.axhline(0, color="0.7", lw=0.6)
    a1.set_xlabel("intrusion displacement [mm]")
    a1.set_ylabel("stress [kPa]")
    return fig


def plot_result(result: RunArrays, axes: AxesArg = None) -> Figure:
    """Forces against time, and vertical force against depth, for a :class:`~mudrft.Result`."""
    fig, a0, a1 = _two_panels(axes)
    for i, lab in enumerate(("$F_x$", "$F_y$", "$F_z$")):
        a0.plot(result.time, result.force[:, i], lw=1.3, label=lab)
    a0.axhline(0, color="0.7", lw=0.6)
    a0.set_xlabel("time [s]")
    a0.set_ylabel("force [N]")
    a0.legend(fontsize=8)
    a0.set_title(f"{result.foot} in {result.terrain}", fontsize=9)
    a1.plot(result.depth * 1e3, result.force[:, 2], "k", lw=1.3)
    a1.axhline(0, color="0.7", lw=0.6)
    a1.set_xlabel("tip depth [mm]")
    a1.set_ylabel("$F_z$ [N]")
    return fig
