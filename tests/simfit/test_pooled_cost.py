"""The fit's cost pooled over experiments: the plain mean by default and without logs, the
logs' windows by their median on request, a fall never hidden."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from zmpkit.cli import main
from zmpkit.errors import ParameterError
from zmpkit.pipelines.identify_sim_config import IdentifySimConfig
from zmpkit.robots.registry import get_robot
from zmpkit.simfit.cost import FAILED_COST
from zmpkit.simfit.pooled_cost import WINDOW_POOLINGS, check_window_pooling, pooled_cost
from zmpkit.simfit.problem import FitProblem
from zmpkit.simfit.shooting_window import ShootingWindow


def _window(log: str) -> ShootingWindow:
    """A window of ``log``: only its kind and log enter the pooling."""
    return ShootingWindow(
        name=f"{log}@0", robot=None, signals=None, start=None,  # type: ignore[arg-type]
        command_time_s=np.zeros(1), q_cmd_rad=np.zeros((1, 1)), burn_in_s=0.3, log_name=log,
    )  # fmt: skip


_COSTS = st.lists(st.floats(0.0, 50.0), min_size=1, max_size=30)


@given(_COSTS, st.sampled_from(WINDOW_POOLINGS))
def test_experiments_that_are_not_windows_pool_to_their_plain_mean(costs, pooling):
    assert pooled_cost([object() for _ in costs], costs, pooling) == float(np.mean(costs))


@given(_COSTS)
def test_the_mean_pooling_takes_windows_as_any_experiment(costs):
    windows = [_window("walk") for _ in costs]
    assert pooled_cost(windows, costs, "mean") == float(np.mean(costs))


@given(_COSTS, st.randoms(use_true_random=False))
def test_windows_pool_to_their_median_in_any_order(costs, random):
    windows = [_window("walk") for _ in costs]
    shuffled = random.sample(costs, len(costs))
    median = float(np.median(costs))
    assert pooled_cost(windows, costs, "median") == pytest.approx(median, rel=1e-12)
    assert pooled_cost(windows, shuffled, "median") == pytest.approx(
        pooled_cost(windows, costs, "median"), rel=1e-12
    )


@given(
    _COSTS,
    st.lists(st.floats(0.0, 50.0), min_size=1, max_size=10),
    st.lists(st.floats(FAILED_COST, 2 * FAILED_COST), min_size=0, max_size=5),
)
def test_windows_weigh_as_many_experiments_and_falls_are_charged_in_full(
    window_costs, other_costs, fallen
):
    """C = (Σ others + n_w · median(windows) + Σ fallen windows) / N: a candidate whose
    replay falls in a window pays its fall even when the median does not see it."""
    windows = window_costs + fallen
    experiments = [_window("a") for _ in windows] + [object() for _ in other_costs]
    costs = windows + other_costs
    expected = (sum(other_costs) + len(windows) * float(np.median(windows)) + sum(fallen)) / len(
        costs
    )
    pooled = pooled_cost(experiments, costs, "median")
    assert pooled == pytest.approx(expected, rel=1e-12)
    assert pooled >= sum(fallen) / len(costs)


def test_one_diverging_window_does_not_move_the_pooled_cost_but_a_mean_would():
    calm = [0.05, 0.06, 0.04, 0.05, 0.07]
    windows = [_window("walk") for _ in range(6)]
    assert pooled_cost(windows, [*calm, 0.9], "median") == pytest.approx(0.055)
    assert pooled_cost(windows, [*calm, 0.9], "mean") > 3 * 0.055


def test_a_cost_per_experiment_is_required():
    with pytest.raises(ValueError, match="one cost per experiment"):
        pooled_cost([object()], [], "mean")
    with pytest.raises(ValueError, match="one cost per experiment"):
        pooled_cost([], [], "median")
    with pytest.raises(ValueError, match="got 2 for 1"):
        pooled_cost([_window("walk")], [0.1, 0.2], "median")


def test_an_unknown_pooling_is_one_clear_error():
    with pytest.raises(ParameterError, match="window pooling must be one of mean, median"):
        check_window_pooling("trimmed")


def test_a_bad_pooling_names_the_valid_ones(tmp_path: Path, capsys) -> None:
    with pytest.raises(ParameterError, match="got 'trim'"):
        IdentifySimConfig(self_test=True, window_pooling="trim")
    with pytest.raises(ParameterError, match="window pooling must be one of mean, median"):
        FitProblem(get_robot("nao"), "M", (), {}, (), window_pooling="trim")
    argv = ["identify", "sim", "--self-test", "--window-pooling", "trim"]
    code = main([*argv, "--out", str(tmp_path)])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1
    assert "'mean'" in err
    assert "'median'" in err
