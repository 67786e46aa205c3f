"""A robot's truth YAML as a document the fit edits: read, set parameters by path, write.

The fit never reads the hidden truth of the robot it fits; it starts from a *base* truth
file (the shipped one, or the user's ``--truth``) that holds every parameter it does not fit,
and writes the fitted values into a copy of it. That copy is a normal truth file, loadable
as ``--truth`` by the simulator (the robot's :attr:`~zmpkit.robots.robot.Robot.truth`).

Paths: keys joined by dots, list items in brackets; ``[0,2]`` or ``[*]`` addresses several
items at once (a shared value), e.g. ``flex[0,1].stiffness[0]`` or ``sensors.ft_offset.right[2]``
or ``torso.com_m[0]`` (one coordinate of a vector).
"""

from __future__ import annotations

import copy
import os
import re
import uuid
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from numpy.typing import NDArray

from zmpkit.errors import InputFileError, ParameterError
from zmpkit.io.yaml_file import load_yaml, yaml_error
from zmpkit.robots.robot import Robot
from zmpkit.sim.truth_file import RobotTruth
from zmpkit.simfit.parameters import FitParameter, ParameterValues

__all__ = [
    "EXPECTED_READINGS_ZEROED",
    "RobotTruth",
    "base_truth_path",
    "doc_with_columns",
    "expected_readings",
    "get_path",
    "load_robot_truth",
    "load_truth_doc",
    "set_path",
    "truth_doc_with",
    "write_truth_doc",
]


_TOKEN = re.compile(r"([^.\[\]]+)|\[([^\]]*)\]")


def _tokens(path: str) -> list[str | list[int] | None]:
    """``"a.b[0,1].c"`` → ``["a", "b", [0, 1], "c"]``; ``[*]`` → None (every item)."""
    out: list[str | list[int] | None] = []
    for key, index in _TOKEN.findall(path):
        if key:
            out.append(key)
        elif index.strip() == "*":
            out.append(None)
        else:
            try:
                out.append([int(i) for i in index.split(",")])
            except ValueError:
                raise ParameterError(f"bad index [{index}] in truth path {path!r}") from None
    if not out:
        raise ParameterError(f"empty truth path {path!r}")
    return out


def _children(node: Any, token: str | list[int] | None, path: str) -> list[Any]:
    if isinstance(token, str):
        if not isinstance(node, Mapping) or token not in node:
            raise ParameterError(
                f"truth path {path!r}: no key {token!r}; expected a truth document with the "
                "layout of the robot's shipped truth file (an older file may lack a section)"
            )
        return [node[token]]
    if not isinstance(node, list):
        raise ParameterError(f"truth path {path!r}: expected a list before the index")
    indices = range(len(node)) if token is None else token
    bad = [i for i in indices if not 0 <= i < len(node)]
    if bad:
        raise ParameterError(f"truth path {path!r}: index {bad} outside a list of {len(node)}")
    return [node[i] for i in indices]


def _parents(doc: Mapping[str, Any], path: str) -> tuple[list[Any], str | list[int] | None]:
    tokens = _tokens(path)
    nodes: list[Any] = [doc]
    for token in tokens[:-1]:
        nodes = [child for node in nodes for child in _children(node, token, path)]
    return nodes, tokens[-1]


def get_path(doc: Mapping[str, Any], path: str) -> list[float]:
    """Every number at ``path`` (one per addressed item)."""
    nodes, last = _parents(doc, path)
    values = [v for node in nodes for v in _children(node, last, path)]
    if not all(isinstance(v, int | float) and not isinstance(v, bool) for v in values):
        raise ParameterError(f"truth path {path!r} does not hold numbers: {values}")
    return [float(v) for v in values]


def set_path(doc: dict[str, Any], path: str, value: float) -> None:
    """Set every number at ``path`` to ``value`` (in place)."""
    get_path(doc, path)  # validates that numbers live there
    nodes, last = _parents(doc, path)
    for node in nodes:
        if isinstance(last, str):
            node[last] = float(value)
        else:
            for i in range(len(node)) if last is None else last:
                node[i] = float(value)


def base_truth_path(robot: Robot, truth: str | Path | None) -> Path:
    """The base truth file: ``truth`` if given, else the robot's shipped one."""
    if truth is not None:
        return Path(truth)
    return Path(robot.truth.default_path)


