"""A step manifest: a real robot's recorded ZMP-step experiments, as step trials.

A robot's logs hold wrenches, not what the experimenter commanded, so a manifest says it::

    plane: sagittal                 # or frontal
    feet: feet.yaml                 # FEET.yaml path (relative to the manifest), or a mapping
    mass_kg: 62.6                   # pendulum the controller believes [kg]
    length_m: 0.777                 # pendulum length, ankle pivot to CoM [m]
    startup_window_s: 0.5           # quiet standing before each step, for the ZMP offset [s]
    contact_threshold_n: 10         # optional: a foot is in contact above this F_z [N];
                                    # a light robot's is lower (zmpkit's: 5 % of the weight)
    units: units.yaml               # optional, as for ``zmpkit zmp --units``
    trials:
      - {log: step_020.db3, target_m: 0.02, t_step_s: 3.5,
         right_topic: /jr3/ch0, left_topic: /jr3/ch1}
      - {log: step_040.csv, target_m: 0.04, t_step_s: 3.5}

``log`` is anything :func:`~zmpkit.io.read_ft_source` reads (CSV, Parquet, a ROS 2 bag, a YARP
dump folder); paths are relative to the manifest. Each trial becomes a
:class:`~zmpkit.signals.StepTrial` whose measured ZMP is that of both feet in the world frame
(``zmpkit.sensors``), minus its mean over the start-up window, in the manifest's plane.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from zmpkit.errors import InputFileError, ParameterError
from zmpkit.io.feet import feet_from_mapping, read_feet_yaml
from zmpkit.io.ft_source import read_ft_source
from zmpkit.io.yaml_file import read_yaml_mapping, require_number
from zmpkit.sensors import (
    CONTACT_FORCE_THRESHOLD_N,
    SensorMount,
    contact_threshold,
    remove_zmp_offset,
    zmp_offset_from_standing_window,
)
from zmpkit.signals import PLANES, StepTrial

__all__ = ["StepManifest", "read_step_manifest"]

_TRIAL_FIELDS = ("log", "target_m", "t_step_s", "right_topic", "left_topic")


@dataclass(frozen=True, eq=False)
class StepManifest:
    """The manifest's trials and the pendulum the controller believes.

    Attributes:
        trials: one step trial per listed log (time from the step, measured ZMP [m]).
        mass_kg: pendulum mass [kg].
        length_m: pendulum length, ankle pivot to CoM [m].
        plane: ``"sagittal"`` or ``"frontal"``.
    """

    trials: tuple[StepTrial, ...]
    mass_kg: float
    length_m: float
    plane: str


def read_step_manifest(path: str | Path) -> StepManifest:
    """Read a step manifest and every log it lists.

    Raises:
        InputFileError: a missing or malformed field (named), or a log that cannot be read.
    """
    path = Path(path)
    doc = read_yaml_mapping(path)
    plane = doc.get("plane", "sagittal")
    if plane not in PLANES:
        raise InputFileError(path, f"field 'plane' must be one of {', '.join(PLANES)}")
    mounts = _mounts(path, doc.get("feet"))
    window = require_number(path, "startup_window_s", doc.get("startup_window_s", 0.5))
    threshold = _threshold(path, doc.get("contact_threshold_n", CONTACT_FORCE_THRESHOLD_N))
    units = _relative(path, doc["units"]) if "units" in doc else None
    entries = doc.get("trials")
    if not isinstance(entries, list) or not entries:
        raise InputFileError(path, "field 'trials' must be a non-empty list of trials")
    trials = tuple(
        _trial(path, k, entry, mounts, plane, window, units, threshold)
        for k, entry in enumerate(entries)
    )
    return StepManifest(
        trials=trials,
        mass_kg=require_number(path, "mass_kg", _required(path, doc, "mass_kg")),
        length_m=require_number(path, "length_m", _required(path, doc, "length_m")),
        plane=plane,
    )


def _threshold(manifest: Path, value: object) -> float:
    number = require_number(manifest, "contact_threshold_n", value)
    try:
        return contact_threshold(number)
    except ParameterError as exc:
        raise InputFileError(manifest, str(exc)) from None


def _required(path: Path, doc: Mapping[str, Any], key: str) -> Any:
    if key not in doc:
        raise InputFileError(path, f"missing field '{key}'")
    return doc[key]


def _relative(manifest: Path, value: object) -> Path:
    if not isinstance(value, str):
        raise InputFileError(manifest, f"expected a file path, got {value!r}")
    return manifest.parent / value


def _mounts(manifest: Path, feet: object) -> dict[str, SensorMount]:
    if isinstance(feet, Mapping):
        return feet_from_mapping(feet, source=manifest)
    if feet is None:
        raise InputFileError(manifest, "missing field 'feet' (a FEET.yaml path or a mapping)")
    return read_feet_yaml(_relative(manifest, feet))


def _trial(
    manifest: Path,
    index: int,
    entry: object,
    mounts: Mapping[str, SensorMount],
    plane: str,
    window_s: float,
    units: Path | None,
    contact_threshold_n: float,
) -> StepTrial:
    field = f"trials[{index}]"
    if not isinstance(entry, Mapping) or "log" not in entry:
        raise InputFileError(manifest, f"{field} must be a mapping with at least 'log'")
    unknown = sorted(set(entry) - set(_TRIAL_FIELDS))
    if unknown:
        valid = ", ".join(_TRIAL_FIELDS)
        raise InputFileError(manifest, f"{field} has unknown field '{unknown[0]}'; valid: {valid}")
    target = require_number(manifest, f"{field}.target_m", entry.get("target_m"))
    t_step = require_number(manifest, f"{field}.t_step_s", entry.get("t_step_s"))
    log = read_ft_source(
        _relative(manifest, entry["log"]),
        right_topic=entry.get("right_topic"),
        left_topic=entry.get("left_topic"),
        units=units,
    )
    series = log.zmp_series(mounts, contact_threshold_n)
    offset = zmp_offset_from_standing_window(series, None, (t_step - window_s, t_step))
    zmp = remove_zmp_offset(series, offset).zmp[:, 0 if plane == "sagittal" else 1]
    return StepTrial(
        time=log.time - t_step,
        zmp_measured=zmp,
        zmp_ref=target,
        t_step=0.0,
        plane=plane,
        zmp_commanded=target,
    )
