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


def test_a_voltage_drive_fits_its_winding_resistance_and_a_current_drive_does_not() -> None:
    motor = {**DOC["motor"], "resistance": 7.0}
    current = servo_fit_catalogue({**DOC, "motor": {**motor, "drive": "current"}})
    assert "winding_resistance" not in [p.name for p in current]
    assert current == servo_fit_catalogue({**DOC, "motor": motor})  # current is the default
    voltage = {
        p.name: p for p in servo_fit_catalogue({**DOC, "motor": {**motor, "drive": "voltage"}})
    }
    resistance = voltage["winding_resistance"]
    assert (resistance.path, resistance.nominal, resistance.unit) == ("motor.resistance", 7.0, "Ω")
    assert list(voltage)[2:4] == ["winding_resistance", "coulomb_friction"]


def test_the_op3_truth_derives_the_op3s_own_catalogue() -> None:
    """The OP3's truth file (a voltage drive) through the generic derivation gives the
    parameters, paths and nominal values of its hand-written catalogue (bounds aside)."""
    from zmpkit.robots.op3 import fit_catalogue, preset
    from zmpkit.simfit.truth_doc import load_truth_doc

    derived = servo_fit_catalogue(load_truth_doc(preset.OP3_TRUTH_PATH))
    by_hand = fit_catalogue.FIT_CATALOGUE
    assert [(p.effect, p.name, p.path) for p in derived] == [
        (p.effect, p.name, p.path) for p in by_hand
    ]
    for d, h in zip(derived, by_hand, strict=True):
        assert d.nominal == pytest.approx(h.nominal, rel=1e-12), d.name


def test_a_fit_candidate_of_a_voltage_drive_robot_keeps_the_drive(tmp_path) -> None:
    """A candidate truth (the user's truth with the fitted values set) loads as a voltage
    drive with the candidate's resistance: the fit simulates the drive the truth has."""
    from helpers.biped import BIPED_MJCF
    from zmpkit.cli import main
    from zmpkit.robots.registry import get_robot
    from zmpkit.simfit.truth_doc import load_robot_truth, load_truth_doc, truth_doc_with

    (tmp_path / "biped.xml").write_text(BIPED_MJCF, encoding="utf-8")
    robot_file = tmp_path / "robot.yaml"
    assert main(["robot", "init", str(tmp_path / "biped.xml"), "--out", str(robot_file)]) == 0
    (tmp_path / "truth.yaml").write_text(
        "servo_rate_hz: 1000.0\n"
        "motor: {gear_ratio: 200.0, supply_voltage: 24.0, torque_constant: 0.02,\n"
        "        resistance: 1.0, inductance: 1.0e-4, rotor_inertia: 1.0e-6, drive: voltage}\n"
        "pid: {kp: 400.0, ki: 0.0, kd: 4.0, integral_limit_link: 0.05}\n"
        "friction: {coulomb_link: 0.05}\n"
        "gear: {stiffness: 3000.0, damping: 1.0, backlash: 0.0, inertia_link: 1.0e-3}\n",
        encoding="utf-8",
    )
    with robot_file.open("a", encoding="utf-8") as handle:
        handle.write("truth: truth.yaml\n")
    robot = get_robot(robot_file)
    assert robot.fit is not None
    catalogue = {p.name: p for p in robot.fit.catalogue}
    assert "winding_resistance" in catalogue
    doc = truth_doc_with(
        load_truth_doc(tmp_path / "truth.yaml"), [catalogue["winding_resistance"]], [2.5]
    )
    truth = load_robot_truth(robot, doc)
    assert truth.motor.voltage_drive
    assert truth.motor.resistance == 2.5