def load_truth_doc(path: str | Path) -> dict[str, Any]:
    """Read a truth YAML as a plain mapping.

    Raises:
        InputFileError: if it cannot be read or is not a mapping.
    """
    try:
        doc = load_yaml(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputFileError(path, "truth file not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputFileError(path, f"cannot read the truth file as UTF-8 text ({exc})") from None
    except yaml.YAMLError as exc:
        raise yaml_error(Path(path), exc) from None
    if not isinstance(doc, dict):
        raise InputFileError(path, "expected a mapping of sections at the top level")
    return doc


def truth_doc_with(
    base: Mapping[str, Any], parameters: Sequence[FitParameter], values: ParameterValues
) -> dict[str, Any]:
    """A copy of ``base`` with each parameter's path set to its value [units]."""
    doc = copy.deepcopy(dict(base))
    for parameter, value in zip(parameters, values, strict=True):
        set_path(doc, parameter.path, value)
    return doc


def doc_with_columns(
    base: Mapping[str, Any],
    parameters: Sequence[FitParameter],
    values: NDArray[np.float64],
) -> dict[str, Any]:
    """A copy of ``base`` whose fitted numbers are columns: one value per candidate [units].

    Args:
        base: the base truth document.
        parameters: the fitted parameters.
        values: ``(ncandidate, len(parameters))`` each candidate's values [units].

    Returns:
        The document with each parameter's path (every item it addresses) holding its
        ``(ncandidate,)`` column of float64 values, what a
        :class:`~zmpkit.robots.field_rule.FieldRule` reads.
    """
    doc = copy.deepcopy(dict(base))
    values = np.asarray(values, dtype=np.float64)
    for k, parameter in enumerate(parameters):
        get_path(doc, parameter.path)  # validates that numbers live there
        nodes, last = _parents(doc, parameter.path)
        for node in nodes:
            keys = [last] if isinstance(last, str) else last or range(len(node))
            for key in keys:
                node[key] = values[:, k].copy()
    return doc


EXPECTED_READINGS_ZEROED: dict[str, Any] = {
    "ft_noise_std": [0.0] * 6,
    "ft_quantisation": [0.0] * 6,
    "ft_offset_drift_std": [0.0] * 6,
    "encoder_resolution": 0.0,
    "gyro_noise_std": 0.0,
    "accel_noise_std": 0.0,
}
"""The ``sensors`` values :func:`expected_readings` sets: the chain's random and quantising
parts, zero."""


def expected_readings(doc: Mapping[str, Any]) -> dict[str, Any]:
    r"""A copy of ``doc`` whose sensors read their expected value: no noise, no quantisation.

    The sensor chain's deterministic parts stay (F-T offsets, gain error, low-pass filter,
    sample rate): a simulated reading is then the mean of what the real sensor would read.
    Fitting to it is least squares under the sensors' noise, and the cost is smooth in the
    parameters: quantised simulated encoders compared with quantised recorded ones change
    by whole quanta where the angles cross a quantum's edge, so the squared joint error
    grows like :math:`|\delta|`, not :math:`\delta^2`, and jumps on small scales.
    """
    out = copy.deepcopy(dict(doc))
    sensors = out.get("sensors")
    out["sensors"] = {
        **(sensors if isinstance(sensors, dict) else {}),
        **copy.deepcopy(EXPECTED_READINGS_ZEROED),
    }  # a truth without a sensors section reads the defaults, which have noise
    return out


def write_truth_doc(doc: Mapping[str, Any], path: str | Path, header: str = "") -> Path:
    """Write ``doc`` as a truth YAML (atomically), with ``header`` as leading comments."""
    path = Path(path)
    lines = "".join(f"# {line}\n" for line in header.splitlines())
    text = lines + yaml.safe_dump(dict(doc), sort_keys=False, allow_unicode=True)
    tmp = path.with_name(f"{path.name}.{os.getpid()}.{uuid.uuid4().hex}.tmp")  # writers may race
    tmp.write_text(text, encoding="utf-8")
    os.replace(tmp, path)
    return path


def load_robot_truth(robot: Robot, doc: Mapping[str, Any]) -> RobotTruth:
    """The robot's truth object for a truth document.

    Raises:
        InputFileError: if the document does not fit the robot's truth layout.
    """
    return robot.truth.from_doc(doc, "<fit candidate truth>")
