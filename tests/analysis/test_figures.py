"""What the figures draw: every trial (held-out and unsettled ones too), falls, pushes, SI units.

Each test captures the matplotlib figure before it is saved and checks the artists a reader
would rely on: a legend entry is only there for data that are drawn.
"""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from zmpkit.analysis import balance_plots, walk_plots
from zmpkit.analysis.balance_validation import evaluate_trial
from zmpkit.analysis.table1 import Table1Row
from zmpkit.identify import identify_balance
from zmpkit.pipelines.walk_figures import JOINT_PLOT_STEPS, joint_plot_span
from zmpkit.signals import StepTrial
from zmpkit.signals.contact_phases import double_support_distance


def _capture(monkeypatch: pytest.MonkeyPatch, module: Any) -> list[Any]:
    """Replace ``module.save_figure`` by one that keeps the figure; return the list it fills."""
    figures: list[Any] = []

    def keep(fig: Any, path: str | Path, dpi: int = 120) -> Path:
        figures.append(fig)
        return Path(path)

    monkeypatch.setattr(module, "save_figure", keep)
    return figures


def _legend_texts(fig: Any) -> list[str]:
    return [t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().texts]


def _step(target: float, final: float, drift_m_per_s: float = 0.0) -> StepTrial:
    """A damped ZMP step to ``final`` [m] at t = 1 s, optionally creeping at a constant rate."""
    t = np.arange(0.0, 12.0, 0.002)
    tau = np.clip(t - 1.0, 0.0, None)
    shape = 1 - np.exp(-3.0 * tau) * (np.cos(6.0 * tau) + 0.5 * np.sin(6.0 * tau))
    noise = np.random.default_rng(round(1e4 * target)).normal(0.0, 2e-5, t.size)
    return StepTrial(t, final * shape + drift_m_per_s * tau + noise, target, 1.0)


def test_fig16_draws_held_out_and_unsettled_trials(monkeypatch: pytest.MonkeyPatch) -> None:
    settled = [_step(x, 1.08 * x) for x in (0.0, 0.02, 0.04, 0.06, 0.08)]
    creeping = _step(0.10, 0.108, drift_m_per_s=2e-3)  # 2 mm/s: never settles
    ident = identify_balance([*settled, creeping], mass=60.0, com_height=0.9)
    plane = ident.planes["sagittal"]
    assert len(plane.excluded) == 1
    held_out = Table1Row(
        "sagittal", 0.05, *(evaluate_trial(c, _step(0.05, 1.08 * 0.05)) for c in ("lipm",) * 3),
        fitted_on=False,
    )  # fmt: skip
    figures = _capture(monkeypatch, balance_plots)
    balance_plots.plot_error_fit(plane, [held_out], "fig16.png", plane="sagittal")
    texts = _legend_texts(figures[0])
    assert "did not settle: left out of the fit (1)" in texts
    assert "validation LIPM trials (not fitted)" in texts
    main = figures[0].axes[0]
    unsettled = next(ln for ln in main.get_lines() if ln.get_label().startswith("did not"))
    x, y = unsettled.get_data()
    assert x[0] == pytest.approx(0.10)
    assert y[0] == pytest.approx(0.108 + 2e-3 * 10.5, abs=1e-3)  # its last second's mean


def test_fig16_has_no_legend_entry_for_markers_it_does_not_draw(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    ident = identify_balance(
        [_step(x, 1.08 * x) for x in (0.0, 0.03, 0.06, 0.09)], mass=60.0, com_height=0.9
    )
    figures = _capture(monkeypatch, balance_plots)
    balance_plots.plot_error_fit(ident.planes["sagittal"], [], "fig16.png", plane="sagittal")
    texts = _legend_texts(figures[0])
    assert not any("validation" in t or "did not settle" in t for t in texts)
    assert "identification trials (fitted)" in texts


def test_time_plots_mark_the_fall_and_the_push_in_si(monkeypatch: pytest.MonkeyPatch) -> None:
    t = np.linspace(0.0, 8.0, 801)
    roll = 0.1 * np.exp(t - 6.0)  # reaches 0.74 rad, near the 0.8 rad fall tilt
    figures = _capture(monkeypatch, walk_plots)
    fall = walk_plots.FallMark(6.32, "roll")
    push = walk_plots.PushMark(4.2, 0.1, "push 20 N +y")
    walk_plots.plot_trunk_tilt(t, roll, "roll.png", "walk", axis="roll", fall_tilt_rad=0.8,
                               fall=fall, pushes=(push,))  # fmt: skip
    texts = _legend_texts(figures[0])
    assert "fell (roll) at 6.32 s" in texts
    assert "push 20 N +y at 4.20 s" in texts
    assert "fall tilt" in texts  # the roll came near the limit
    assert figures[0].axes[0].get_ylabel() == "trunk roll [rad]"


def test_joint_figure_shows_the_tracking_error(monkeypatch: pytest.MonkeyPatch) -> None:
    t = np.linspace(0.0, 2.0, 201)
    target = 0.5 * np.sin(2 * np.pi * t)
    actual = 0.5 * np.sin(2 * np.pi * (t - 0.02))
    figures = _capture(monkeypatch, walk_plots)
    walk_plots.plot_joint_tracking(t, target, actual, np.zeros_like(t), "joint.png", "knee")
    error_axis = figures[0].axes[1]
    (error_line,) = [ln for ln in error_axis.get_lines() if ln.get_label() == "target − actual"]
    assert np.allclose(error_line.get_ydata(), target - actual)
    assert error_axis.get_ylabel() == "tracking error [rad]"


def test_joint_span_is_four_steps_of_the_steady_walk_or_up_to_the_fall() -> None:
    standing = SimpleNamespace(window_s=(2.0, 9.5), fall_time_s=None)
    assert joint_plot_span(standing, 0.5, 10.0) == (2.0, 2.0 + JOINT_PLOT_STEPS * 0.5)  # type: ignore[arg-type]
    fallen = SimpleNamespace(window_s=(2.0, 6.1), fall_time_s=6.1)
    start, stop = joint_plot_span(fallen, 0.5, 6.2)  # type: ignore[arg-type]
    assert stop == pytest.approx(6.2)  # the record ends there
    assert stop - start == pytest.approx(JOINT_PLOT_STEPS * 0.5)


def test_feet_distance_is_the_step_length_along_the_heading() -> None:
    # a 0.12 m step walked at heading 0.5 rad: 0.12 m, not its x component
    heading = 0.5
    soles = np.array([[[0.12 * math.cos(heading), 0.12 * math.sin(heading)], [0.0, 0.0]]])
    both = np.array([[True, True]])
    assert double_support_distance(soles, both, heading)[0] == pytest.approx(0.12)
    assert double_support_distance(soles, both)[0] == pytest.approx(0.12 * math.cos(heading))
    assert np.isnan(double_support_distance(soles, np.array([[True, False]]), heading)[0])


@given(
    step=st.floats(0.0, 0.3),
    width=st.floats(-0.2, 0.2),
    heading=st.floats(-math.pi, math.pi),
    origin=st.tuples(st.floats(-5, 5), st.floats(-5, 5)),
)
def test_feet_distance_is_invariant_to_where_and_which_way_the_robot_walks(
    step: float, width: float, heading: float, origin: tuple[float, float]
) -> None:
    c, s = math.cos(heading), math.sin(heading)
    front = (origin[0] + step * c - width * s, origin[1] + step * s + width * c)
    soles = np.array([[front, origin]])
    distance = double_support_distance(soles, np.array([[True, True]]), heading)[0]
    assert distance == pytest.approx(step, abs=1e-9)
