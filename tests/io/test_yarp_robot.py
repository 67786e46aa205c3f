"""YARP joints and IMU through read_robot_source: dumps written here, read back exactly;
every bad file named with its line; garbage never escapes as anything but InputFileError."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from helpers.yarp_data import T0, write_dump
from helpers.yarp_data import fmt as _fmt
from zmpkit.errors import InputFileError, ParameterError
from zmpkit.io import LogUnits, RobotLog, read_ft_source, read_robot_source, read_yarp_imu, resample
from zmpkit.sensors import rpy_to_matrix

DT = 0.01
LEFT_LEG = "/teo/leftLeg/state:o"
RIGHT_LEG = "/teo/rightLeg/state:o"
IMU = "/teo/imu:o"
NAMES = ("l_hip_yaw", "l_hip_roll", "l_hip_pitch", "r_hip_yaw", "r_hip_roll", "r_hip_pitch")


def _stamps(n: int, offset: float = 0.0) -> np.ndarray:
    return T0 + offset + np.arange(n) * DT


def _feet(root: Path, n: int) -> None:
    rows = np.arange(n * 6, dtype=float).reshape(n, 6) * 0.5 - 7.25
    write_dump(root / "jr3" / "ch0_o", "/jr3/ch0:o", [_fmt(r) for r in rows], _stamps(n))
    write_dump(root / "jr3" / "ch1_o", "/jr3/ch1:o", [_fmt(-r) for r in rows], _stamps(n))


def _legs(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Joint angles [deg], linear in time so that interpolation is exact."""
    k = np.arange(n, dtype=float)[:, None]
    return 10.0 + k * np.array([0.5, -1.0, 2.0]), -20.0 + k * np.array([1.5, 0.25, -3.0])


def _imu_rows(n: int) -> np.ndarray:
    """rpy [deg], acc [m/s²], gyro [deg/s], mag: 12 columns."""
    k = np.arange(n, dtype=float)[:, None]
    return np.hstack(
        [
            [5.0, -10.0, 30.0] + k * [0.5, 1.0, -2.0],
            [0.1, -0.2, 9.81] + k * 0.01,
            [45.0, -90.0, 180.0] + k * 3.0,
            np.tile([0.3, 0.1, -0.5], (n, 1)),
        ]
    )


def _mas_body(gyro: np.ndarray, acc: np.ndarray, rpy: np.ndarray | None, ts: float) -> str:
    """A multipleanalogsensorsserver bottle (11 groups) with one IMU."""
    orient = "()" if rpy is None else f"((({_fmt(rpy)}) {ts!r}))"
    groups = [f"((({_fmt(gyro)}) {ts!r}))", f"((({_fmt(acc)}) {ts!r}))", "()", orient]
    return " ".join(groups + ["()"] * 7)


def _robot(root: Path, n: int = 8) -> Path:
    _feet(root, n)
    left, right = _legs(n)
    write_dump(root / "teo" / "leftLeg" / "state_o", LEFT_LEG, [_fmt(r) for r in left], _stamps(n))
    write_dump(
        root / "teo" / "rightLeg" / "state_o", RIGHT_LEG, [_fmt(r) for r in right], _stamps(n)
    )
    write_dump(root / "teo" / "imu_o", IMU, [_fmt(r) for r in _imu_rows(n)], _stamps(n, 0.002))
    return root


def _read(root: Path, **kwargs: object) -> RobotLog:
    options = {"joint_topic": [LEFT_LEG, RIGHT_LEG], "imu_topic": IMU, **kwargs}
    return read_robot_source(root, **options)  # type: ignore[arg-type]


def test_joints_and_legacy_imu_round_trip_on_one_origin(tmp_path: Path) -> None:
    log = _read(_robot(tmp_path / "log"), joint_names=NAMES)
    left, right = _legs(8)
    assert log.joints is not None
    assert log.imu is not None
    assert log.joints.names == NAMES
    np.testing.assert_array_equal(log.joints.position, np.hstack([left, right]))
    assert log.joints.velocity is None
    np.testing.assert_array_equal(log.joints.time, _stamps(8) - T0)
    np.testing.assert_array_equal(log.ft.time, _stamps(8) - T0)
    np.testing.assert_allclose(log.imu.time, _stamps(8, 0.002) - T0, rtol=0, atol=1e-9)
    rows = _imu_rows(8)
    np.testing.assert_array_equal(log.imu.angular_velocity, rows[:, 6:9])
    np.testing.assert_array_equal(log.imu.linear_acceleration, rows[:, 3:6])
    assert log.time_origin_ns == round(T0 * 1e9)


