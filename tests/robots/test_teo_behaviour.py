"""The virtual TEO behaves like paper A's robot under LIPM step commands (issue 3).

A *lean* is paper A's open-loop ankle strategy (§4.1, Fig. 9 and 14): from the upright
stance, command the LIPM angle for a ZMP target as a step (through TEO's servo trajectory
limits), hold, and measure the ZMP from the ankle F-T sensors as a user would (measured
wrenches, nominal sensor mounts, start-up offset removed).

- sagittal: both ankle pitch joints by θ, so the robot above the ankles leans forward;
- frontal: both ankle roll joints by θ and both hip roll joints by −θ (a parallelogram), so
  the pelvis shifts sideways, level, and the feet stay flat.

The LIPM angle is ``θ = asin(x_ref / l)`` with ``l`` the lean lever of the rigid design
geometry (the CoM's displacement per radian about the ankle axes, ≈ 0.777 m sagittal: the
ankle axis is 0.123 m above the sole). Run as a script to print the steady-state tables::

    .venv/bin/python tests/robots/test_teo_behaviour.py --effects 'all;none' --plane both
"""

from __future__ import annotations

import argparse
import math
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from functools import cache

import mujoco
import numpy as np
import pytest

from zmpkit.errors import SimulationDivergedError
from zmpkit.experiments import design_lean_model
from zmpkit.io import feet_from_mapping
from zmpkit.robots.registry import get_robot
from zmpkit.robots.teo import (
    TEO_BALANCE_MASS_KG,
    TEO_SERVO_LIMITS,
    TeoTruth,
    make_teo,
    teo_feet_mounts,
    teo_mjcf,
)
from zmpkit.sensors.fast import DoubleSupportZmp
from zmpkit.sim.names import ft_site
from zmpkit.sim.world import Simulation

G = 9.81
PLANES = ("sagittal", "frontal")
TARGETS_M = tuple(round(0.01 * i, 2) for i in range(1, 11))
SAMPLE_S = 0.005  # F-T sample period (200 Hz) [s]
SETTLE_S = 1.5  # stand at least this long before the baseline window [s]
SETTLE_MAX_S = 10.0  # ... and at most this long [s]
SETTLED_M = 1e-4  # settled: ZMP peak-to-peak over the baseline window below this [m]
BASELINE_S = 0.5  # start-up offset window [s]
STEADY_WINDOW_S = 1.0  # steady-state mean over the last second [s]


def lean_joints(plane: str, angle: float) -> dict[str, float]:
    """Joint targets [rad] of a lean by ``angle`` [rad] in ``plane`` (positive = +x or +y)."""
    return design_lean_model(get_robot("teo"), plane).joint_targets(angle)


@cache
def lean_lever(plane: str) -> float:
    """d(CoM above the sensors)/dθ in the foot frame of the rigid design geometry [m/rad]."""
    model = mujoco.MjModel.from_xml_string(teo_mjcf("none"))
    data = mujoco.MjData(model)
    axis = 0 if plane == "sagittal" else 1
    soles = {model.body(f"{s}_sole").id for s in ("right", "left")}
    weights = np.array([0.0 if b in soles else m for b, m in enumerate(model.body_mass)])

    def com_in_foot(angle: float) -> float:
        data.qpos[:] = model.qpos0
        for joint, q in lean_joints(plane, angle).items():
            data.qpos[model.jnt_qposadr[model.joint(joint).id]] = q
        mujoco.mj_kinematics(model, data)
        com = weights @ data.xipos / weights.sum()
        site = data.site(ft_site("right"))
        return float((site.xmat.reshape(3, 3).T @ (com - site.xpos))[axis])

    step = 1e-4
    return (com_in_foot(step) - com_in_foot(-step)) / (2 * math.sin(step))


def lipm_angle(plane: str, target_m: float) -> float:
    """The LIPM ankle angle for a ZMP target, ``asin(x_ref / l)`` [rad]."""
    return math.asin(target_m / lean_lever(plane))


