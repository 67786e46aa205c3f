r"""Do two simulator fits agree? Each parameter's difference against the fits' resolutions.

Two fits of the same robot and parameters (another backend, e.g. MuJoCo Warp's float32 on
a GPU against the CPU's float64; another seed, another day's data) agree on a parameter
when their values differ by no more than the larger of their *resolutions*: the relative
step from the optimum at which the fit's cost rises visibly with every other parameter
free to compensate (the *marginal* resolution, :mod:`~zmpkit.simfit.identifiability`; the
profile's, the others held, for a fit written before it was recorded), the width within
which the data cannot tell values apart:

.. math:: \delta = \frac{\theta_B - \theta_A}{|\theta_A|}, \qquad
          \text{agree} \iff |\delta| \le \max(r_A, r_B).

A parameter either fit flags as not identifiable is reported but not judged (the data do
not pin it down, so any two values agree). Reads each fit's ``fitted_parameters.yaml``
(:func:`~zmpkit.simfit.outputs.write_fitted_parameters`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from zmpkit.errors import InputFileError
from zmpkit.io.yaml_file import read_yaml_mapping

__all__ = ["FitAgreement", "FittedValue", "ParameterAgreement", "compare_fits", "read_fit"]

_FILE = "fitted_parameters.yaml"


@dataclass(frozen=True)
class FittedValue:
    """One parameter of a fit.

    Attributes:
        value: the fitted value [its unit].
        unit: its unit.
        identifiable: whether the fit found it pinned down by the data.
        resolution: relative step at which the cost rises visibly [-] (inf: never).
    """

    value: float
    unit: str
    identifiable: bool
    resolution: float


@dataclass(frozen=True)
class ParameterAgreement:
    r"""One parameter in both fits.

    Attributes:
        name: the parameter.
        unit: its unit.
        value_a: fit A's value [unit].
        value_b: fit B's value [unit].
        difference: :math:`\delta = (\theta_B - \theta_A)/|\theta_A|` [-] (inf if only A
            is 0).
        tolerance: :math:`\max(r_A, r_B)` [-].
        judged: both fits found it identifiable.
        agree: judged and :math:`|\delta| \le` tolerance; None when not judged.
    """

    name: str
    unit: str
    value_a: float
    value_b: float
    difference: float
    tolerance: float
    judged: bool
    agree: bool | None


@dataclass(frozen=True)
class FitAgreement:
    """Two fits compared.

    Attributes:
        robot: the robot both fitted.
        parameters: per parameter, in fit A's order.
    """

    robot: str
    parameters: tuple[ParameterAgreement, ...]

    @property
    def agree(self) -> bool:
        """Every judged parameter agrees (True when none is judged: nothing disagrees)."""
        return all(p.agree for p in self.parameters if p.judged)


def _fit_file(folder: Path) -> Path:
    path = Path(folder)
    return path / _FILE if path.is_dir() else path


def read_fit(folder: Path) -> tuple[str, dict[str, FittedValue]]:
    """A fit's robot and parameters from its folder (or its ``fitted_parameters.yaml``).

    Raises:
        InputFileError: no such file, or not a fit's ``fitted_parameters.yaml``.
    """
    path = _fit_file(folder)
    if not path.is_file():
        raise InputFileError(
            path, f"no {_FILE} here; give a folder written by 'zmpkit identify sim' or the file"
        )
    doc = read_yaml_mapping(path)
    if not isinstance(doc.get("parameters"), dict):
        raise InputFileError(path, "expected a fit's keys robot, effects, cost and parameters")
    values = {}
    for name, entry in doc["parameters"].items():
        values[str(name)] = _fitted_value(path, str(name), entry)
    if not values:
        raise InputFileError(path, "no fitted parameters", key="parameters")
    return str(doc.get("robot", "")), values


def _fitted_value(path: Path, name: str, entry: Any) -> FittedValue:
    key = f"parameters.{name}"
    if not isinstance(entry, dict):
        raise InputFileError(path, "expected value, unit, identifiable, resolution_pct", key=key)
    value: Any = entry.get("value")
    key_used = "marginal_resolution_pct" if "marginal_resolution_pct" in entry else "resolution_pct"
    resolution: Any = entry.get(key_used)
    if not _is_finite(value):
        raise InputFileError(path, f"value: expected a finite number, got {value!r}", key=key)
    if resolution is not None and not (_is_finite(resolution) and resolution >= 0):
        raise InputFileError(
            path, f"{key_used}: expected a number >= 0 or null, got {resolution!r}", key=key
        )
    identifiable = entry.get("identifiable")
    if not isinstance(identifiable, bool):
        raise InputFileError(
            path, f"identifiable: expected true or false, got {identifiable!r}", key=key
        )
    return FittedValue(
        float(value),
        str(entry.get("unit", "")),
        identifiable,
        math.inf if resolution is None else float(resolution) / 100.0,
    )


def _is_finite(x: object) -> bool:
    return isinstance(x, int | float) and not isinstance(x, bool) and math.isfinite(x)


def _relative(a: float, b: float) -> float:
    """:math:`(b - a)/|a|`; 0 when both are 0, inf when only ``a`` is."""
    if a == 0.0:
        return 0.0 if b == 0.0 else math.inf
    return (b - a) / abs(a)


def compare_fits(folder_a: Path, folder_b: Path) -> FitAgreement:
    """Fit B against fit A, parameter by parameter (module docstring).

    Raises:
        InputFileError: a fit cannot be read, or the two fits differ in robot or parameters.
    """
    robot_a, a = read_fit(folder_a)
    robot_b, b = read_fit(folder_b)
    if robot_a != robot_b:
        raise InputFileError(
            _fit_file(folder_b), f"robot {robot_b!r}, but the first fit is of {robot_a!r}"
        )
    if set(a) != set(b):
        raise InputFileError(
            _fit_file(folder_b),
            f"parameters {sorted(b)}, but the first fit has {sorted(a)}: compare fits of the "
            "same --effects",
        )
    rows = []
    for name, fa in a.items():
        fb = b[name]
        difference = _relative(fa.value, fb.value)
        tolerance = max(fa.resolution, fb.resolution)
        judged = fa.identifiable and fb.identifiable
        agree = (abs(difference) <= tolerance) if judged else None
        rows.append(
            ParameterAgreement(
                name, fa.unit, fa.value, fb.value, difference, tolerance, judged, agree
            )
        )
    return FitAgreement(robot_a, tuple(rows))
