"""zmpkit.sensors.plausibility: which F-T samples reach a feedback loop."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from zmpkit.errors import ParameterError
from zmpkit.sensors import DoubleSupportZmp, SensorMount
from zmpkit.sensors.plausibility import (
    FT_FORCE_RANGE_N,
    MAX_PLAUSIBLE_FORCE_N,
    PlausibilityGate,
    PlausibilityLimits,
)

RIGHT = SensorMount.from_rpy((0.0, -0.1285, 0.01), (0.0, 0.0, 0.0), 0.01, "right")
LEFT = SensorMount.from_rpy((0.0, 0.1285, 0.01), (0.0, 0.0, 0.0), 0.01, "left")


def load(x_m: float, fz_n: float = 300.0) -> list[float]:
    """Sensor-frame wrench of a vertical load fz at x on the sole, under the sensor (y = 0).

    Mount with identity rotation at height 0.01 m: τ_y = -x F_z, so p_x = -τ_y / F_z = x.
    """
    return [0.0, 0.0, fz_n, 0.0, -x_m * fz_n, 0.0]


def gate(**limits: float) -> PlausibilityGate:
    return PlausibilityGate(DoubleSupportZmp(RIGHT, LEFT), 0, PlausibilityLimits(**limits))


def test_plausible_sample_gives_the_zmp() -> None:
    assert gate()(load(0.03), load(0.05)) == pytest.approx(0.04, abs=1e-12)


@pytest.mark.parametrize(
    ("index", "value", "reason"),
    [
        (2, math.nan, "non_finite"),
        (4, math.inf, "non_finite"),
        (0, 2 * MAX_PLAUSIBLE_FORCE_N, "implausible"),
        (2, FT_FORCE_RANGE_N, "saturated"),
        (1, -FT_FORCE_RANGE_N, "saturated"),
    ],
)
def test_faulty_samples_are_rejected_with_their_reason(
    index: int, value: float, reason: str
) -> None:
    g = gate()
    right = load(0.0)
    right[index] = value
    assert g(right, load(0.0)) is None
    assert g.rejected[reason] == 1
    assert sum(g.rejected.values()) == 1


def test_no_contact_is_rejected() -> None:
    g = gate()
    assert g(load(0.0, 1.0), load(0.0, 1.0)) is None
    assert g.rejected["no_contact"] == 1


def test_spike_is_rejected_until_too_many_in_a_row() -> None:
    g = gate(max_zmp_jump_m=0.01, max_rejected_in_row=3)
    assert g(load(0.02), load(0.02)) == pytest.approx(0.02)
    assert g(load(0.2), load(0.2)) is None  # a 0.18 m jump in one sample
    assert g(load(0.025), load(0.025)) == pytest.approx(0.025)  # back: accepted
    for _ in range(3):
        assert g(load(0.1), load(0.1)) is None
    assert g(load(0.1), load(0.1)) == pytest.approx(0.1)  # a real move is not locked out
    assert g.rejected["spike"] == 4


@given(st.lists(st.floats(allow_nan=True, allow_infinity=True), min_size=12, max_size=12))
def test_gate_output_is_none_or_finite(values: list[float]) -> None:
    out = gate()(values[:6], values[6:])
    assert out is None or math.isfinite(out)


def test_limits_error_texts() -> None:
    with pytest.raises(ParameterError, match="force_range_n"):
        PlausibilityLimits(force_range_n=0.0)
    with pytest.raises(ParameterError, match="max_rejected_in_row"):
        PlausibilityLimits(max_rejected_in_row=0)
    with pytest.raises(ParameterError, match="axis"):
        PlausibilityGate(DoubleSupportZmp(RIGHT, LEFT), 2)
