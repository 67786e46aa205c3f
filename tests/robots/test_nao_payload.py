"""NAO's C effect (CAD vs real mass and CoM): the truth's real torso link.

The truth file's ``torso`` section holds the real torso's mass [kg] and CoM [m, torso frame];
the design model (the IK's, the URDF's) keeps 1.04956 kg at (-0.00413, 0, 0.04342) m. The
difference acts as a payload of ``m_real - m_urdf`` whose first moment is
``m_real c_real - m_urdf c_urdf``: these tests check that closed form on the compiled models
and recover the torso from the standing robot's F-T wrenches.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import mujoco
import numpy as np
import pytest

from zmpkit.errors import InputFileError
from zmpkit.robots.nao import (
    DEFAULT_TRUTH_PATH,
    NAO_DRIVEN_JOINTS,
    load_truth,
    make_nao,
    nao_ik_model,
    nao_mjcf,
)
from zmpkit.robots.nao.geometry import TORSO
from zmpkit.robots.nao.model import SOLE_PLATE_M
from zmpkit.robots.registry import get_robot
from zmpkit.simfit.outputs import write_fitted_truth
from zmpkit.simfit.parameters import default_parameters
from zmpkit.simfit.truth_doc import (
    base_truth_path,
    get_path,
    load_truth_doc,
    truth_doc_with,
    write_truth_doc,
)

GRAVITY = 9.81
"""MuJoCo's default |g| [m/s²]."""


def _truth_file(tmp_path: Path, torso: Any, name: str = "truth.yaml") -> Path:
    """The shipped truth with its ``torso`` section replaced (``None`` deletes it)."""
    doc = load_truth_doc(DEFAULT_TRUTH_PATH)
    if torso is None:
        del doc["torso"]
    else:
        doc["torso"] = torso
    return write_truth_doc(doc, tmp_path / name)


def _design_truth(tmp_path: Path) -> Path:
    """The shipped truth with the URDF torso: the robot without the C effect."""
    return _truth_file(tmp_path, {"mass_kg": TORSO.mass, "com_m": list(TORSO.com)}, "design.yaml")


def test_shipped_truth_has_a_heavier_torso_with_its_com_forward() -> None:
    truth = load_truth()
    assert truth.torso_mass_kg == pytest.approx(1.15)
    assert truth.torso_com_m == pytest.approx((0.010, 0.0, 0.045))
    inertial = truth.torso_inertial()
    ratio = 1.15 / TORSO.mass
    assert inertial.inertia == pytest.approx([ratio * i for i in TORSO.inertia])


@pytest.mark.parametrize(
    ("torso", "message"),
    [
        (None, r"missing section 'torso'"),
        ({"com_m": [0.0, 0.0, 0.04]}, r"torso: missing 'mass_kg' \(the real torso mass \[kg\]\)"),
        ({"mass_kg": 1.1}, r"torso: missing 'com_m'"),
        ({"mass_kg": -0.2, "com_m": [0.0, 0.0, 0.04]}, r"torso.mass_kg must be a mass > 0 kg"),
        ({"mass_kg": 0.0, "com_m": [0.0, 0.0, 0.04]}, r"mass > 0 kg, got 0.0"),
        ({"mass_kg": "heavy", "com_m": [0.0, 0.0, 0.04]}, r"mass > 0 kg, got 'heavy'"),
        ({"mass_kg": 1.1, "com_m": [0.0, 0.04]}, r"torso.com_m must be 3 finite numbers"),
        ({"mass_kg": 1.1, "com_m": [0.0, "a", 0.04]}, r"\[x, y, z\] in the torso frame \[m\]"),
        ({"mass_kg": 1.1, "com_m": 0.04}, r"torso.com_m must be 3 finite numbers"),
        ([1.1, 0.0], r"torso: expected a mapping with mass_kg and com_m"),
    ],
)
def test_torso_section_errors_name_the_file_and_field(
    tmp_path: Path, torso: Any, message: str
) -> None:
    path = _truth_file(tmp_path, torso)
    with pytest.raises(InputFileError, match=r"truth\.yaml.*" + message):
        load_truth(path)


def _mass_and_com(mjcf: str) -> tuple[float, np.ndarray, np.ndarray]:
    """Whole-robot mass [kg], CoM and torso origin [m, world] in the zero pose."""
    model = mujoco.MjModel.from_xml_string(mjcf)
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    mujoco.mj_comPos(model, data)
    torso = model.body("torso").id
    com = data.subtree_com[torso].copy()
    return float(model.body_subtreemass[torso]), com, data.xpos[torso].copy()


