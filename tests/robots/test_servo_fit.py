"""A user's robot with a servo truth file gets a fit catalogue derived from it."""

from __future__ import annotations

import pytest

from zmpkit.robots.servo_fit import SERVO_FIT_FACTOR, servo_fit_catalogue

DOC = {
    "pid": {"kp": 400.0, "ki": 0.0, "kd": 4.0},
    "friction": {"coulomb_link": 0.05},
    "motor": {"inductance": 1.0e-4, "gear_ratio": 200.0},
    "gear": {"stiffness": 3000.0, "damping": 1.0, "backlash": 0.0},
    "flex": [
        {"name": "l_shank", "stiffness": [4000.0, 0.0, 0.0]},
        {"name": "r_shank", "stiffness": [4000.0, 0.0, 0.0]},
    ],
}


def test_every_positive_value_is_a_parameter_a_factor_of_four_either_side() -> None:
    catalogue = {p.name: p for p in servo_fit_catalogue(DOC)}
    assert list(catalogue) == [
        "pid_p_gain",
        "pid_d_gain",
        "coulomb_friction",
        "inductance",
        "gear_stiffness",
        "gear_damping",
        "flex_stiffness",
    ]  # fmt: skip  (ki and backlash are 0: out; gear_ratio is not a fit parameter)
    kp = catalogue["pid_p_gain"]
    assert (kp.path, kp.nominal, kp.effect, kp.unit) == ("pid.kp", 400.0, "M", "N·m/rad")
    for p in catalogue.values():
        assert p.log_scale
        assert p.lower == pytest.approx(p.nominal / SERVO_FIT_FACTOR)
        assert p.upper == pytest.approx(p.nominal * SERVO_FIT_FACTOR)
        assert p.to_unit(p.nominal) == pytest.approx(0.5)
    assert catalogue["flex_stiffness"].path == "flex[0,1].stiffness[0]"  # one shared value


def test_flex_links_of_different_stiffness_are_fitted_one_by_one() -> None:
    doc = {"flex": [{"name": "a", "stiffness": [4000.0]}, {"name": "b", "stiffness": [2000.0]}]}
    catalogue = servo_fit_catalogue(doc)
    assert [(p.name, p.path, p.nominal) for p in catalogue] == [
        ("flex_stiffness_a", "flex[0].stiffness[0]", 4000.0),
        ("flex_stiffness_b", "flex[1].stiffness[0]", 2000.0),
    ]


@pytest.mark.parametrize(
    "doc", [{}, {"pid": "fast"}, {"pid": {"kp": True}}, {"flex": "stiff"}, {"flex": [{"x": 1}]}]
)
def test_a_document_without_usable_values_gives_no_parameter(doc) -> None:
    assert servo_fit_catalogue(doc) == ()
