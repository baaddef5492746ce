"""The figure of a fit: measured and fitted stress against time, one panel per trial
(internal; needs matplotlib)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from ..io import IntrusionDataset
from ._problem import PHASES, segment

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["plot_fit"]


def plot_fit(
    ds: IntrusionDataset,
    predictions: Sequence[NDArray[np.float64]],
    *,
    title: str,
    axes: Any = None,  # an array or sequence of matplotlib Axes (np.ravel cannot type it)
) -> Figure:
    """Stress [kPa] against time [s], data and fit, one panel per trial.

    Parameters
    ----------
    ds : IntrusionDataset
        The data (SI).
    predictions : sequence of ndarray
        Model stress [Pa] at the samples of each trial.
    title : str, keyword-only
        Title of the figure.
    axes : array of matplotlib Axes, optional, keyword-only
        One per trial; default a new figure.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ..plotting import require_matplotlib

    plt = require_matplotlib()
    n = len(ds)
    if axes is None:
        fig, axes = plt.subplots(
            1, n, figsize=(3.6 * n + 0.6, 3.2), squeeze=False, constrained_layout=True
        )
    else:
        fig = np.ravel(axes)[0].figure
    axs = np.ravel(axes)
    for j, (tr, yp) in enumerate(zip(ds.trials, predictions, strict=True)):
        ax = axs[j]
        used = segment(tr) != PHASES["out"]
        ax.plot(tr.time[used], tr.stress[used] / 1e3, ".", ms=2.5, color="0.55", label="data")
        if not used.all():
            ax.plot(
                tr.time[~used],
                tr.stress[~used] / 1e3,
                "x",
                ms=4,
                color="0.55",
                label="not fitted (out of the mud)",
            )
        ax.plot(tr.time[used], yp[used] / 1e3, "C3", lw=1.5, label="fit")
        ax.axhline(0.0, color="0.8", lw=0.6)
        ax.set_title(f"{tr.name}: {1e3 * tr.speed:.3g} mm/s", fontsize=9)
        ax.set_xlabel("time [s]")
        if j == 0:
            ax.set_ylabel("stress [kPa]")
            ax.legend(fontsize=8, loc="lower left")
    fig.suptitle(title, fontsize=10)
    return fig
