"""Algorithm 2 inside the feedback walk: the reference it rewrites, against its definition."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.compensate.algorithm2 import Algorithm2Offsets, Algorithm2Parameters
from zmpkit.compensate.evaluations import WalkSpec
from zmpkit.compensate.methods import walk_with_algorithm2
from zmpkit.errors import ParameterError
from zmpkit.experiments.walk import make_controller
from zmpkit.robots.registry import get_robot
from zmpkit.walking import PatternConfig, generate_pattern

PATTERN = generate_pattern(PatternConfig(duration_s=3.0, com_height_m=0.25))
WINDOW = 150  # frames a preview window reads [-]


def _reference() -> list[np.ndarray]:
    """A controller's reference as zmpip holds it: per axis, padded past the end."""
    desired = PATTERN.zmp_reference_in_world
    padded = np.concatenate([desired, np.repeat(desired[-1:], WINDOW, axis=0)])
    return [np.ascontiguousarray(padded[:, axis]) for axis in (0, 1)]


@settings(max_examples=30, deadline=None)
@given(
    deviations=st.lists(
        st.tuples(st.floats(-0.05, 0.05), st.floats(-0.05, 0.05), st.booleans()),
        min_size=40,
        max_size=40,
    ),
    start=st.integers(0, 250),
    axes=st.sampled_from([(0,), (1,), (0, 1)]),
)
def test_the_rewritten_reference_is_line_6_for_every_frame_the_preview_reads(
    deviations, start, axes
) -> None:
    """After each frame's update, the window the observer reads equals p_r + p_o (line 6).

    The independent reading: :meth:`Algorithm2Offsets.reference_window` recomputes every
    window entry from the current offsets; :meth:`adapt` only rewrote the frames of the
    slot it changed. NaN samples learn nothing.
    """
    learner = Algorithm2Offsets(PATTERN, Algorithm2Parameters(0.9, 0.5, axes))
    reference = _reference()
    n = PATTERN.time_s.size
    for i, (dx, dy, missing) in enumerate(deviations):
        frame = start + i
        zmp = PATTERN.zmp_reference_in_world[frame] + [dx, dy]
        learner.adapt(frame, np.full(2, np.nan) if missing else zmp, reference)
        expected = learner.reference_window(frame, WINDOW)
        stop = min(frame + WINDOW, n)
        got = np.column_stack([reference[0][frame:stop], reference[1][frame:stop]])
        np.testing.assert_allclose(got, expected[: stop - frame], atol=1e-15)
        np.testing.assert_array_equal(learner.target[frame], got[0])
    untouched = [a for a in (0, 1) if a not in axes]
    for axis in untouched:
        np.testing.assert_array_equal(reference[axis][:n], PATTERN.zmp_reference_in_world[:, axis])


def test_a_constant_deviation_is_learnt_as_its_bias_the_offsets_only_while_it_builds() -> None:
    """A ZMP ``D`` = 1 cm behind the plan at every frame, in closed form.

    Line 5 gives ``b_k = D (1 - α1^k)`` after ``k`` frames, so line 7 adds ``(1 - α2) D α1^k``
    at frame ``k``: slot ``s``, updated at ``k_j = s + 1 + jT``, holds
    ``Σ_j α2^{m-1-j} (1 - α2) D α1^{k_j}`` — the transient only; the bias is removed.
    """
    a1, a2, deviation = 0.9, 0.5, 0.01
    learner = Algorithm2Offsets(PATTERN, Algorithm2Parameters(a1, a2))
    reference = _reference()
    frames = range(learner.first_frame, learner.last_frame + 1)
    for frame in frames:
        learner.adapt(frame, PATTERN.zmp_reference_in_world[frame] - [deviation, 0.0], reference)
    steps = learner.frames_per_step
    expected = np.zeros(steps)
    for slot in range(steps):
        k = np.arange(slot + 1, len(frames) + 1, steps)  # k_j, j = 0 .. m - 1
        j = np.arange(k.size)
        expected[slot] = np.sum(a2 ** (k.size - 1 - j) * (1 - a2) * deviation * a1**k)
    np.testing.assert_allclose(learner.offsets[:, 0], expected, rtol=1e-9, atol=1e-18)
    assert learner.bias[0] == pytest.approx(deviation * (1 - a1 ** len(frames)), rel=1e-12)
    learner.adapt(learner.last_frame + 5, np.zeros(2), reference)  # after the walk: nothing
    assert learner.bias[0] == pytest.approx(0.01, rel=1e-6)


def test_only_zmpip_takes_a_reference_adapter() -> None:
    learner = Algorithm2Offsets(PATTERN, Algorithm2Parameters())
    with pytest.raises(ParameterError, match="needs the zmpip controller"):
        make_controller("dcm", PATTERN, None, None, None, None, reference_adapter=learner)  # type: ignore[arg-type]


@pytest.mark.slow
def test_a_feedback_walk_with_algorithm_2_tracks_its_rewritten_reference() -> None:
    """All effects, 3 s at 0.2 m/s with zmpip: p' differs from p_r only inside the walk."""
    walk = WalkSpec(duration_s=3.0, controller="zmpip", robot=get_robot("nao"))
    result = walk_with_algorithm2(walk, Algorithm2Parameters(0.99, 0.8))
    assert not result.fell
    learner = Algorithm2Offsets(PATTERN, Algorithm2Parameters())
    changed = np.flatnonzero(np.any(result.target_zmp_in_world != result.desired_zmp_in_world, 1))
    assert changed.size > 0
    assert learner.first_frame <= changed.min()
    assert changed.max() <= learner.last_frame + 1
    assert np.isfinite(result.step_peak_rad)
