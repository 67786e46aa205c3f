"""``zmpkit identify balance``: identify the DLIPM error model from recorded steps.

Reads either a dataset folder of LIPM step trials (one plane; written by ``zmpkit sim push``)
or a step manifest (``.yaml``, :mod:`zmpkit.io.step_manifest`) listing a real robot's logs —
CSV, Parquet, ROS 2 bags, YARP dumps — with each step's target and time; fits the
steady-state error model and the transients on every trial, and writes ``params.yaml``,
``fig16_<plane>.png`` and the report (:func:`identification_document`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from zmpkit._validate import shorten
from zmpkit.analysis.balance_plots import plot_error_fit
from zmpkit.analysis.provenance import capture_described
from zmpkit.analysis.report_document import Check, Figure, ReportDocument, Section, Text
from zmpkit.analysis.report_files import write_report
from zmpkit.errors import InputFileError, ParameterError, ZmpkitError
from zmpkit.experiments import dataset_trials, read_step_dataset
from zmpkit.identify import BalanceIdentification, identify_balance
from zmpkit.io.step_manifest import read_step_manifest
from zmpkit.pipelines.balance_sections import identification_blocks
from zmpkit.robots.registry import get_robot
from zmpkit.signals import StepTrial

__all__ = ["IdentifyBalanceResult", "identification_document", "run_identify_balance"]


@dataclass(frozen=True, eq=False)
class IdentifyBalanceResult:
    """The identification and the files written."""

    identification: BalanceIdentification
    params_path: Path
    figure_path: Path
    summary_path: Path
    plane: str = "sagittal"
    lean_length_m: float = 0.0


def run_identify_balance(
    dataset_dir: str | Path,
    out_dir: str | Path,
    *,
    mass_kg: float | None = None,
    length_m: float | None = None,
    report_format: str = "html",
    robot: str | None = None,
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
        report_format: ``html`` (``report.html``), ``md`` (``report.md``) or ``both``.
        robot: a step dataset's robot (registry name or ``robot.yaml``), whose design mass
            is the default pendulum mass, instead of the one its ``meta.json`` records;
            None: that one. A manifest gives its own ``mass_kg``.

    Raises:
        ParameterError: ``robot`` given with a manifest, or one without a balance model.
    """
    started_s = time.time()
    trials, plane, mass, length = _recorded_steps(Path(dataset_dir), mass_kg, length_m, robot)
    identification = identify_balance(trials, mass=mass, com_height=length)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    figure = plot_error_fit(
        identification.planes[plane], (), out / f"fig16_{plane}.png", plane=plane
    )
    params = identification.params.to_yaml(out / "params.yaml")
    result = IdentifyBalanceResult(identification, params, figure, figure, plane, length)
    doc = identification_document(result, Path(dataset_dir), started_s)
    return replace(result, summary_path=write_report(doc, out, report_format))


def identification_document(
    result: IdentifyBalanceResult, source: Path, started_s: float
) -> ReportDocument:
    """The report of an identification: the error model, its residuals, the transients."""
    ident = result.identification.planes[result.plane]
    fit = ident.error_fit
    residual_mm = 1e3 * float(np.max(np.abs(fit.residuals), initial=0.0))
    p = ident.params
    checks = (
        Check(
            "steady-state error model (no bar)",
            "info",
            f"{fit.kind}, largest fit residual {residual_mm:.2f} mm over {len(fit.x_cmd)} trials",
        ),
        Check(
            "transient (no bar)",
            "info" if p.zeta is not None else "undefined",
            f"ζ = {p.zeta:.3f}, ω_n = {p.omega_n:.2f} rad/s"
            if p.zeta is not None and p.omega_n is not None
            else "no trial's transient could be fitted",
        ),
        Check(
            "every trial used",
            "met" if not ident.excluded else "missed",
            "; ".join(ident.excluded) or f"all {len(ident.trials)} trials settled",
        ),
    )
    figure = Figure(
        result.figure_path,
        f"The settled force–torque ZMP [m] of each step against the commanded ZMP [m], with "
        f"the fitted error model and its 95 % band ({result.plane}; paper A Fig. 16).",
    )
    return ReportDocument(
        title=f"zmpkit identify balance: the DLIPM's error model from {source.name}",
        summary=(
            f"Steady-state error model (paper A eq. 13) and transients of the {result.plane} "
            f"steps recorded in `{source}`, chosen by leave-one-out cross-validation."
        ),
        checks=checks,
        sections=(
            Section(
                "Identification",
                (*identification_blocks(ident, result.plane, result.lean_length_m), figure),
            ),
            Section("Data", (Text("`params.yaml`: the identified DLIPM parameters."),)),
        ),
        provenance=capture_described(
            robot="recorded data",
            started_s=started_s,
            extra=(("data", str(source)),),
        ),
    )


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
