"""Reading logs and configuration files; writing results."""

from zmpkit.io.feet import FOOT_NAMES, feet_from_mapping, read_feet_yaml
from zmpkit.io.ft_log import (
    FT_LOG_COLUMNS,
    WRENCH_AXES,
    FtLog,
    read_column_map,
    read_ft_log_csv,
)
from zmpkit.io.zmp_csv import ZMP_CSV_COLUMNS, write_zmp_csv

__all__ = [
    "FOOT_NAMES",
    "FT_LOG_COLUMNS",
    "WRENCH_AXES",
    "ZMP_CSV_COLUMNS",
    "FtLog",
    "feet_from_mapping",
    "read_column_map",
    "read_feet_yaml",
    "read_ft_log_csv",
    "write_zmp_csv",
]
