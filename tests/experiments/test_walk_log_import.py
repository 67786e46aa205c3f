"""A walk log imported from a ROS 2 bag: streams on their own clocks, put on the encoders'.

A walk log of known values is written into a bag as a robot would record it (feet, encoders,
commands at a lower rate, IMU half a sample late), imported, and compared with the values
the module's rules give: rows at the encoder stamps the streams share, commands held, the
IMU interpolated (linear signals, so interpolation is exact), the orientation reordered to
w, x, y, z. Then the errors a user meets: no orientation, a commanded joint without an
encoder, streams that do not overlap.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from helpers.rosbag_data import (
    IMU,
    JOINTS,
    PLUGINS,
    T0_NS,
    WRENCH,
    imu_msg,
    joint_msg,
    wrench_msg,
    write_bag,
)
from helpers.yarp_data import T0, fmt, write_dump
from zmpkit.cli import main
from zmpkit.errors import InputFileError
from zmpkit.experiments.walk_log import read_walk_log
from zmpkit.experiments.walk_log_import import walk_log_from_source
from zmpkit.io import LogUnits
from zmpkit.sensors import rpy_to_matrix

N = 40
PERIOD_NS = 5_000_000  # 200 Hz encoders and feet
NAMES = ["hip", "knee", "ankle"]


def _time_ns(k: np.ndarray | int, offset_ns: int = 0) -> np.ndarray:
    return T0_NS + offset_ns + np.asarray(k, dtype=np.int64) * PERIOD_NS


def _encoders(k: np.ndarray) -> np.ndarray:
    return np.stack([0.01 * k, -0.02 * k, 0.5 + 0.003 * k], axis=-1).astype(float)


def _commands(k: np.ndarray) -> np.ndarray:
    return _encoders(k) + 0.05


def _wrench(k: np.ndarray, sign: float) -> np.ndarray:
    base = np.array([1.0, -2.0, 150.0, 0.5, -0.25, 0.1])
    return sign * (base + 0.01 * np.asarray(k, dtype=float)[..., None])


def _gyro(t_s: np.ndarray) -> np.ndarray:
    return np.stack([0.1 + t_s, -0.2 * t_s, 0.3 + 0 * t_s], axis=-1)


def _bag(
    path: Path,
    imu_orientation: bool = True,
    command_names: list[str] = NAMES,
    command_delay_ns: int = 1_000_000,
) -> Path:
    k = np.arange(N)
    stamps = [int(s) for s in _time_ns(k)]
    feet = {
        f"/ft/{side}": (
            WRENCH,
            [(s, wrench_msg(s, _wrench(i, sign))) for i, s in zip(k, stamps, strict=True)],
        )
        for side, sign in (("right", 1.0), ("left", -1.0))
    }
    encoders = [
        (int(s), joint_msg(int(s), NAMES, _encoders(i), np.zeros(3)))
        for i, s in zip(k, _time_ns(k), strict=True)
    ]
    sent = k[::4]  # commands at 50 Hz, sent 1 ms after the encoder sample
    commands = [
        (int(s), joint_msg(int(s), command_names, _commands(i), np.zeros(0)))
        for i, s in zip(sent, _time_ns(sent, command_delay_ns), strict=True)
    ]
    quat = np.array([0.0, np.sin(0.05), 0.0, np.cos(0.05)])
    imu_stamps = _time_ns(np.arange(-1, N), PERIOD_NS // 2)  # half a period late
    imu = []
    for s in imu_stamps:
        msg = imu_msg(int(s), _gyro((s - T0_NS) * 1e-9), np.array([0.0, 0.0, 9.81]), quat)
        if not imu_orientation:  # REP 145: orientation absent
            msg.orientation_covariance[0] = -1.0
        imu.append((int(s), msg))
    topics = feet | {
        "/joint_states": (JOINTS, encoders),
        "/joint_commands": (JOINTS, commands),
        "/imu": (IMU, imu),
    }
    return write_bag(path, topics, PLUGINS[0])


def _import(bag: Path):
    return walk_log_from_source(
        bag,
        right_topic="/ft/right",
        left_topic="/ft/left",
        joint_topic="/joint_states",
        command_topic="/joint_commands",
        imu_topic="/imu",
    )


def test_streams_on_the_encoders_clock(tmp_path: Path) -> None:
    log = _import(_bag(tmp_path / "bag"))
    # rows: encoder samples from the first command (k = 1, 1 ms after k = 0) to the end
    k = np.arange(1, N)
    # times from the earliest stamp of all streams (the IMU's, half a period before k = 0)
    np.testing.assert_allclose(log.time_s, (k + 0.5) * PERIOD_NS * 1e-9, atol=1e-12)
    assert log.joint_names == tuple(NAMES)
    np.testing.assert_allclose(log.q_enc_rad, _encoders(k), atol=1e-12)
    held = (k - 1) // 4 * 4  # the last command sent at or before each row
    np.testing.assert_allclose(log.q_cmd_rad, _commands(held), atol=1e-12)
    np.testing.assert_allclose(log.right_wrench, _wrench(k, 1.0), atol=1e-9)
    np.testing.assert_allclose(log.left_wrench, _wrench(k, -1.0), atol=1e-9)
    assert log.gyro_rps is not None
    np.testing.assert_allclose(log.gyro_rps, _gyro(k * PERIOD_NS * 1e-9), atol=1e-9)  # linear
    np.testing.assert_allclose(log.imu_quat_wxyz[0], [np.cos(0.05), 0.0, np.sin(0.05), 0.0])


def test_the_cli_writes_a_log_the_fit_reads(tmp_path: Path) -> None:
    bag = _bag(tmp_path / "bag")
    out = tmp_path / "walk_log.csv"
    args = ["walk", "import", str(bag), "--right-topic", "/ft/right", "--left-topic", "/ft/left"]
    args += ["--joint-topic", "/joint_states", "--command-topic", "/joint_commands"]
    assert main([*args, "--imu-topic", "/imu", "--out", str(out)]) == 0
    read = read_walk_log(out)
    direct = _import(bag)
    np.testing.assert_allclose(read.q_cmd_rad, direct.q_cmd_rad, rtol=1e-9)
    np.testing.assert_allclose(read.right_wrench, direct.right_wrench, rtol=1e-9)


def test_an_imu_without_orientation_is_refused(tmp_path: Path) -> None:
    with pytest.raises(InputFileError, match="no orientation"):
        _import(_bag(tmp_path / "bag", imu_orientation=False))


def test_a_commanded_joint_without_encoder_is_refused(tmp_path: Path) -> None:
    with pytest.raises(InputFileError, match=r"commanded joints \['wrist'\] have no encoder"):
        _import(_bag(tmp_path / "bag", command_names=["hip", "knee", "wrist"]))


def test_streams_that_do_not_overlap_are_refused(tmp_path: Path) -> None:
    bag = _bag(tmp_path / "bag", command_delay_ns=2 * N * PERIOD_NS)  # sent after the walk
    with pytest.raises(InputFileError, match=r"do not overlap: feet 0\.0"):
        _import(bag)


def test_yarp_dumps_in_degrees(tmp_path: Path) -> None:
    """Encoder and command ports in degrees, the legacy inertial port (rpy in degrees)."""
    root, n, dt = tmp_path / "yarp", 30, 0.01
    stamps = T0 + np.arange(n) * dt
    k = np.arange(n)
    wrench = [fmt(w) for w in _wrench(k, 1.0)]
    write_dump(root / "jr3" / "ch0_o", "/jr3/ch0:o", wrench, stamps)
    write_dump(
        root / "jr3" / "ch1_o",
        "/jr3/ch1:o",
        [fmt(-np.asarray(w.split(), float)) for w in wrench],
        stamps,
    )
    degrees = np.rad2deg(_encoders(k))
    write_dump(root / "leg" / "state_o", "/leg/state:o", [fmt(q) for q in degrees], stamps)
    sent = k[::2]
    commands = [fmt(np.rad2deg(_commands(i))) for i in sent]
    write_dump(root / "leg" / "command_o", "/leg/command:o", commands, stamps[sent] + 0.001)
    rpy_deg = np.array([1.0, 3.0, -20.0])
    imu = [
        fmt(np.r_[rpy_deg, [0.0, 0.0, 9.81], np.rad2deg(_gyro(t)), [0.3, 0.1, -0.5]])
        for t in k * dt
    ]
    write_dump(root / "imu_o", "/imu:o", imu, stamps + 0.002)
    log = walk_log_from_source(
        root,
        joint_topic="/leg/state:o",
        command_topic="/leg/command:o",
        imu_topic="/imu:o",
        joint_names=NAMES,
        units=LogUnits(joint_angle_unit="deg", imu_angular_velocity_unit="deg/s"),
    )
    rows = np.arange(1, n)  # from the first encoder row after the first command and IMU sample
    assert log.joint_names == tuple(NAMES)
    np.testing.assert_allclose(log.q_enc_rad, _encoders(rows), atol=1e-12)
    np.testing.assert_allclose(log.q_cmd_rad, _commands((rows - 1) // 2 * 2), atol=1e-12)
    w, x, y, z = log.imu_quat_wxyz[0]
    rotation = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )
    np.testing.assert_allclose(rotation, rpy_to_matrix(np.deg2rad(rpy_deg)), atol=1e-9)
