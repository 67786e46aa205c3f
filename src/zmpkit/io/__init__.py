"""Reading logs and configuration files; writing results."""

from zmpkit.io.feet import FOOT_NAMES, feet_from_mapping, read_feet_yaml
from zmpkit.io.ft_log import (
    FT_LOG_COLUMNS,
    MAX_PLAUSIBLE_FORCE_N,
    MAX_PLAUSIBLE_MOMENT_NM,
    WRENCH_AXES,
    FtLog,
    check_plausible,
    read_column_map,
    read_ft_log_csv,
)
from zmpkit.io.ft_parquet import read_ft_log_parquet
from zmpkit.io.ft_source import SOURCE_KINDS, detect_source_kind, read_ft_source, read_robot_source
from zmpkit.io.log_units import FootUnits, LogUnits, read_log_units
from zmpkit.io.resample import DEFAULT_MAX_GAP_PERIODS, merge_feet, resample
from zmpkit.io.robot_log import ImuLog, JointLog, RobotLog
from zmpkit.io.rosbag import TIME_SOURCES, list_bag_topics, read_ros2_bag
from zmpkit.io.yarp import (
    JR3_LEFT_FOOT_PORT,
    JR3_RIGHT_FOOT_PORT,
    find_yarp_dumps,
    read_yarp_ft,
    read_yarp_joints,
    read_yarp_robot,
)
from zmpkit.io.yarp_datalog import YarpDump, read_yarp_dump
from zmpkit.io.yarp_imu import read_yarp_imu
from zmpkit.io.zmp_csv import ZMP_CSV_COLUMNS, check_zmp_finite, write_zmp_csv

__all__ = [
    "DEFAULT_MAX_GAP_PERIODS",
    "FOOT_NAMES",
    "FT_LOG_COLUMNS",
    "JR3_LEFT_FOOT_PORT",
    "JR3_RIGHT_FOOT_PORT",
    "MAX_PLAUSIBLE_FORCE_N",
    "MAX_PLAUSIBLE_MOMENT_NM",
    "SOURCE_KINDS",
    "TIME_SOURCES",
    "WRENCH_AXES",
    "ZMP_CSV_COLUMNS",
    "FootUnits",
    "FtLog",
    "ImuLog",
    "JointLog",
    "LogUnits",
    "RobotLog",
    "YarpDump",
    "check_plausible",
    "check_zmp_finite",
    "detect_source_kind",
    "feet_from_mapping",
    "find_yarp_dumps",
    "list_bag_topics",
    "merge_feet",
    "read_column_map",
    "read_feet_yaml",
    "read_ft_log_csv",
    "read_ft_log_parquet",
    "read_ft_source",
    "read_log_units",
    "read_robot_source",
    "read_ros2_bag",
    "read_yarp_dump",
    "read_yarp_ft",
    "read_yarp_imu",
    "read_yarp_joints",
    "read_yarp_robot",
    "resample",
    "write_zmp_csv",
]