@dataclass(frozen=True)
class Lean:
    """One lean: the measured ZMP along the plane's axis after the command.

    Attributes:
        target: ZMP target x_ref [m].
        time: sample times from the command [s].
        zmp: measured ZMP minus the start-up offset [m].
        steady: mean ZMP over the last :data:`STEADY_WINDOW_S` [m].
        drift: steady minus the mean of the window before it [m] (≈ 0 once settled).
        fell: a foot lost contact or the simulation diverged.
        fz_sum_n: sum of the measured F_z at the end [N].
    """

    target: float
    time: np.ndarray
    zmp: np.ndarray
    steady: float
    drift: float
    fell: bool
    fz_sum_n: float

    @property
    def error_pct(self) -> float:
        """100 (steady − target) / target [%]."""
        return 100.0 * (self.steady - self.target) / self.target

    @property
    def overshoot_pct(self) -> float:
        """100 (peak − steady) / steady, peak after the command [%]."""
        return 100.0 * (float(np.max(self.zmp)) - self.steady) / self.steady

    @property
    def ringing_pct(self) -> float:
        """Peak-to-peak of the ZMP in the second after the setpoint stops, % of steady."""
        moving = lean_duration_s(self.target)
        window = (self.time > moving) & (self.time < moving + 1.0)
        return 100.0 * float(np.ptp(self.zmp[window])) / self.steady


def lean_duration_s(target_m: float, plane: str = "sagittal") -> float:
    """Time the servo setpoint takes to reach the lean angle (bang-bang in acceleration) [s]."""
    lim = TEO_SERVO_LIMITS
    angle = abs(lipm_angle(plane, target_m))
    t_acc = math.sqrt(angle / lim.max_acceleration)
    if lim.max_acceleration * t_acc <= lim.max_velocity:
        return 2 * t_acc
    t_v = lim.max_velocity / lim.max_acceleration
    return 2 * t_v + (angle - lim.max_velocity * t_v) / lim.max_velocity


def _zmp_component(sim: Simulation, zmp: DoubleSupportZmp, axis: int) -> float | None:
    point = zmp(tuple(sim.ft("right")), tuple(sim.ft("left")))
    return None if point is None else point[axis]


def _stand_still(sim: Simulation, zmp: DoubleSupportZmp, axis: int) -> float:
    """Stand until the ZMP is still over a baseline window; return its mean (the offset)."""
    sim.run(SETTLE_S)
    while True:
        base = []
        for _ in range(round(BASELINE_S / SAMPLE_S)):
            sim.run(SAMPLE_S)
            base.append(_zmp_component(sim, zmp, axis))
        if np.ptp(base) < SETTLED_M or sim.time > SETTLE_MAX_S:
            return float(np.mean(base))


def run_lean(
    effects: str,
    plane: str,
    target_m: float,
    hold_s: float = 6.0,
    seed: int = 0,
    truth: TeoTruth | None = None,
) -> Lean:
    """Stand, remove the start-up ZMP offset, command the LIPM lean, hold and record."""
    sim = make_teo(effects, truth=truth, seed=seed)
    mounts = feet_from_mapping(teo_feet_mounts())
    zmp = DoubleSupportZmp(mounts["right"], mounts["left"])
    axis = 0 if plane == "sagittal" else 1
    offset = _stand_still(sim, zmp, axis)
    sim.command(lean_joints(plane, lipm_angle(plane, target_m)))
    n = round(hold_s / SAMPLE_S)
    values = np.full(n, np.nan)
    fell = False
    try:
        for k in range(n):
            sim.run(SAMPLE_S)
            p = _zmp_component(sim, zmp, axis)
            if p is None or min(sim.ft("right")[2], sim.ft("left")[2]) < 10.0:
                fell = True
                break
            values[k] = p - offset
    except SimulationDivergedError:  # a diverged simulation counts as a fall
        fell = True
    w = round(STEADY_WINDOW_S / SAMPLE_S)
    return Lean(
        target=target_m,
        time=SAMPLE_S * np.arange(1, n + 1),
        zmp=values,
        steady=float(np.mean(values[-w:])),
        drift=float(np.mean(values[-w:]) - np.mean(values[-2 * w : -w])),
        fell=fell,
        fz_sum_n=float(sim.ft("right")[2] + sim.ft("left")[2]),
    )


