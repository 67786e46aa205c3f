"""Designed double-support experiments: soles flat, the CoM on its path, replayed exactly."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from zmpkit.errors import ParameterError
from zmpkit.experiments.double_support import (
    CHIRP_HZ,
    RAMP_S,
    SWAY_SHARE,
    double_support_targets,
)
from zmpkit.experiments.double_support_record import record_double_support
from zmpkit.models.pendulum import STANDARD_GRAVITY_MPS2
from zmpkit.robots.registry import get_robot
from zmpkit.sim.names import sole_site
from zmpkit.simfit.experiments import read_experiments
from zmpkit.simfit.rollout import simulate_experiment
from zmpkit.simfit.truth_doc import base_truth_path, load_robot_truth, load_truth_doc

NAO = get_robot("nao")


@pytest.fixture(scope="module")
def squat():
    return double_support_targets(NAO, "squat")


def _played(targets, effects: str = "none"):
    """Play the targets as the recorder does; the sole sites, the CoM and both feet's F_z."""
    sim = NAO.make_simulation(effects)
    ticks = np.round(targets.time_s / sim.dt).astype(int)
    wanted = set(ticks.tolist())
    soles, com, fz = [], [], []
    for k in range(int(ticks[-1])):
        t = (k + 1) * sim.dt
        sim.servo.reset([float(np.interp(t, targets.time_s, q)) for q in targets.q_rad.T])
        sim.step(1)
        if k + 1 in wanted:
            soles.append([sim.data.site(sole_site(f.foot)).xpos.copy() for f in sim.robot.feet])
            com.append(sim.data.subtree_com[0].copy())
            fz.append(sim.ft("right")[2] + sim.ft("left")[2])
    return np.array(soles), np.array(com), np.array(fz)


def test_the_squat_keeps_the_soles_and_lowers_the_com_by_the_walking_crouch(squat) -> None:
    assert squat.com_error_m < 1e-3
    soles, com, fz = _played(squat)
    # Soles flat where they stood (within a millimetre of sinking into the soft contact).
    assert np.max(np.abs(soles - soles[0])) < 2e-3
    assert np.all(fz > 0.8 * np.median(fz))  # both feet carry the robot throughout
    standing = com[0, 2]
    crouched = com[np.searchsorted(squat.time_s, RAMP_S), 2]
    expected = max(standing - NAO.require_walking().com_height_m, 0.08 * standing)
    assert standing - crouched == pytest.approx(expected, abs=4e-3)
    # The squat then travels 4 % of the standing height below the crouch, and back.
    after = com[squat.time_s > RAMP_S, 2]
    assert crouched - after.min() == pytest.approx(0.04 * standing, abs=4e-3)


@pytest.mark.slow
def test_the_chirp_keeps_the_lipm_zmp_excursion_at_its_share_of_the_sole() -> None:
    """The CoM follows x(t) = A_p / (1 + ω(t)² z_c/g) sin φ(t): its sway shrinks as the
    frequency grows so that the LIPM's ZMP sways A_p at every frequency."""
    sway = double_support_targets(NAO, "sway_sagittal")
    _, com, _ = _played(sway)
    t = sway.time_s
    zmp_amplitude = SWAY_SHARE * NAO.require_walking().sole_size_m[0] / 2.0
    z_c = com[np.searchsorted(t, RAMP_S), 2]
    s = np.clip(t - RAMP_S, 0.0, None)
    f0, f1 = CHIRP_HZ
    rate = (f1 - f0) / (t[-1] - RAMP_S)
    omega = 2.0 * np.pi * (f0 + rate * s)
    phase = 2.0 * np.pi * (f0 * s + 0.5 * rate * s * s)
    expected = zmp_amplitude / (1.0 + omega**2 * z_c / STANDARD_GRAVITY_MPS2) * np.sin(phase)
    x = com[:, 0] - com[0, 0]
    moving = t > RAMP_S
    assert np.max(np.abs(x[moving] - expected[moving])) < 1.5e-3
    assert np.max(np.abs(x[moving])) > 0.5 * zmp_amplitude  # it does sway


def test_a_recording_is_what_the_fit_replays_at_the_same_seed(squat, tmp_path: Path) -> None:
    """The recorder and the fit's step replay run the same ticks: the same encoders and ZMP
    (to the last bits the CSV's 10 significant digits leave in the commanded angles)."""
    folder = record_double_support(NAO, squat, "M,G,S", None, 0, tmp_path / "squat")
    assert folder is not None
    (experiment,) = read_experiments([folder], NAO)
    truth = load_robot_truth(NAO, load_truth_doc(base_truth_path(NAO, None)))
    replay = simulate_experiment(experiment, truth, "M,G,S")
    np.testing.assert_allclose(replay.q_meas_rad, experiment.signals.q_meas_rad, atol=1e-9)
    np.testing.assert_allclose(replay.zmp_m, experiment.signals.zmp_m, atol=1e-7)
    np.testing.assert_allclose(replay.force_z_n, experiment.signals.force_z_n, atol=1e-6)
    assert np.all(replay.force_z_n > 5.0)  # both feet carry the robot


def test_an_unknown_design_is_named_with_the_valid_ones() -> None:
    with pytest.raises(ParameterError, match="crouch_hold"):
        double_support_targets(NAO, "jump")
