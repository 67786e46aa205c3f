"""``zmpkit identify balance``: identify the DLIPM error model from recorded steps.

Reads either a dataset folder of LIPM step trials (one plane; written by ``zmpkit sim push``)
or a step manifest (``.yaml``, :mod:`zmpkit.io.step_manifest`) listing a real robot's logs —
CSV, Parquet, ROS 2 bags, YARP dumps — with each step's target and time; fits the
steady-state error model and the transients on every trial, and writes ``params.yaml``,
``fig16_<plane>.png`` and
``identification.md``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from zmpkit.analysis.balance_plots import plot_error_fit
from zmpkit.errors import InputFileError, ZmpkitError
from zmpkit.experiments import read_step_dataset
from zmpkit.identify import BalanceIdentification, identify_balance
from zmpkit.io.step_manifest import read_step_manifest
from zmpkit.pipelines.balance import dataset_trials
from zmpkit.robots.registry import get_robot
from zmpkit.signals import StepTrial

__all__ = ["IdentifyBalanceResult", "run_identify_balance"]


@dataclass(frozen=True, eq=False)
class IdentifyBalanceResult:
    """The identification and the files written."""

    identification: BalanceIdentification
    params_path: Path
    figure_path: Path
    summary_path: Path


def run_identify_balance(
    dataset_dir: str | Path,
    out_dir: str | Path,
    *,
    mass_kg: float | None = None,
    length_m: float | None = None,
) -> IdentifyBalanceResult:
    """Identify from ``dataset_dir`` and write the results into ``out_dir``.

    Args:
        dataset_dir: a step dataset folder (``meta.json`` + one CSV per trial), or a step
            manifest ``.yaml`` listing a real robot's recorded logs.
        out_dir: output folder, created if missing.
        mass_kg: pendulum mass [kg]; default: the manifest's, or the robot's design mass
            (its balance model's mass, e.g. paper A's 62.6 kg).
        length_m: pendulum length, ankle to CoM [m]; default: the manifest's, or the
            dataset's design lean length.
    """
    trials, plane, mass, length = _recorded_steps(Path(dataset_dir), mass_kg, length_m)
    identification = identify_balance(trials, mass=mass, com_height=length)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    fit = identification.planes[plane].error_fit
    figure = plot_error_fit(
        fit.x_cmd,
        fit.x_measured,
        [True] * len(fit.x_cmd),
        fit,
        out / f"fig16_{plane}.png",
        plane=plane,
    )
    params = identification.params.to_yaml(out / "params.yaml")
    summary = out / "identification.md"
    summary.write_text(
        f"# Identification of {dataset_dir}\n\nPlane {plane}; {fit.reason}.\n\n"
        f"{fit.model.equation} with coefficients {dict(fit.model.as_dict())}, "
        f"R² = {fit.r_squared:.5f}.\n\n![fig16]({figure.name})\n",
        encoding="utf-8",
    )
    return IdentifyBalanceResult(identification, params, figure, summary)


def _recorded_steps(
    source: Path, mass_kg: float | None, length_m: float | None
) -> tuple[list[StepTrial], str, float, float]:
    """The trials, plane and pendulum (mass [kg], length [m]) of a dataset or a manifest."""
    mass: float | None
    length: float | None
    if source.suffix in (".yaml", ".yml"):
        manifest = read_step_manifest(source)
        mass = manifest.mass_kg if mass_kg is None else mass_kg
        length = manifest.length_m if length_m is None else length_m
        return list(manifest.trials), manifest.plane, mass, length
    dataset = read_step_dataset(source)
    meta_path = source / "meta.json"
    mass = mass_kg if mass_kg is not None else _design_mass(dataset.meta.get("robot"))
    if mass is None:
        raise InputFileError(meta_path, "unknown robot: give the pendulum mass with --mass KG")
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
