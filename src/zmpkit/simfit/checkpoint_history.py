"""A fit's generations: :class:`GenerationRecord`, and reading them back from a checkpoint.

The checkpoint's JSON keeps the history as :meth:`GenerationRecord.as_plain` of each record;
:func:`history_from_json` checks every field (type, range, one record per generation
in order) and raises :class:`~zmpkit.errors.InputFileError` in one line on the first that
is not as zmpkit wrote it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from pathlib import Path

from zmpkit.simfit.checkpoint_data import damaged

__all__ = ["GenerationRecord", "history_from_json"]


@dataclass(frozen=True)
class GenerationRecord:
    """One generation of the fit.

    Attributes:
        generation: 1-based generation number.
        evaluations: candidates evaluated so far.
        best_cost: lowest cost of this generation [-].
        best_so_far: lowest cost of the whole fit so far [-].
        median_cost: median cost of this generation [-].
        sigma: CMA-ES step size, in normalised coordinates [-].
        best_values: the best-so-far parameter values, by name [units].
        wall_s: wall time of this generation [s].
        restart: the CMA-ES run it belongs to: 0 the first, k the k-th IPOP restart.
        popsize: candidates of this generation (its run's population).
    """

    generation: int
    evaluations: int
    best_cost: float
    best_so_far: float
    median_cost: float
    sigma: float
    best_values: dict[str, float]
    wall_s: float
    restart: int = 0
    popsize: int = 0

    def as_plain(self) -> dict[str, object]:
        """The record as JSON-ready values, as ``dataclasses.asdict`` gives them.

        Built directly: a checkpoint writes every record after every generation, and
        ``asdict``'s generic deep copy made a 770-generation fit spend 32 s in it.
        """
        return {
            "generation": self.generation,
            "evaluations": self.evaluations,
            "best_cost": self.best_cost,
            "best_so_far": self.best_so_far,
            "median_cost": self.median_cost,
            "sigma": self.sigma,
            "best_values": dict(self.best_values),
            "wall_s": self.wall_s,
            "restart": self.restart,
            "popsize": self.popsize,
        }


_FIELDS = tuple(f.name for f in fields(GenerationRecord))
_COUNTS = ("generation", "evaluations", "restart", "popsize")
_COSTS = ("best_cost", "best_so_far", "median_cost")  # >= 0; +inf where every rollout failed


def _number(value: object) -> float | None:
    """``value`` as a float if it is a JSON number (not a flag), else None."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    return float(value)


def _field_problem(name: str, value: object) -> str | None:
    """What is wrong with one field of a record, or None."""
    if name in _COUNTS:
        return None if type(value) is int and value >= 0 else "expected an integer >= 0"
    if name == "best_values":
        if not isinstance(value, dict):
            return "expected an object of parameter values"
        numbers = [_number(v) for v in value.values()]
        ok = all(x is not None and math.isfinite(x) for x in numbers)
        return None if ok else "expected finite parameter values"
    x = _number(value)
    if name in _COSTS:
        return None if x is not None and x >= 0.0 else "expected a cost >= 0"
    if name == "sigma":
        return None if x is not None and 0.0 < x < math.inf else "expected a positive step size"
    return None if x is not None and 0.0 <= x < math.inf else "expected a finite time >= 0"


def _record(raw: object, k: int, where: Path) -> GenerationRecord:
    key = f"history[{k}]"
    if not isinstance(raw, dict):
        raise damaged(where, "expected an object of a generation's fields", key=key)
    missing, unknown = sorted(set(_FIELDS) - set(raw)), sorted(set(raw) - set(_FIELDS))
    if missing or unknown:
        what = f"lacks the field {missing[0]!r}" if missing else f"unknown field {unknown[0]!r}"
        raise damaged(where, what[:80], key=key)
    for name in _FIELDS:
        problem = _field_problem(name, raw[name])
        if problem is not None:
            message = f"{problem}"
            raise damaged(where, message, key=f"{key}.{name}")
    if raw["generation"] != k + 1:
        raise damaged(where, f"expected generation {k + 1}", key=f"{key}.generation")
    floats = {name: float(raw[name]) for name in (*_COSTS, "sigma", "wall_s")}
    values = {str(n): float(v) for n, v in raw["best_values"].items()}
    return GenerationRecord(**{**raw, **floats, "best_values": values})


def history_from_json(raw: object, generations: int, where: Path) -> list[GenerationRecord]:
    """The records of a checkpoint's ``history``, one per finished generation.

    Args:
        raw: the parsed JSON value.
        generations: the checkpoint's finished generations.
        where: the checkpoint file, for messages.

    Raises:
        InputFileError: on a record missing, extra, out of order or with a bad field.
    """
    if not isinstance(raw, list) or len(raw) != generations:
        raise damaged(where, f"expected a list of {generations} generations", key="history")
    return [_record(r, k, where) for k, r in enumerate(raw)]
