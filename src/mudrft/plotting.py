"""Matplotlib figures (optional extra ``plot``). They read a run's arrays by attribute, so
that :mod:`mudrft.simulation` and :mod:`mudrft.plate` call this module and not back."""

from __future__ import annotations

from collections.abc import Sequence
from types import ModuleType
from typing import TYPE_CHECKING, Any, TypeAlias

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: The caller's axes: a sequence or object array of at least two matplotlib ``Axes``, or
#: None for a new figure (the type of :meth:`mudrft.Result.plot`'s ``axes``).
AxesArg: TypeAlias = "Sequence[Axes] | NDArray[np.object_] | None"

__all__ = ["plot_plate", "plot_result", "require_matplotlib"]


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
        _, axes = require_matplotlib().subplots(1, 2, figsize=(9, 3.4), constrained_layout=True)
    a0, a1 = np.asarray(axes, dtype=object).ravel()[:2]
    return a0.figure, a0, a1


def plot_plate(result: Any, ax: AxesArg = None) -> Figure:
    """A plate test's (:class:`mudrft.PlateResult`) stress and its terms [Pa] against time
    [s] and the stress against displacement [m] (drawn in kPa and mm), new or in the
    caller's axes ``ax``."""
    fig, a0, a1 = _two_panels(ax)
    a0.plot(result.time, result.stress / 1e3, "k", lw=1.6, label=r"$\sigma_{tot}$")
    for term, label in (("elastic", r"$\sigma_b$"), ("thixotropic", r"$\sigma_{th}$"),
                        ("suction", r"$H_\nu\sigma_s$")):  # fmt: skip
        a0.plot(result.time, getattr(result, term) / 1e3, "--", lw=1, label=label)
    a0.axhline(0, color="0.7", lw=0.6)
    a0.set(xlabel="time [s]", ylabel="stress [kPa]")
    a0.legend(fontsize=8, ncol=2)
    a1.plot(result.displacement * 1e3, result.stress / 1e3, "k", lw=1.4)
    a1.axhline(0, color="0.7", lw=0.6)
    a1.set(xlabel="intrusion displacement [mm]", ylabel="stress [kPa]")
    return fig


def plot_result(result: Any, axes: AxesArg = None) -> Figure:
    """Forces [N] of a :class:`mudrft.Result` against time [s], and the vertical force
    against depth [m] (drawn in mm), new or in the caller's ``axes``."""
    fig, a0, a1 = _two_panels(axes)
    for i, lab in enumerate(("$F_x$", "$F_y$", "$F_z$")):
        a0.plot(result.time, result.force[:, i], lw=1.3, label=lab)
    a0.axhline(0, color="0.7", lw=0.6)
    a0.set(xlabel="time [s]", ylabel="force [N]")
    a0.legend(fontsize=8)
    a0.set_title(f"{result.foot} in {result.terrain}", fontsize=9)
    a1.plot(result.depth * 1e3, result.force[:, 2], "k", lw=1.3)
    a1.axhline(0, color="0.7", lw=0.6)
    a1.set(xlabel="tip depth [mm]", ylabel="$F_z$ [N]")
    return fig
