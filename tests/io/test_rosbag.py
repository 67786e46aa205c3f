"""ROS 2 bags: write them with rosbags' Writer (sqlite3 and MCAP), read them back exactly."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from rosbags.rosbag2.enums import StoragePlugin

from helpers.ft_data import FEET_YAML
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
from zmpkit.errors import InputFileError, ParameterError
from zmpkit.io import read_ft_source, read_robot_source, read_ros2_bag
from zmpkit.pipelines.zmp_log import run_zmp_log
from zmpkit.pipelines.zmp_log_files import write_zmp_log


def _stamps(n: int, offset_ns: int = 0) -> list[int]:
    return [T0_NS + offset_ns + k * 1_000_000 for k in range(n)]


def _wrenches(n: int, sign: float = 1.0) -> np.ndarray:
    return sign * (np.arange(n * 6, dtype=float).reshape(n, 6) * 0.125 + 300.0)


def _feet(n: int, left_offset_ns: int = 0) -> dict[str, tuple[str, list]]:
    right, left = _wrenches(n), _wrenches(n, -1.0)
    r = [(s + 7, wrench_msg(s, w)) for s, w in zip(_stamps(n), right, strict=True)]
    left_stamps = _stamps(n, left_offset_ns)
    m = [(s + 7, wrench_msg(s, w)) for s, w in zip(left_stamps, left, strict=True)]
    return {"/ft/right": (WRENCH, r), "/ft/left": (WRENCH, m)}


def _full_bag(path: Path, plugin: StoragePlugin, n: int = 20) -> Path:
    topics = _feet(n)
    names = ["hip", "knee", "ankle"]
    pos = np.linspace(-1.0, 1.0, n * 3).reshape(n, 3)
    joints = [
        (s + 3, joint_msg(s, names, p, 2.0 * p))
        for s, p in zip(_stamps(n, 500_000), pos, strict=True)
    ]
    quat = np.tile([0.0, 0.0, np.sin(0.1), np.cos(0.1)], (n, 1))
    imu = [
        (s + 1, imu_msg(s, np.array([k, 0.5, -0.5]), np.array([0.0, 0.1, 9.81]), quat[k]))
        for k, s in enumerate(_stamps(n, 250_000))
    ]
    topics |= {"/joint_states": (JOINTS, joints), "/imu": (IMU, imu)}
    return write_bag(path, topics, plugin)


@pytest.mark.parametrize("plugin", PLUGINS, ids=["sqlite3", "mcap"])
def test_round_trip_every_stream(tmp_path: Path, plugin: StoragePlugin) -> None:
    bag = _full_bag(tmp_path / "bag", plugin)
    log = read_ros2_bag(
        bag,
        right_topic="/ft/right",
        left_topic="/ft/left",
        joint_topic="/joint_states",
        imu_topic="/imu",
    )
    assert log.time_origin_ns == T0_NS
    np.testing.assert_array_equal(log.ft.time, np.arange(20) * 1_000_000 / 1e9)
    np.testing.assert_array_equal(log.ft.right_wrench, _wrenches(20))
    np.testing.assert_array_equal(log.ft.left_wrench, _wrenches(20, -1.0))
    assert log.joints is not None
    assert log.joints.names == ("hip", "knee", "ankle")
    np.testing.assert_array_equal(log.joints.time, (np.arange(20) * 1_000_000 + 500_000) / 1e9)
    np.testing.assert_array_equal(log.joints.position, np.linspace(-1.0, 1.0, 60).reshape(20, 3))
    np.testing.assert_array_equal(log.joints.velocity, 2.0 * log.joints.position)
    assert log.imu is not None
    np.testing.assert_array_equal(log.imu.angular_velocity[:, 0], np.arange(20.0))
    np.testing.assert_array_equal(log.imu.linear_acceleration[3], [0.0, 0.1, 9.81])
    np.testing.assert_array_equal(log.imu.orientation_xyzw[5], [0.0, 0.0, np.sin(0.1), np.cos(0.1)])


@pytest.mark.parametrize(("plugin", "suffix"), [(PLUGINS[0], "db3"), (PLUGINS[1], "mcap")])
def test_storage_file_alone_and_receive_time(
    tmp_path: Path, plugin: StoragePlugin, suffix: str
) -> None:
    write_bag(tmp_path / "bag", _feet(5), plugin)
    storage = next((tmp_path / "bag").glob(f"*.{suffix}"))
    ft = read_ft_source(
        storage, right_topic="/ft/right", left_topic="/ft/left", time_source="receive"
    )
    # receive times are header + 7 ns; the origin is the first receive time
    np.testing.assert_array_equal(ft.time, (np.arange(5) * 1_000_000) / 1e9)
    np.testing.assert_array_equal(ft.right_wrench, _wrenches(5))


def test_feet_on_separate_clocks_are_joined_on_the_right_clock(tmp_path: Path) -> None:
    bag = write_bag(tmp_path / "bag", _feet(10, left_offset_ns=500_000), PLUGINS[0])
    ft = read_ft_source(bag, right_topic="/ft/right", left_topic="/ft/left")
    # right samples 1..9 lie within the left span; left is linear in k so halfway is exact
    np.testing.assert_array_equal(ft.time, np.arange(1, 10) * 1_000_000 / 1e9)
    left = _wrenches(10, -1.0)
    np.testing.assert_allclose(ft.left_wrench, 0.5 * (left[:-1] + left[1:]), rtol=0, atol=1e-12)


def test_joint_order_follows_the_first_message(tmp_path: Path) -> None:
    msgs = [
        (1, joint_msg(T0_NS, ["a", "b"], np.array([1.0, 2.0]), np.zeros(0))),
        (2, joint_msg(T0_NS + 10, ["b", "a"], np.array([4.0, 3.0]), np.zeros(0))),
    ]
    bag = write_bag(tmp_path / "bag", _feet(2) | {"/js": (JOINTS, msgs)}, PLUGINS[1])
    log = read_robot_source(bag, right_topic="/ft/right", left_topic="/ft/left", joint_topic="/js")
    np.testing.assert_array_equal(log.joints.position, [[1.0, 2.0], [3.0, 4.0]])
    assert log.joints.velocity is None


def test_missing_topic_lists_the_topics_with_types(tmp_path: Path) -> None:
    bag = _full_bag(tmp_path / "bag", PLUGINS[0], n=3)
    with pytest.raises(
        InputFileError,
        match=r"bag: topic '/ft/r' not found; expected a geometry_msgs/msg/WrenchStamped topic; "
        r"the bag has: /ft/left \(geometry_msgs/msg/WrenchStamped\), /ft/right \(geometry_msgs/"
        r"msg/WrenchStamped\), /imu \(sensor_msgs/msg/Imu\), /joint_states \(sensor_msgs/msg/Joi",
    ):
        read_ros2_bag(bag, right_topic="/ft/r", left_topic="/ft/left")


def test_wrong_message_type(tmp_path: Path) -> None:
    bag = _full_bag(tmp_path / "bag", PLUGINS[1], n=3)
    with pytest.raises(
        InputFileError,
        match=r"topic '/imu' has message type sensor_msgs/msg/Imu; expected geometry_msgs/msg/Wr",
    ):
        read_ros2_bag(bag, right_topic="/ft/right", left_topic="/imu")


def test_empty_topic(tmp_path: Path) -> None:
    topics = _feet(3)
    topics["/ft/left"] = (WRENCH, [])
    bag = write_bag(tmp_path / "bag", topics, PLUGINS[0])
    with pytest.raises(
        InputFileError, match=r"topic '/ft/left' has no messages; expected at least"
    ):
        read_ros2_bag(bag, right_topic="/ft/right", left_topic="/ft/left")


def test_non_monotonic_header_stamps(tmp_path: Path) -> None:
    topics = _feet(4)
    msgs = topics["/ft/right"][1]
    msgs[2] = (msgs[2][0], wrench_msg(T0_NS, _wrenches(1)[0]))
    bag = write_bag(tmp_path / "bag", topics, PLUGINS[1])
    with pytest.raises(
        InputFileError,
        match=r"topic '/ft/right': header stamps must be strictly increasing, but message 3 "
        r"\(1712345678.123456789 s\) follows message 2 \(1712345678.124456789 s\); try time_so",
    ):
        read_ros2_bag(bag, right_topic="/ft/right", left_topic="/ft/left")


def test_nan_value_names_topic_message_and_field(tmp_path: Path) -> None:
    topics = _feet(4)
    w = _wrenches(1)[0]
    w[4] = np.nan
    topics["/ft/left"][1][1] = (T0_NS + 1_000_007, wrench_msg(T0_NS + 1_000_000, w))
    bag = write_bag(tmp_path / "bag", topics, PLUGINS[0])
    with pytest.raises(
        InputFileError,
        match=r"bag: topic '/ft/left', message 2: wrench.torque.y is nan; expected a finite",
    ):
        read_ros2_bag(bag, right_topic="/ft/right", left_topic="/ft/left")


def test_not_a_bag(tmp_path: Path) -> None:
    path = tmp_path / "broken.db3"
    path.write_bytes(b"SQLite format 3\x00" + b"\x01" * 200)
    with pytest.raises(InputFileError, match=r"broken.db3: cannot be opened as a ROS 2 bag"):
        read_ft_source(path, right_topic="/a", left_topic="/b")


def test_bag_without_topics_chosen_lists_wrench_topics(tmp_path: Path) -> None:
    bag = _full_bag(tmp_path / "bag", PLUGINS[0], n=2)
    with pytest.raises(
        ParameterError,
        match=r"needs right_topic and left_topic .*WrenchStamped topics: /ft/left, /ft/right$",
    ):
        read_ft_source(bag)


def test_zmp_pipeline_reads_a_bag(tmp_path: Path) -> None:
    n = 5
    load = np.tile([0.0, 0.0, -300.0, 0.0, 0.0, 0.0], (n, 1))  # sensor z points down
    msgs = [(s, wrench_msg(s, w)) for s, w in zip(_stamps(n), load, strict=True)]
    topics = {"/ft/right": (WRENCH, msgs), "/ft/left": (WRENCH, list(msgs))}
    bag = write_bag(tmp_path / "bag", topics, PLUGINS[1])
    (tmp_path / "feet.yaml").write_text(FEET_YAML)
    computed = run_zmp_log(
        bag, feet_path=tmp_path / "feet.yaml", right_topic="/ft/right", left_topic="/ft/left"
    )
    result = write_zmp_log(computed, tmp_path / "out")
    assert result.files["csv"].is_file()
    np.testing.assert_allclose(result.series.zmp[:, 1], 0.0, atol=1e-12)  # feet symmetric in y


def test_zmp_command_reads_a_bag_by_topic(tmp_path: Path) -> None:
    from zmpkit.cli import main

    n = 4
    load = np.tile([0.0, 0.0, -300.0, 0.0, 0.0, 0.0], (n, 1))  # sensor z points down
    msgs = [(s, wrench_msg(s, w)) for s, w in zip(_stamps(n), load, strict=True)]
    topics = {"/ft/right": (WRENCH, msgs), "/ft/left": (WRENCH, list(msgs))}
    bag = write_bag(tmp_path / "bag", topics, PLUGINS[0])
    (tmp_path / "feet.yaml").write_text(FEET_YAML)
    args = ["zmp", str(bag), "--right-topic", "/ft/right", "--left-topic", "/ft/left"]
    args += ["--feet", str(tmp_path / "feet.yaml"), "--out", str(tmp_path / "out")]
    assert main(args) == 0
    rows = (tmp_path / "out" / "zmp.csv").read_text().splitlines()
    assert len(rows) == n + 1
    bad = ["zmp", str(bag), "--right-topic", "/nope", "--left-topic", "/ft/left"]
    assert main([*bad, "--feet", str(tmp_path / "feet.yaml"), "--out", str(tmp_path / "o")]) == 2
