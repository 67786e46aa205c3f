"""Algorithm 1 reduces the multibody ZMP error; the walk loop's hook keeps the default path."""

from __future__ import annotations

import numpy as np
import pytest

from zmpkit.compensate.algorithm1 import compensate_abstraction
from zmpkit.compensate.algorithm2 import Algorithm2Parameters, OnlineZmpCompensator
from zmpkit.errors import ParameterError
from zmpkit.experiments.walk_trial import simulate_walk
from zmpkit.robots.nao import make_nao, nao_ik_model
from zmpkit.robots.registry import get_robot
from zmpkit.walking import PatternConfig, generate_pattern
from zmpkit.walking.ik import solve_walking_ik

NAO_IK = get_robot("nao").ik_settings


@pytest.mark.slow
def test_algorithm1_reduces_the_error_on_a_short_walk() -> None:
    result = compensate_abstraction(PatternConfig(duration_s=3.0, com_height_m=0.25),
                                    nao_ik_model(), iterations=4, ik_settings=NAO_IK)  # fmt: skip
    rms = result.iteration_rms_m
    assert rms.shape == (4,)
    assert np.all(np.diff(rms) < 0.0)
    assert rms[-1] < 0.2 * rms[0]
    assert result.zmp_offset_in_world.shape == result.desired_zmp_in_world.shape


def test_algorithm1_iterations_are_checked() -> None:
    with pytest.raises(ParameterError, match="iterations must be an integer >= 1; got 0"):
        compensate_abstraction(PatternConfig(duration_s=2.0), nao_ik_model(), iterations=0,
                               ik_settings=NAO_IK)  # fmt: skip


@pytest.fixture(scope="module")
def short_walk():
    pattern = generate_pattern(PatternConfig(duration_s=1.5, com_height_m=0.25))
    settings = NAO_IK
    return pattern, settings, solve_walking_ik(pattern, nao_ik_model(), settings)


@pytest.mark.slow
def test_a_hook_that_returns_none_leaves_the_walk_unchanged(short_walk) -> None:
    _, _, trajectory = short_walk
    plain = simulate_walk(make_nao("none"), trajectory)
    calls = []
    hooked = simulate_walk(make_nao("none"), trajectory,
                           frame_hook=lambda k, reading: calls.append(k))  # fmt: skip
    assert calls == list(range(1, trajectory.time_s.size))
    np.testing.assert_array_equal(plain.qpos, hooked.qpos)
    np.testing.assert_array_equal(plain.trunk_pitch_rad, hooked.trunk_pitch_rad)


def test_algorithm2_without_deviation_keeps_the_planned_walk(short_walk) -> None:
    pattern, settings, _ = short_walk
    hook = OnlineZmpCompensator(pattern, nao_ik_model(), Algorithm2Parameters(), settings)
    for frame in range(1, 60):  # measured ZMP = desired ZMP: no offset, the planned CoM
        hook.update(frame - 1, pattern.linear_zmp_reference.zmp_in_world[frame - 1])
        window = hook.reference_window(frame - 1, hook.window)
        np.testing.assert_array_equal(
            window[0], pattern.linear_zmp_reference.zmp_in_world[frame - 1]
        )
    assert np.all(hook.offsets == 0.0)


def test_algorithm2_offsets_follow_the_deviation_per_step_slot(short_walk) -> None:
    pattern, settings, _ = short_walk
    params = Algorithm2Parameters(bias_gain=0.0, smoothing_gain=0.5)
    hook = OnlineZmpCompensator(pattern, nao_ik_model(), params, settings)
    frame = hook.first_frame + 3
    desired = pattern.linear_zmp_reference.zmp_in_world[frame]
    hook.update(frame, desired - [0.01, 0.0])  # deviation 1 cm, bias follows at once (α1 = 0)
    assert hook.offsets[3, 0] == pytest.approx(0.0)
    hook.parameters = Algorithm2Parameters(bias_gain=0.5, smoothing_gain=0.5)
    hook.bias[:] = 0.0
    hook.update(frame, desired - [0.01, 0.0])  # b = 5 mm, p_o = 0.5 (10 - 5) mm
    assert hook.offsets[3, 0] == pytest.approx(0.0025)
    assert np.count_nonzero(hook.offsets) == 1


@pytest.mark.parametrize(("kwargs", "match"),
                         [({"bias_gain": 1.0}, r"bias_gain must be in \[0, 1\); got 1.0"),
                          ({"axes": (2,)}, "axes must hold 0 and/or 1")])  # fmt: skip
def test_algorithm2_parameters_are_checked(kwargs, match) -> None:
    with pytest.raises(ParameterError, match=match):
        Algorithm2Parameters(**kwargs)
