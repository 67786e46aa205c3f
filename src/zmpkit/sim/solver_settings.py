"""Constraint-solver settings for a batch of rollouts (MuJoCo's ``opt`` fields).

MuJoCo (and MuJoCo Warp) stop the constraint solver after ``iterations`` or when the
relative cost improvement falls below ``tolerance``; the line search likewise after
``ls_iterations``. A batch on a GPU pays for the slowest world's iterations, so fewer may
be cheaper; ``benchmarks/bench_warp_solver.py`` measures what that costs in accuracy.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco

from zmpkit.errors import ParameterError

__all__ = ["SolverSettings"]


@dataclass(frozen=True)
class SolverSettings:
    """Solver options to set on a model; None keeps the model's own.

    Attributes:
        iterations: main solver iterations per step [-] (MuJoCo's default 100).
        tolerance: relative cost improvement that ends the solve [-] (default 1e-8; MuJoCo
            Warp computes in float32 and uses at least 1e-6).
        ls_iterations: line-search iterations per solver iteration [-] (default 50).
    """

    iterations: int | None = None
    tolerance: float | None = None
    ls_iterations: int | None = None

    def __post_init__(self) -> None:
        for name in ("iterations", "ls_iterations"):
            value = getattr(self, name)
            if value is not None and (isinstance(value, bool) or not isinstance(value, int)):
                raise ParameterError(f"{name} must be an integer >= 1 or None, got {value!r}")
            if value is not None and value < 1:
                raise ParameterError(f"{name} must be an integer >= 1 or None, got {value!r}")
        if self.tolerance is not None and not self.tolerance >= 0.0:
            raise ParameterError(f"tolerance must be >= 0 or None, got {self.tolerance!r}")

    def apply(self, model: mujoco.MjModel) -> None:
        """Set the options given on ``model`` (in place)."""
        if self.iterations is not None:
            model.opt.iterations = self.iterations
        if self.tolerance is not None:
            model.opt.tolerance = self.tolerance
        if self.ls_iterations is not None:
            model.opt.ls_iterations = self.ls_iterations

    @property
    def label(self) -> str:
        """A short description, e.g. ``"iterations=4, tolerance=1e-07"``."""
        parts = [f"{k}={v:g}" for k, v in vars(self).items() if v is not None]
        return ", ".join(parts) or "model default"
