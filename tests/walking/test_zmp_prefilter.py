"""What the walking observer reads of the measured ZMP (:mod:`zmpkit.walking.zmp_prefilter`)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from zmpkit.walking.zmp_prefilter import ZmpPrefilter

PERIOD_S = 0.01


def test_the_expected_offset_is_subtracted_and_nothing_else_without_a_filter() -> None:
    expected = np.array([[0.01, -0.02], [0.03, 0.0]])
    prefilter = ZmpPrefilter(PERIOD_S, expected, cutoff_hz=None)
    np.testing.assert_allclose(prefilter.read(0, np.array([0.1, 0.2])), [0.09, 0.22])
    np.testing.assert_allclose(prefilter.read(1, np.array([0.1, 0.2])), [0.07, 0.2])
    np.testing.assert_allclose(prefilter.read(7, np.array([0.1, 0.2])), [0.07, 0.2])  # last row


def test_a_step_rises_as_a_first_order_lag_of_the_cut_off() -> None:
    """A unit step read through the low-pass: after n periods 1 − (1 − α)ⁿ, α = T/(T + τ)."""
    cutoff = 10.0
    alpha = PERIOD_S / (PERIOD_S + 1.0 / (2.0 * math.pi * cutoff))
    prefilter = ZmpPrefilter(PERIOD_S, None, cutoff)
    prefilter.read(0, np.zeros(2))
    for n in range(1, 30):
        read = prefilter.read(n, np.ones(2)).copy()
        assert read == pytest.approx(np.full(2, 1.0 - (1.0 - alpha) ** n))


def test_a_frame_without_contact_passes_on_and_restarts_the_filter() -> None:
    prefilter = ZmpPrefilter(PERIOD_S, None, 10.0)
    prefilter.read(0, np.zeros(2))
    assert np.isnan(prefilter.read(1, np.array([np.nan, np.nan]))).all()
    np.testing.assert_allclose(prefilter.read(2, np.array([0.05, -0.05])), [0.05, -0.05])


@given(st.floats(-0.2, 0.2), st.floats(0.5, 50.0))
def test_a_constant_zmp_is_read_unchanged(value: float, cutoff: float) -> None:
    prefilter = ZmpPrefilter(PERIOD_S, None, cutoff)
    for k in range(20):
        read = prefilter.read(k, np.array([value, -value]))
    np.testing.assert_allclose(read, [value, -value], atol=1e-12)
