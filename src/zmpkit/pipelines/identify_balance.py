"""``zmpkit identify balance``: identify the DLIPM error model from recorded steps.

Reads either a dataset folder of LIPM step trials (one plane; written by ``zmpkit sim push``)
or a step manifest (``.yaml``, :mod:`zmpkit.io.step_manifest`) listing a real robot's logs —
CSV, Parquet, ROS 2 bags, YARP dumps — with each step's target and time; fits the
steady-state error model and the transients on every trial (:func:`run_identify_balance`,
which writes nothing); :func:`~zmpkit.pipelines.identify_balance_files.write_identify_balance`
writes ``params.yaml``, ``fig16_<plane>.png`` and the report.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

from zmpkit._validate import shorten
from zmpkit.errors import InputFileError, ParameterError, ZmpkitError
from zmpkit.experiments import dataset_trials, read_step_dataset
from zmpkit.identify import BalanceIdentification, identify_balance
from zmpkit.io.step_manifest import read_step_manifest
from zmpkit.robots.registry import get_robot
from zmpkit.signals import StepTrial

__all__ = ["IdentifyBalanceResult", "run_identify_balance"]


@dataclass(frozen=True, eq=False)
class IdentifyBalanceResult:
    """An identification from recorded steps.

    Attributes:
        identification: the error model, transients and parameters.
        source: the dataset folder or manifest it read.
        plane: the plane of the recorded steps.
        lean_length_m: the pendulum length, ankle to CoM [m].
        started_s: when the run started [s since the epoch].
        files: the files written by role (``params``, ``figure``, ``report``; empty until
            :func:`~zmpkit.pipelines.identify_balance_files.write_identify_balance`).
    """

    identification: BalanceIdentification
    source: Path
    plane: str = "sagittal"
    lean_length_m: float = 0.0
    started_s: float = field(default_factory=time.time)
    files: dict[str, Path] = field(default_factory=dict)


def run_identify_balance(
    dataset_dir: str | Path,
    *,
    mass_kg: float | None = None,
    length_m: float | None = None,
    robot: str | None = None,
) -> IdentifyBalanceResult:
    """Identify the error model and transients from ``dataset_dir``; nothing is written.

    Args:
        dataset_dir: a step dataset folder (``meta.json`` + one CSV per trial), or a step
            manifest ``.yaml`` listing a real robot's recorded logs.
        mass_kg: pendulum mass [kg]; default: the manifest's, or the robot's design mass
            (its balance model's mass, e.g. paper A's 62.6 kg).
        length_m: pendulum length, ankle to CoM [m]; default: the manifest's, or the
            dataset's design lean length.
        robot: a step dataset's robot (registry name or ``robot.yaml``), whose design mass
            is the default pendulum mass, instead of the one its ``meta.json`` records;
            None: that one. A manifest gives its own ``mass_kg``.

    Raises:
        ParameterError: ``robot`` given with a manifest, or one without a balance model.
    """
    started_s = time.time()
    trials, plane, mass, length = _recorded_steps(Path(dataset_dir), mass_kg, length_m, robot)
    identification = identify_balance(trials, mass=mass, com_height=length)
    return IdentifyBalanceResult(identification, Path(dataset_dir), plane, length, started_s)


def _recorded_steps(
    source: Path, mass_kg: float | None, length_m: float | None, robot: str | None = None
) -> tuple[list[StepTrial], str, float, float]:
    """The trials, plane and pendulum (mass [kg], length [m]) of a dataset or a manifest."""
    mass: float | None
    length: float | None
    if source.suffix in (".yaml", ".yml"):
        if robot is not None:
            raise ParameterError(
                "--robot names a step dataset's robot; a manifest gives its pendulum "
                "(mass_kg, length_m; --mass and --length replace them)"
            )
        manifest = read_step_manifest(source)
        mass = manifest.mass_kg if mass_kg is None else mass_kg
        length = manifest.length_m if length_m is None else length_m
        return list(manifest.trials), manifest.plane, mass, length
    dataset = read_step_dataset(source)
    meta_path = source / "meta.json"
    recorded = dataset.meta.get("robot")
    design = get_robot(robot, needs="balance").require_balance().mass_kg if robot else None
    mass = mass_kg if mass_kg is not None else design or _design_mass(recorded)
    if mass is None:
        raise InputFileError(
            meta_path,
            f"unknown robot {shorten(recorded)}: name it with --robot NAME|PATH/robot.yaml, "
            "or give the pendulum mass with --mass KG",
        )
    length = length_m if length_m is not None else dataset.meta.get("lean_length_m")
    if length is None:
        raise InputFileError(meta_path, "no 'lean_length_m': give the pendulum with --length M")
    return dataset_trials(dataset), dataset.plane, float(mass), float(length)


def _design_mass(robot: object) -> float | None:
    """The balance model's mass [kg] of the dataset's robot, or None if it has none."""
    try:
        balance = get_robot(str(robot)).balance
    except ZmpkitError:
        return None
    return None if balance is None else balance.mass_kg