# --- tests ---------------------------------------------------------------------------------

PAPER_A_FIT = (0.834, 1.024, -0.0004)  # x_FT = a x² + b x + c, paper A Eq. (13) [1/m, -, m]


def settling_after_stop_s(lean: Lean, plane: str, band: float = 0.02) -> float:
    """Time after the setpoint stops until the ZMP stays within ``band`` of steady [s]."""
    after = lean.time > lean_duration_s(lean.target, plane)
    smooth = np.convolve(lean.zmp[after] - lean.steady, np.ones(10) / 10, mode="same")
    outside = np.flatnonzero(np.abs(smooth) > band * lean.target)
    return float(outside[-1] * SAMPLE_S) if outside.size else 0.0


def oscillation_hz(lean: Lean, plane: str, seconds: float = 2.0) -> float:
    """Mean frequency of the ZMP's swings about steady after the setpoint stops [Hz]."""
    t_end = lean_duration_s(lean.target, plane)
    window = (lean.time > t_end) & (lean.time < t_end + seconds)
    smooth = np.convolve(lean.zmp[window] - lean.steady, np.ones(10) / 10, mode="valid")
    crossings = np.count_nonzero(np.diff(np.sign(smooth)) != 0)
    return crossings / (2.0 * seconds)


@cache
def sweep(effects: str, plane: str) -> tuple[Lean, ...]:
    """Leans at every target of :data:`TARGETS_M`, held 10 s (shared by the slow tests)."""
    return tuple(run_lean(effects, plane, t, hold_s=10.0) for t in TARGETS_M)


def test_lean_levers_are_the_ankle_pendulum() -> None:
    assert lean_lever("sagittal") == pytest.approx(0.7767, abs=2e-3)
    assert 0.45 < lean_lever("frontal") < 0.55  # legs 0.63 m, the upper body moves, they tilt


def test_frontal_lean_keeps_both_feet_flat_where_they_stand() -> None:
    model = mujoco.MjModel.from_xml_string(teo_mjcf("none"))
    data = mujoco.MjData(model)

    def left_foot_in_right_foot(joints: dict[str, float]) -> np.ndarray:
        data.qpos[:] = model.qpos0
        for joint, q in joints.items():
            data.qpos[model.jnt_qposadr[model.joint(joint).id]] = q
        mujoco.mj_kinematics(model, data)
        right, left = data.site(ft_site("right")), data.site(ft_site("left"))
        rot = right.xmat.reshape(3, 3).T
        return np.concatenate(
            [rot @ (left.xpos - right.xpos), (rot @ left.xmat.reshape(3, 3)).ravel()]
        )

    rest = left_foot_in_right_foot({})
    for angle in (-0.2, 0.05, 0.2):
        np.testing.assert_allclose(
            left_foot_in_right_foot(lean_joints("frontal", angle)), rest, atol=1e-12
        )
    naive = {"right_ankle_sagittal": 0.2, "left_ankle_sagittal": 0.2}
    naive |= {"right_hip_sagittal": -0.2, "left_hip_sagittal": -0.2}
    gap = left_foot_in_right_foot(naive)[2] - rest[2]  # a parallelogram command lifts a foot
    assert abs(gap) == pytest.approx(2 * 0.0175 * np.sin(0.2), rel=0.01)


@pytest.mark.slow
def test_all_effects_zmp_error_grows_with_the_target() -> None:
    near, far = (run_lean("all", "sagittal", t, hold_s=5.0) for t in (0.02, 0.08))
    assert not near.fell
    assert not far.fell
    assert 1.0 < near.error_pct < 5.0
    assert far.error_pct > near.error_pct + 3.0
    assert far.error_pct < 12.0


def test_rigid_robot_meets_the_lipm_and_weighs_its_mass() -> None:
    lean = run_lean("none", "sagittal", 0.10, hold_s=4.0)
    assert abs(lean.error_pct) < 0.5
    assert lean.fz_sum_n == pytest.approx(TEO_BALANCE_MASS_KG * G, rel=0.005)