def test_euler_angles_follow_yarps_rz_ry_rx_in_degrees(tmp_path: Path) -> None:
    log = _read(_robot(tmp_path / "log"))
    rows = _imu_rows(8)
    for quat, rpy_deg in zip(log.imu.orientation_xyzw, rows[:, :3], strict=True):
        expected = rpy_to_matrix(np.deg2rad(rpy_deg))
        np.testing.assert_allclose(Rotation.from_quat(quat).as_matrix(), expected, atol=1e-12)
        assert np.linalg.norm(quat) == pytest.approx(1.0, abs=1e-12)


def test_units_turn_degrees_into_radians(tmp_path: Path) -> None:
    units = LogUnits(joint_angle_unit="deg", imu_angular_velocity_unit="deg/s")
    log = _read(_robot(tmp_path / "log"), units=units)
    left, right = _legs(8)
    np.testing.assert_allclose(log.joints.position, np.deg2rad(np.hstack([left, right])))
    np.testing.assert_allclose(log.imu.angular_velocity, np.deg2rad(_imu_rows(8)[:, 6:9]))
    np.testing.assert_array_equal(log.imu.linear_acceleration, _imu_rows(8)[:, 3:6])


def test_default_joint_names_name_the_port(tmp_path: Path) -> None:
    log = read_robot_source(_robot(tmp_path / "log"), joint_topic=RIGHT_LEG)
    assert log.joints.names == (f"{RIGHT_LEG}[0]", f"{RIGHT_LEG}[1]", f"{RIGHT_LEG}[2]")
    assert log.imu is None


def test_joint_ports_on_two_clocks_join_on_the_first(tmp_path: Path) -> None:
    root = tmp_path / "log"
    _feet(root, 12)
    left, right = _legs(12)
    write_dump(root / "l", LEFT_LEG, [_fmt(r) for r in left[:10]], _stamps(10, 0.015))
    write_dump(root / "r", RIGHT_LEG, [_fmt(r) for r in right], _stamps(12))
    log = read_robot_source(root, joint_topic=[LEFT_LEG, RIGHT_LEG])
    np.testing.assert_allclose(log.joints.time, _stamps(10, 0.015) - T0, atol=1e-9)
    np.testing.assert_array_equal(log.joints.position[:, :3], left[:10])
    # the right leg interpolated at the left leg's stamps (about k + 1.5 samples)
    t_left, t_right = _stamps(10, 0.015) - T0, _stamps(12) - T0
    expected = np.column_stack([np.interp(t_left, t_right, col) for col in right.T])
    np.testing.assert_allclose(log.joints.position[:, 3:], expected, rtol=0, atol=1e-9)
    np.testing.assert_allclose(expected[0], right[0] + 1.5 * (right[1] - right[0]), atol=1e-4)


def test_multipleanalogsensors_bottle_round_trip(tmp_path: Path) -> None:
    root = tmp_path / "log"
    _feet(root, 6)
    rows = _imu_rows(6)
    stamps = _stamps(6)
    bodies = [
        _mas_body(r[6:9], r[3:6], r[:3], float(t) - 0.001)
        for r, t in zip(rows, stamps, strict=True)
    ]
    write_dump(
        root / "icub" / "head" / "inertials" / "measures_o",
        "/icub/head/inertials/measures:o",
        bodies,
        stamps,
    )
    log = read_robot_source(root, imu_topic="/icub/head/inertials/measures:o")
    np.testing.assert_array_equal(log.imu.angular_velocity, rows[:, 6:9])
    np.testing.assert_array_equal(log.imu.linear_acceleration, rows[:, 3:6])
    expected = Rotation.from_euler("xyz", rows[:, :3], degrees=True).as_quat()
    np.testing.assert_allclose(log.imu.orientation_xyzw, expected, atol=1e-12)
    np.testing.assert_array_equal(log.imu.time, log.ft.time)


def test_multipleanalogsensors_without_orientation_and_second_sensor(tmp_path: Path) -> None:
    stamps = _stamps(3)
    a, b = np.array([1.0, 2.0, 3.0]), np.array([4.0, 5.0, 6.0])
    two = f"((({_fmt(a)}) 1.0) (({_fmt(b)}) 1.0))"
    body = " ".join([two, two, "()", "()"] + ["()"] * 8)  # 12 groups, no orientation
    folder = write_dump(tmp_path / "imu", "/x/measures:o", [body] * 3, stamps)
    imu = read_yarp_imu(folder, sensor=1)
    assert imu.orientation_xyzw is None
    np.testing.assert_array_equal(imu.angular_velocity, np.tile(b, (3, 1)))
    with pytest.raises(InputFileError, match=r"data.log, line 1: ThreeAxisGyroscopes has 2 sens"):
        read_yarp_imu(folder, sensor=2)