@pytest.mark.parametrize("effects", ["none", "all"])
def test_real_torso_changes_mass_and_com_by_the_closed_form(tmp_path: Path, effects: str) -> None:
    design_mass, design_com, _ = _mass_and_com(nao_mjcf(effects, _design_truth(tmp_path)))
    truth = load_truth()
    mass, com, origin = _mass_and_com(nao_mjcf(effects, truth))
    extra = truth.torso_mass_kg - TORSO.mass
    assert mass - design_mass == pytest.approx(extra, abs=1e-9)
    # The torso frame is the world frame shifted to the torso origin (zero pose, unrotated):
    # the first moments [kg·m] of the real and the CAD torso swap.
    real = truth.torso_mass_kg * (origin + truth.torso_com_m)
    moment = real - TORSO.mass * (origin + TORSO.com)
    assert com == pytest.approx((design_mass * design_com + moment) / mass, abs=1e-9)
    assert com[0] - design_com[0] == pytest.approx(0.0029, abs=1e-4)  # truth.yaml comment


def test_design_model_keeps_the_urdf_torso() -> None:
    model = nao_ik_model()
    torso = model.body("torso")
    assert float(torso.mass[0]) == pytest.approx(TORSO.mass)
    assert torso.ipos == pytest.approx(TORSO.com)


def test_catalogue_c_starts_from_the_design_and_brackets_the_shipped_truth() -> None:
    params = default_parameters(get_robot("nao"), "C")
    assert [p.name for p in params] == ["torso_mass", "torso_com_x"]
    assert [p.nominal for p in params] == pytest.approx([TORSO.mass, TORSO.com[0]])
    assert [p.unit for p in params] == ["kg", "m"]
    doc = load_truth_doc(base_truth_path(get_robot("nao"), None))
    for p in params:
        (value,) = get_path(doc, p.path)
        assert p.lower < value < p.upper, p.name
        assert value != pytest.approx(p.nominal), p.name  # the real robot is not the CAD


def test_fitted_torso_round_trips_through_the_truth_document(tmp_path: Path) -> None:
    params = default_parameters(get_robot("nao"), "C")
    doc = load_truth_doc(DEFAULT_TRUTH_PATH)
    values = [1.2, -0.0125]
    fitted = write_fitted_truth(tmp_path / "fitted.yaml", doc, params, values, "fit C")
    truth = load_truth(fitted)
    assert truth.torso_mass_kg == pytest.approx(1.2)
    assert truth.torso_com_m == pytest.approx((-0.0125, 0.0, 0.045))  # y, z kept
    assert get_path(truth_doc_with(doc, params, values), "torso.com_m[0]") == [-0.0125]
    model = mujoco.MjModel.from_xml_string(nao_mjcf("all", fitted))
    assert float(model.body("torso").mass[0]) == pytest.approx(1.2)
    assert model.body("torso").ipos[0] == pytest.approx(-0.0125)


def _standing_wrench(truth: Path | None) -> tuple[float, float, float]:
    """Stand 1 s in the zero pose (ideal joints, exact F-T); return the F-T-measured weight
    [N], the centre of pressure x [m, world] and the torso origin x [m, world]."""
    sim = make_nao("none", truth)
    sim.command([0.0] * len(NAO_DRIVEN_JOINTS))
    sim.run(1.0)
    fz_sum, moment_sum = 0.0, 0.0
    for foot in ("left", "right"):
        fx, _, fz, _, ty, _ = sim.ft(foot)
        # CoP on the sole plane, SOLE_PLATE_M below the sensor (under the ankle, x = 0).
        x = (-ty - SOLE_PLATE_M * fx) / fz
        fz_sum, moment_sum = fz_sum + fz, moment_sum + fz * x
    ankle_x = float(sim.data.body("LFoot").xpos[0])
    return abs(fz_sum), ankle_x + moment_sum / fz_sum, float(sim.data.qpos[0])


def test_standing_ft_wrenches_recover_the_real_torso(tmp_path: Path) -> None:
    weight_d, cop_d, torso_x_d = _standing_wrench(_design_truth(tmp_path))
    weight, cop, torso_x = _standing_wrench(None)
    # Static: weight above the sensors and CoP = CoM projection. Difference = the torso's.
    mass = TORSO.mass + (weight - weight_d) / GRAVITY
    first_moment = (weight * cop - weight_d * cop_d) / GRAVITY
    com_x = (first_moment + TORSO.mass * (torso_x_d + TORSO.com[0])) / mass - torso_x
    truth = load_truth()
    assert mass == pytest.approx(truth.torso_mass_kg, abs=1e-4)
    assert com_x == pytest.approx(truth.torso_com_m[0], abs=5e-5)
