"""Identified balance parameters (paper A §4.3–4.4): the step fits per plane, and their YAML file.

:func:`identify_balance` runs, per plane, the steady-state detection, the error-model fit
(eq. 13, chosen by cross-validation) and the transient fits over a set of step trials, and
returns everything as a :class:`BalanceIdentification`. Its :class:`BalanceParams` — error
model per plane, mean transient ζ and ω_n, and the pendulum the controller believes (mass,
CoM height, g) — is what :meth:`BalanceParams.to_yaml` writes and the controller loads.
The YAML keys carry their units::

    format: zmpkit-balance-params
    version: 1
    pendulum: {mass_kg: 62.6, com_height_m: 0.893, g_m_per_s2: 9.81}
    planes:
      sagittal:
        error_model: {model: quadratic, a_per_m: 0.834, b: 1.024, c_m: -0.0004}
        transient: {zeta: 0.3, omega_n_rad_per_s: 6.0}
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
import yaml

from zmpkit._validate import positive
from zmpkit.errors import InputFileError, ModelError, ParameterError
from zmpkit.identify.error_fit import PARSIMONY_MARGIN, ErrorModelFit, fit_error_model
from zmpkit.identify.error_model import EQUATIONS, MODEL_KINDS, TERMS, ErrorModel
from zmpkit.identify.transient import TransientFit, fit_transient
from zmpkit.io.yaml_file import read_yaml_mapping, require_number
from zmpkit.models.pendulum import STANDARD_GRAVITY_MPS2
from zmpkit.signals.steady_state import SteadyState, steady_state
from zmpkit.signals.step_trial import PLANES, StepTrial

__all__ = [
    "BalanceIdentification",
    "BalanceParams",
    "PlaneIdentification",
    "PlaneParams",
    "identify_balance",
]

FORMAT = "zmpkit-balance-params"
VERSION = 1
COEFFICIENT_KEYS = {"d": "d_per_m2", "a": "a_per_m", "b": "b", "c": "c_m"}
"""YAML key of each error-model coefficient, with its unit."""


@dataclass(frozen=True)
class PlaneParams:
    """Identified parameters of one plane.

    Attributes:
        error_model: the steady-state error model x_measured = f(x_cmd).
        zeta: mean damping ratio of the transient fits [-]; None if none succeeded.
        omega_n: mean natural frequency of the transient fits [rad/s]; None likewise.
    """

    error_model: ErrorModel
    zeta: float | None = None
    omega_n: float | None = None


@dataclass(frozen=True, eq=False)
class BalanceParams:
    """What the balance controller loads: the pendulum it believes and the error per plane.

    Attributes:
        mass: pendulum mass [kg].
        com_height: pendulum length, ankle to CoM [m].
        g: gravitational acceleration [m/s²].
        planes: :class:`PlaneParams` by plane name (``"sagittal"``, ``"frontal"``).
    """

    mass: float
    com_height: float
    planes: Mapping[str, PlaneParams]
    g: float = STANDARD_GRAVITY_MPS2

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", positive("mass", self.mass, "kg"))
        object.__setattr__(self, "com_height", positive("com_height", self.com_height, "m"))
        object.__setattr__(self, "g", positive("g", self.g, "m/s^2"))
        unknown = [p for p in self.planes if p not in PLANES]
        if unknown or not self.planes:
            raise ParameterError(f"planes must be a non-empty subset of {PLANES}, got {unknown}")
        object.__setattr__(self, "planes", dict(self.planes))

    def plane(self, name: str) -> PlaneParams:
        """The parameters of plane ``name``; ParameterError listing the planes present."""
        if name not in self.planes:
            raise ParameterError(f"no parameters for plane {name!r}; have {tuple(self.planes)}")
        return self.planes[name]

    def to_dict(self) -> dict[str, Any]:
        """The YAML document as plain data (module docstring)."""
        planes = {}
        for name, plane in self.planes.items():
            model: dict[str, str | float] = {
                "model": plane.error_model.kind,
                "equation": plane.error_model.equation,
            }
            for key, value in plane.error_model.as_dict().items():
                model[COEFFICIENT_KEYS[key]] = value
            transient = {"zeta": plane.zeta, "omega_n_rad_per_s": plane.omega_n}
            planes[name] = {"error_model": model, "transient": transient}
        pendulum = {"mass_kg": self.mass, "com_height_m": self.com_height, "g_m_per_s2": self.g}
        return {"format": FORMAT, "version": VERSION, "pendulum": pendulum, "planes": planes}

    def to_yaml(self, path: str | Path) -> Path:
        """Write the parameters to ``path`` as YAML; returns the path."""
        path = Path(path)
        path.write_text(yaml.safe_dump(self.to_dict(), sort_keys=False), encoding="utf-8")
        return path

    @classmethod
    def from_yaml(cls, path: str | Path) -> BalanceParams:
        """Read parameters written by :meth:`to_yaml`.

        Raises:
            InputFileError: naming the file and the field that is missing or malformed.
        """
        path = Path(path)
        data = read_yaml_mapping(path)
        if data.get("format") != FORMAT or data.get("version") != VERSION:
            raise InputFileError(
                path,
                f"expected format: {FORMAT} and version: {VERSION}, got format: "
                f"{data.get('format')!r}, version: {data.get('version')!r}",
            )
        pendulum = _mapping(path, "pendulum", data.get("pendulum"))
        _known_keys(path, "pendulum", pendulum, ("mass_kg", "com_height_m", "g_m_per_s2"))
        numbers = [
            _positive(path, f"pendulum.{key}", pendulum.get(key))
            for key in ("mass_kg", "com_height_m", "g_m_per_s2")
        ]
        planes = _mapping(path, "planes", data.get("planes"))
        if not planes or any(name not in PLANES for name in planes):
            raise InputFileError(
                path, f"field 'planes' must map some of {PLANES} to parameters, got {list(planes)}"
            )
        parsed = {name: _plane(path, name, value) for name, value in planes.items()}
        return cls(numbers[0], numbers[1], parsed, numbers[2])


def _mapping(path: Path, field: str, value: object) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise InputFileError(path, f"field '{field}' must be a mapping, got {value!r}")
    return value


def _known_keys(path: Path, field: str, value: Mapping[str, Any], keys: Sequence[str]) -> None:
    unknown = [key for key in value if key not in keys]
    if unknown:
        raise InputFileError(
            path, f"field '{field}' has unknown keys {unknown}; valid keys: {list(keys)}"
        )


def _positive(path: Path, field: str, value: object) -> float:
    if value is None:
        raise InputFileError(path, f"field '{field}' is missing")
    number = require_number(path, field, value)
    if number <= 0.0:
        raise InputFileError(path, f"field '{field}' must be > 0, got {number}")
    return number


def _plane(path: Path, name: str, value: object) -> PlaneParams:
    plane = _mapping(path, f"planes.{name}", value)
    _known_keys(path, f"planes.{name}", plane, ("error_model", "transient"))
    field = f"planes.{name}.error_model"
    model = _mapping(path, field, plane.get("error_model"))
    kind = model.get("model")
    if kind not in MODEL_KINDS:
        raise InputFileError(
            path, f"field '{field}.model' must be one of {list(MODEL_KINDS)}, got {kind!r}"
        )
    keys = [COEFFICIENT_KEYS[term] for term in TERMS[kind]]
    _known_keys(path, field, model, ["model", "equation", *keys])
    coefficients = []
    for key in keys:
        if key not in model:
            raise InputFileError(path, f"field '{field}.{key}' is missing ({EQUATIONS[kind]})")
        coefficients.append(require_number(path, f"{field}.{key}", model[key]))
    transient = _mapping(path, f"planes.{name}.transient", plane.get("transient", {}))
    _known_keys(path, f"planes.{name}.transient", transient, ("zeta", "omega_n_rad_per_s"))
    zeta, omega = (
        None
        if transient.get(key) is None
        else _positive(path, f"planes.{name}.transient.{key}", transient[key])
        for key in ("zeta", "omega_n_rad_per_s")
    )
    return PlaneParams(ErrorModel(kind, tuple(coefficients)), zeta, omega)


@dataclass(frozen=True, eq=False)
class PlaneIdentification:
    """Everything identified in one plane.

    Attributes:
        plane: ``"sagittal"`` or ``"frontal"``.
        trials: the plane's trials, in input order.
        indices: their positions in the sequence given to :func:`identify_balance`.
        steady_states: steady state of each trial.
        transients: transient fit of each trial.
        error_fit: the error-model fit over the settled trials.
        excluded: why each unsettled trial was left out of the error-model fit.
        params: the plane's :class:`PlaneParams`.
    """

    plane: str
    trials: tuple[StepTrial, ...]
    indices: tuple[int, ...]
    steady_states: tuple[SteadyState, ...]
    transients: tuple[TransientFit, ...]
    error_fit: ErrorModelFit
    excluded: tuple[str, ...]
    params: PlaneParams


@dataclass(frozen=True, eq=False)
class BalanceIdentification:
    """Result of :func:`identify_balance`.

    Attributes:
        planes: :class:`PlaneIdentification` by plane name.
        params: the :class:`BalanceParams` to save and load into the controller.
    """

    planes: Mapping[str, PlaneIdentification]
    params: BalanceParams


def identify_balance(
    trials: Sequence[StepTrial],
    *,
    mass: float,
    com_height: float,
    g: float = STANDARD_GRAVITY_MPS2,
    weighted: bool = True,
    candidates: tuple[str, ...] = MODEL_KINDS,
    margin: float = PARSIMONY_MARGIN,
    dead_time: bool = True,
    steady_options: Mapping[str, Any] | None = None,
) -> BalanceIdentification:
    """Identify the steady-state error model and the transient per plane from step trials.

    Args:
        trials: step trials of one or both planes.
        mass: pendulum mass the controller believes [kg].
        com_height: pendulum length (ankle to CoM) the controller believes [m].
        g: gravitational acceleration [m/s²].
        weighted: weight the error-model fit by 1/SE² of the steady states.
        candidates: error models to cross-validate (see :func:`fit_error_model`).
        margin: parsimony margin of the model choice [-].
        dead_time: whether the transient fits include a dead time.
        steady_options: keyword arguments for :func:`steady_state` (e.g. ``min_duration_s``).

    Raises:
        ParameterError: no trials.
        ModelError: a plane with too few settled trials to fit its error model.
    """
    if len(trials) == 0:
        raise ParameterError("trials must hold at least one StepTrial, got none")
    planes = {}
    for plane in PLANES:
        indices = tuple(i for i, trial in enumerate(trials) if trial.plane == plane)
        if indices:
            settings = _Settings(weighted, candidates, margin, dead_time, steady_options or {})
            planes[plane] = _identify_plane(plane, trials, indices, settings)
    params = BalanceParams(mass, com_height, {p: r.params for p, r in planes.items()}, g)
    return BalanceIdentification(planes, params)


class _Settings(NamedTuple):
    weighted: bool
    candidates: tuple[str, ...]
    margin: float
    dead_time: bool
    steady_options: Mapping[str, Any]


def _identify_plane(
    plane: str, trials: Sequence[StepTrial], indices: tuple[int, ...], settings: _Settings
) -> PlaneIdentification:
    chosen = tuple(trials[i] for i in indices)
    steadies = tuple(steady_state(trial, **settings.steady_options) for trial in chosen)
    transients = tuple(
        fit_transient(t, s, dead_time=settings.dead_time)
        for t, s in zip(chosen, steadies, strict=True)
    )
    used = [k for k, s in enumerate(steadies) if s.settled]
    excluded = tuple(
        f"trial {indices[k]} (zmp_ref = {chosen[k].zmp_ref:.4g} m): {s.reason}"
        for k, s in enumerate(steadies)
        if not s.settled
    )
    if len(used) < 3:
        raise ModelError(
            f"the {plane} plane has {len(used)} settled trials, the error model needs at least 3; "
            + ("; ".join(excluded) or "give more trials")
        )
    se = np.array([steadies[k].std_error for k in used], dtype=float)
    fit = fit_error_model(
        [chosen[k].x_cmd for k in used],
        np.asarray([steadies[k].value for k in used], dtype=np.float64),  # all settled: not None
        std_errors=se if settings.weighted and np.all(se > 0.0) else None,
        candidates=settings.candidates,
        margin=settings.margin,
    )
    good = [t for t in transients if t.ok]
    zeta = float(np.mean([t.zeta for t in good])) if good else None
    omega = float(np.mean([t.omega_n for t in good])) if good else None
    params = PlaneParams(fit.model, zeta, omega)
    return PlaneIdentification(plane, chosen, indices, steadies, transients, fit, excluded, params)
