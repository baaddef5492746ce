"""mudrft.plotting: the figures of a Result and of a plate test, new or in the caller's axes."""

from __future__ import annotations

import numpy as np
import pytest

import mudrft

plt = pytest.importorskip("matplotlib.pyplot")


@pytest.fixture(scope="module")
def runs():
    result = mudrft.simulate(mudrft.feet.Flat(), mudrft.paper_mud(0.25), mudrft.gait(speed=0.2))
    plate = mudrft.plate_intrusion(depth=0.02, speed=0.02, hold=0.2)
    return result, mudrft.plate_response(plate, mudrft.paper_parameters(0.25))


@pytest.mark.parametrize("which", [0, 1])
def test_each_figure_has_two_panels_of_the_run(runs, which):
    fig = runs[which].plot()
    try:
        left, right = fig.axes
        assert left.get_xlabel() == "time [s]" and len(left.lines) >= 3
        assert right.lines and right.get_xlabel().endswith("[mm]")
    finally:
        plt.close(fig)


@pytest.mark.parametrize("which", [0, 1])
def test_each_figure_draws_into_the_first_two_of_the_callers_axes(runs, which):
    fig, axes = plt.subplots(2, 2)
    try:
        kw = {"axes": axes} if which == 0 else {"ax": axes}
        assert runs[which].plot(**kw) is fig
        drawn = [bool(a.lines) for a in np.ravel(axes)]
        assert drawn == [True, True, False, False]
        time = np.ravel(axes)[0].lines[0].get_xdata()
        np.testing.assert_array_equal(time, runs[which].time)
    finally:
        plt.close(fig)