def test_resample_puts_joints_and_imu_on_the_ft_clock(tmp_path: Path) -> None:
    log = _read(_robot(tmp_path / "log"))
    inside = log.ft.time[(log.ft.time >= log.imu.time[0]) & (log.ft.time <= log.imu.time[-1])]
    on_ft = resample(log, time=inside)
    assert on_ft.imu.time is on_ft.joints.time or np.array_equal(on_ft.imu.time, inside)
    np.testing.assert_array_equal(on_ft.joints.time, inside)
    assert on_ft.imu.angular_velocity.shape == (inside.size, 3)


# --- errors ---------------------------------------------------------------------------------


def test_missing_port_folder_lists_the_dumps_present(tmp_path: Path) -> None:
    root = _robot(tmp_path / "log")
    with pytest.raises(InputFileError, match=r"no dump of port '/teo/trunk/state:o' found; dumps "):
        read_robot_source(root, joint_topic="/teo/trunk/state:o")
    with pytest.raises(InputFileError, match=r"no dump of port '/imu' found; .*teo/imu_o \(/teo/"):
        read_robot_source(root, imu_topic="/imu")


def _corrupt(root: Path, folder: str, line: str, *, replace_last: bool = False) -> None:
    data = root / folder / "data.log"
    lines = data.read_text().splitlines()
    lines = [*lines[:-1], line] if replace_last else [*lines, line]
    data.write_text("\n".join(lines) + "\n")


@pytest.mark.parametrize(
    ("folder", "line", "message"),
    [
        ("teo/leftLeg/state_o", "8 1712345678.4 1 2", r"state_o/data.log, line 9: 2 values, but"),
        ("teo/leftLeg/state_o", "8 1712345678.3 1 2 3", r"line 9: stamps must be strictly incr"),
        ("teo/leftLeg/state_o", "8 1712345678.4 1 nan 3", r"line 9: value 2: expected a finite"),
        ("teo/imu_o", "8 1712345678.4 1 2 3 4 5 6 7 8 9 1 2 (3", r"imu_o/data.log, line 9: unbal"),
        ("teo/imu_o", "8 1712345678.4 1 2 3 4 5 6 7 8 9 1 2 3e", r"line 9: value 12: expected a n"),
    ],
)
def test_bad_joint_or_imu_line_names_file_and_line(
    tmp_path: Path, folder: str, line: str, message: str
) -> None:
    root = _robot(tmp_path / "log")
    _corrupt(root, folder, line)
    with pytest.raises(InputFileError, match=message):
        _read(root)


