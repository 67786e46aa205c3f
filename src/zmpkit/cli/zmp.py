"""``zmpkit zmp``: the ZMP of a recorded force-torque log."""

from __future__ import annotations

from pathlib import Path

import click

from zmpkit.cli.options import Bounded, log_source_options, report_option
from zmpkit.cli.robot_option import robot_option
from zmpkit.io import feet_from_mapping
from zmpkit.pipelines.zmp_log import run_zmp_log
from zmpkit.pipelines.zmp_log_files import write_zmp_log
from zmpkit.robots.registry import get_robot
from zmpkit.sensors import CONTACT_FORCE_THRESHOLD_N, CONTACT_THRESHOLD_RANGE_N, SensorMount

__all__ = ["zmp_command"]


@click.command("zmp")
@click.argument("log", type=click.Path(path_type=Path))
@click.option("--right-topic", help="ROS 2 bag: WrenchStamped topic of the right foot.")
@click.option("--left-topic", help="ROS 2 bag: WrenchStamped topic of the left foot.")
@log_source_options
@click.option(
    "--feet",
    "feet_path",
    type=click.Path(path_type=Path),
    help="FEET.yaml: each foot's sensor position [m], rpy [rad] and sole_height [m].",
)
@robot_option(None, help_text="Use a robot's sensor mounts instead of --feet")
@click.option(
    "--columns",
    "columns_path",
    type=click.Path(path_type=Path),
    help="Column-map YAML {canonical_name: header_in_file} for logs with other headers.",
)
@click.option(
    "--contact-threshold",
    type=Bounded(*CONTACT_THRESHOLD_RANGE_N, "N"),
    default=None,
    help="Minimum normal force for a foot to be in contact [N] (default 10; "
    f"{CONTACT_THRESHOLD_RANGE_N[0]:g} to {CONTACT_THRESHOLD_RANGE_N[1]:g}).",
)
@click.option(
    "--out", "out_dir", type=click.Path(path_type=Path), required=True, help="Output folder."
)
@report_option
def zmp_command(
    log: Path,
    right_topic: str | None,
    left_topic: str | None,
    units_path: Path | None,
    time_source: str,
    feet_path: Path | None,
    robot: str | None,
    columns_path: Path | None,
    contact_threshold: float | None,
    out_dir: Path,
    report_format: str,
) -> None:
    """ZMP of a recorded force-torque LOG; writes zmp.csv and zmp.png.

    LOG is a CSV, Parquet, ROS 2 bag (folder, .db3, .mcap) or YARP dump folder.
    """
    if (feet_path is None) == (robot is None):
        raise click.UsageError("give exactly one of --feet FEET.yaml or --robot ROBOT")
    feet = _robot_feet(robot) if robot is not None else None
    default_threshold = (
        CONTACT_FORCE_THRESHOLD_N if robot is None else get_robot(robot).contact_force_threshold_n
    )
    threshold = default_threshold if contact_threshold is None else contact_threshold
    result = run_zmp_log(
        log,
        feet=feet,
        feet_path=feet_path,
        feet_source=f"robot {robot}" if robot is not None else f"{feet_path}",
        columns_path=columns_path,
        contact_threshold_n=threshold,
        right_topic=right_topic,
        left_topic=left_topic,
        units_path=units_path,
        time_source=time_source,
    )
    result = write_zmp_log(result, out_dir, report_format)
    s = result.series
    click.echo(
        f"{len(s.time)} samples, ZMP defined on {len(s.time) - s.n_undefined}; "
        f"wrote {result.files['csv']} and {result.files['figure']}"
    )
    click.echo(f"report: {result.files['report']}")


def _robot_feet(robot: str) -> dict[str, SensorMount]:
    """The foot sensor mounts of the robot named ``robot`` (or its ``robot.yaml``)."""
    chosen = get_robot(robot)
    return feet_from_mapping(chosen.feet_mounts(), source=f"robot {chosen.name!r}")
