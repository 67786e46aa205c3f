"""Picklable factories of the lean controllers compared in the balance validation.

The balance pipeline builds one per plane and kind from the identified error model. A sweep
runs its trials in worker processes, so it receives a factory, not a controller: each trial
builds its own controller, at rest, from these settings. ``settings()`` goes into the
dataset's ``meta.json``, so a resumed sweep refuses a folder run with other settings.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, TypedDict

from zmpkit.control import (
    DlipmController,
    DlipmFeedbackController,
    GainSchedule,
    LinearCorrectionController,
    LipmController,
    ZmpFeedbackGains,
)
from zmpkit.experiments.trial import CONTROL_PERIOD_S, LeanController
from zmpkit.identify import ErrorModel
from zmpkit.models.pendulum import STANDARD_GRAVITY_MPS2

__all__ = ["CONTROLLER_KINDS", "FEEDBACK_AUTHORITY", "FEEDBACK_KINDS", "LeanControllerFactory"]

CONTROLLER_KINDS = ("dlipm", "linear", "lipm_pid", "dlipm_fb")
"""Controllers built here: the scheduled DLIPM (Fig. 19), one linear correction, the LIPM
with a PI on the measured ZMP (LIPM+PID), and the DLIPM with the same PI (DLIPM+feedback)."""
FEEDBACK_KINDS = ("lipm_pid", "dlipm_fb")
"""The kinds that read the measured ZMP each tick."""
FEEDBACK_AUTHORITY = 0.25
"""The PI's correction is clamped to this fraction of the lean angle limit [-]: the
feedforward does the lean, the feedback trims it."""


class _Limits(TypedDict):
    """The limits both kinds of controller take, by keyword."""

    angle_limit_rad: float
    rate_limit_rad_s: float
    support_polygon: tuple[float, float]


@dataclass(frozen=True)
class LeanControllerFactory:
    """Builds one plane's lean controller from identified parameters and design data.

    Attributes:
        kind: ``"dlipm"`` (gain-scheduled DLIPM), ``"linear"`` (θ from the fitted slope),
            ``"lipm_pid"`` (the LIPM angle plus a PI on the measured ZMP) or ``"dlipm_fb"``
            (the DLIPM plus the same PI, :mod:`zmpkit.control.dlipm_feedback`).
        error_model: the identified steady-state error model x_FT = f(x_cmd).
        mass_kg: pendulum mass the controller believes [kg].
        lean_length_m: pendulum length, ankle pivot to CoM, from the design model [m].
        zeta: damping ratio the DLIPM is designed for [-].
        time_scale: DLIPM time scale (see :mod:`zmpkit.control.dlipm_controller`) [-].
        angle_limit_rad: lean angle limit [rad].
        rate_limit_rad_s: lean rate limit [rad/s].
        support_polygon: target clamp (x_min, x_max) in this plane [m].
        max_acceleration_rad_s2: if set, the DLIPM slows per target so its planned angular
            acceleration stays within this (the servos' limit) [rad/s²].
        g: gravitational acceleration [m/s²].
        fitted_range: range of measured ZMPs the error model was fitted on [m]; None: unknown.
    """

    kind: str
    error_model: ErrorModel
    mass_kg: float
    lean_length_m: float
    zeta: float
    time_scale: float
    angle_limit_rad: float
    rate_limit_rad_s: float
    support_polygon: tuple[float, float]
    max_acceleration_rad_s2: float | None = None
    g: float = STANDARD_GRAVITY_MPS2
    fitted_range: tuple[float, float] | None = None

    def schedule(self) -> GainSchedule:
        """The gain schedule of this plane, with its fitted range."""
        return GainSchedule(
            self.error_model, self.mass_kg, self.lean_length_m, self.zeta, self.g, self.fitted_range
        )

    def __call__(self) -> LeanController:
        """A new controller at rest on target 0."""
        limits: _Limits = {
            "angle_limit_rad": self.angle_limit_rad,
            "rate_limit_rad_s": self.rate_limit_rad_s,
            "support_polygon": self.support_polygon,
        }
        if self.kind == "linear":
            return LinearCorrectionController.from_error_model(
                self.error_model, self.lean_length_m, CONTROL_PERIOD_S, **limits
            )
        if self.kind == "lipm_pid":  # the LIPM angle, then the same PI on the same mismatch
            lipm = LipmController(self.lean_length_m, CONTROL_PERIOD_S, **limits)
            return DlipmFeedbackController(lipm, self.feedback_gains())
        controller = DlipmController(
            self.schedule(),
            CONTROL_PERIOD_S,
            time_scale=self.time_scale,
            max_acceleration_rad_s2=self.max_acceleration_rad_s2,
            **limits,
        )
        controller.reset(0.0)  # the robot stands upright when the target is given
        if self.kind == "dlipm_fb":
            return DlipmFeedbackController(controller, self.feedback_gains())
        return controller

    def feedback_gains(self) -> ZmpFeedbackGains:
        r"""The PI's gains by the rule of :mod:`zmpkit.control.dlipm_feedback`.

        The plant's DC gain is :math:`G_0 = l\,f'(0)` [m/rad]; the correction and the
        integral are clamped to :data:`FEEDBACK_AUTHORITY` of the lean angle limit.
        """
        dc_gain = self.lean_length_m * float(self.error_model.derivative(0.0))
        return ZmpFeedbackGains.from_plant(
            dc_gain, self.lean_length_m, FEEDBACK_AUTHORITY * self.angle_limit_rad, self.g
        )

    def settings(self) -> dict[str, Any]:
        """JSON-ready description, recorded in the dataset's ``meta.json``."""
        return {
            "kind": self.kind,
            "error_model": {
                "kind": self.error_model.kind,
                "coefficients": list(self.error_model.coefficients),
            },
            "mass_kg": self.mass_kg,
            "lean_length_m": self.lean_length_m,
            "zeta": self.zeta,
            "time_scale": self.time_scale,
            "angle_limit_rad": self.angle_limit_rad,
            "rate_limit_rad_s": self.rate_limit_rad_s,
            "support_polygon_m": list(self.support_polygon),
            "max_acceleration_rad_s2": self.max_acceleration_rad_s2,
            "control_period_s": CONTROL_PERIOD_S,
            "fitted_range_m": None if self.fitted_range is None else list(self.fitted_range),
        }