def test_truncated_last_line_names_its_line(tmp_path: Path) -> None:
    root = _robot(tmp_path / "log")
    full = (root / "teo/imu_o/data.log").read_text().splitlines()[-1]
    _corrupt(root, "teo/imu_o", full[: len(full) // 2], replace_last=True)
    with pytest.raises(
        InputFileError, match=r"imu_o/data.log, line 8: \d+ values, but line 1 has 12"
    ):
        _read(root)


def test_imu_port_of_another_width_says_what_is_expected(tmp_path: Path) -> None:
    root = _robot(tmp_path / "log")
    with pytest.raises(
        InputFileError, match=r"state_o/data.log, line 1: expected an IMU port: 12 "
    ):
        read_robot_source(root, imu_topic=LEFT_LEG)


def test_multipleanalogsensors_errors_name_the_group(tmp_path: Path) -> None:
    bad = " ".join(["(((1 2) 1.0))", "(((1 2 3) 1.0))", "()", "()"] + ["()"] * 6)
    folder = write_dump(tmp_path / "a", "/a", [bad] * 2, _stamps(2))
    with pytest.raises(
        InputFileError,
        match=r"line 1: ThreeAxisGyroscopes sensor 0: expected '\(\(x y z\) timest.*list of 2",
    ):
        read_yarp_imu(folder)
    good = " ".join(["(((1 2 3) 1.0))", "(((1 2 3) 1.0))", "()", "()"] + ["()"] * 6)
    other = good.replace("(((1 2 3) 1.0))", "(((1 2 3 4) 1.0))", 1)
    folder = write_dump(tmp_path / "b", "/b", [good, other], _stamps(2))
    with pytest.raises(InputFileError, match=r"line 2: 9 values, but line 1 has 8"):
        read_yarp_imu(folder)
    shifted = good.replace("(((1 2 3) 1.0))", "((1 2 3 1.0))", 1)
    folder = write_dump(tmp_path / "c", "/c", [good, shifted], _stamps(2))
    with pytest.raises(
        InputFileError, match=r"line 2: the bottle nests as .* expected the same nest"
    ):
        read_yarp_imu(folder)


def test_joint_name_errors(tmp_path: Path) -> None:
    root = _robot(tmp_path / "log")
    with pytest.raises(
        InputFileError,
        match=r"log: 2 joint names were given, but the joint ports carry 6 values per line \(.*",
    ):
        _read(root, joint_names=("a", "b"))
    with pytest.raises(ParameterError, match="joint name 'a' is given twice"):
        _read(root, joint_names=("a", "a", "b", "c", "d", "e"))
    with pytest.raises(ParameterError, match="joint port '/teo/leftLeg/state:o' is given twice"):
        read_robot_source(root, joint_topic=[LEFT_LEG, LEFT_LEG])
    with pytest.raises(ParameterError, match="joint_names needs joint ports"):
        read_robot_source(root, joint_names=NAMES)


def test_joint_ports_that_never_overlap(tmp_path: Path) -> None:
    root = tmp_path / "log"
    _feet(root, 4)
    write_dump(root / "l", LEFT_LEG, ["1 2 3"] * 4, _stamps(4))
    write_dump(root / "r", RIGHT_LEG, ["1 2 3"] * 4, _stamps(4, 10.0))
    with pytest.raises(InputFileError, match=r"the joint ports do not overlap in time: /teo/left"):
        read_robot_source(root, joint_topic=[LEFT_LEG, RIGHT_LEG])


def test_options_that_do_not_apply(tmp_path: Path) -> None:
    both = tmp_path / "data.log"
    both.write_text("0 1.0 " + " ".join(["1"] * 12) + "\n1 1.1 " + " ".join(["2"] * 12) + "\n")
    with pytest.raises(
        ParameterError, match=r"data.log is a single dump; joint and IMU ports need"
    ):
        read_robot_source(both, joint_topic=LEFT_LEG)
    csv = tmp_path / "log.csv"
    csv.write_text("time\n0\n")
    with pytest.raises(ParameterError, match="joint_names applies to YARP dumps, not to csv"):
        read_robot_source(csv, joint_names=NAMES)
    with pytest.raises(ParameterError, match="joint_topic applies to ROS 2 bags and YARP dumps"):
        read_robot_source(csv, joint_topic=LEFT_LEG)
    assert read_ft_source(both).time.size == 2
    bag = tmp_path / "bag"
    bag.mkdir()
    (bag / "metadata.yaml").write_text("{}\n")
    with pytest.raises(ParameterError, match="a ROS 2 bag takes one JointState topic"):
        read_robot_source(bag, joint_topic=[LEFT_LEG, RIGHT_LEG])
    with pytest.raises(ParameterError, match="JointState messages name their joints"):
        read_robot_source(bag, joint_topic="/joint_states", joint_names=NAMES)


# --- garbage --------------------------------------------------------------------------------

_ATOMS = st.sampled_from(["(", ")", "1", "-2.5", "1e3", "nan", "inf", "x", "", " ", "\t", "()"])
_LINES = st.lists(
    st.text(alphabet=st.characters(), max_size=30) | st.lists(_ATOMS, max_size=40).map(" ".join),
    max_size=6,
)


@settings(
    max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(body=_LINES, imu=st.booleans())
def test_garbage_joint_or_imu_dump_is_read_or_named(
    tmp_path_factory: pytest.TempPathFactory, body: list[str], imu: bool
) -> None:
    root = tmp_path_factory.mktemp("garbage")
    _feet(root, 4)
    folder = root / "port"
    folder.mkdir()
    (folder / "info.log").write_text(f"Type: Bottle;\n[0.0] {IMU} [connected]\n")
    lines = [f"{k} {T0 + k * DT!r} {b}" for k, b in enumerate(body)]
    (folder / "data.log").write_text("\n".join(lines), encoding="utf-8", errors="surrogatepass")
    option = {"imu_topic": IMU} if imu else {"joint_topic": IMU}
    try:
        log = read_robot_source(root, **option)  # type: ignore[arg-type]
    except InputFileError as exc:
        message = str(exc)
    else:
        message = ""
    if message:
        assert message.startswith(str(root))  # one line naming the file
        assert "\n" not in message
        return
    stream = log.imu if imu else log.joints
    assert stream is not None
    assert 1 <= stream.time.size <= len(body)
    assert np.all(np.diff(stream.time) > 0)