@pytest.mark.slow
@pytest.mark.parametrize("plane", PLANES)
def test_all_effects_error_grows_like_paper_a(plane: str) -> None:
    leans = sweep("all", plane)
    assert not any(lean.fell for lean in leans)
    errors = np.array([lean.error_pct for lean in leans])
    assert np.all(np.diff(errors) > 0.0), errors  # grows with the target
    assert 1.0 < errors[1] < 5.0  # 0.02 m: paper A's fit gives 2.1 %
    assert 8.0 < errors[-1] < 13.0  # 0.10 m: fit 10.3 %, Table 1 11.6 %; issue: 2-15 %
    a, b, c = PAPER_A_FIT
    x = np.array(TARGETS_M)
    fit = 100 * (a * x**2 + (b - 1) * x + c) / x
    assert np.all(np.abs(errors[1:] - fit[1:]) < 2.5), errors - fit  # 0.01 m: c dominates
    assert all(abs(lean.drift) < 0.005 * lean.target for lean in leans)  # settled


@pytest.mark.slow
@pytest.mark.parametrize("plane", PLANES)
def test_rigid_robot_error_is_below_half_a_percent(plane: str) -> None:
    leans = sweep("none", plane)
    assert all(abs(lean.error_pct) < 0.5 for lean in leans)
    assert all(lean.fz_sum_n == pytest.approx(TEO_BALANCE_MASS_KG * G, rel=0.005) for lean in leans)


@pytest.mark.slow
def test_all_effects_step_response_is_under_damped() -> None:
    """A lightly damped lean mode of a few Hz rings after the setpoint stops (Fig. 14)."""
    for target in (0.04, 0.06):
        index = TARGETS_M.index(target)
        soft, rigid = sweep("all", "sagittal")[index], sweep("none", "sagittal")[index]
        assert soft.overshoot_pct > 10.0
        assert settling_after_stop_s(soft, "sagittal") > 0.5
        assert settling_after_stop_s(soft, "sagittal") > 2 * settling_after_stop_s(
            rigid, "sagittal"
        )
        assert 1.0 < oscillation_hz(soft, "sagittal") < 5.0


# --- script --------------------------------------------------------------------------------


def _job(args: tuple[str, str, float, float]) -> tuple[str, str, float, Lean]:
    effects, plane, target, hold = args
    return effects, plane, target, run_lean(effects, plane, target, hold)


def main() -> None:
    """Print the steady-state error table for effect sets, planes and targets."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--effects", default="all;none", help="';'-separated effect sets")
    parser.add_argument("--plane", default="both", choices=(*PLANES, "both"))
    parser.add_argument("--targets", default=",".join(str(t) for t in TARGETS_M))
    parser.add_argument("--hold", type=float, default=6.0)
    parser.add_argument("--jobs", type=int, default=2)
    opts = parser.parse_args()
    sets = opts.effects.split(";")
    planes = PLANES if opts.plane == "both" else (opts.plane,)
    targets = [float(t) for t in opts.targets.split(",")]
    jobs = [(e, p, t, opts.hold) for e in sets for p in planes for t in targets]
    with ProcessPoolExecutor(opts.jobs) as pool:
        results = list(pool.map(_job, jobs))
    for e in sets:
        for p in planes:
            rows = [r[3] for r in results if r[0] == e and r[1] == p]
            print(f"\n{e:>6} {p:8s} " + " ".join(f"{r.target:6.2f}" for r in rows))
            print(f"{'err %':>15s} " + " ".join(f"{r.error_pct:6.2f}" for r in rows))
            print(f"{'overshoot %':>15s} " + " ".join(f"{r.overshoot_pct:6.1f}" for r in rows))
            print(f"{'ringing %':>15s} " + " ".join(f"{r.ringing_pct:6.1f}" for r in rows))
            print(f"{'drift %':>15s} " + " ".join(f"{100 * r.drift / r.target:6.2f}" for r in rows))
            print(f"{'fell':>15s} " + " ".join(f"{r.fell!s:>6s}" for r in rows))
            print(
                f"{'sum Fz/mg':>15s} " + " ".join(f"{r.fz_sum_n / (62.6 * G):6.4f}" for r in rows)
            )


if __name__ == "__main__":
    main()
