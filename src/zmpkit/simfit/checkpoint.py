"""The fit's checkpoint: CMA-ES state after every generation, and the cost history.

Files in the output folder, both replaced atomically after each generation, so an
interruption (Ctrl-C, kill) at any moment leaves the last finished generation on disk:

- :data:`CHECKPOINT_FILE` — pickle of the :class:`Checkpoint`: the ``cma`` strategy object
  of the current run (IPOP restarts: which restart, where it began), the state of the random
  generator it draws from (numpy's global one), the best candidate so far and the
  fingerprint of the fit it belongs to;
- :data:`HISTORY_FILE` — JSON list of :class:`GenerationRecord`, one per generation, each
  with its restart and population.

A resumed fit checks that its fingerprint equals the checkpoint's.
"""

from __future__ import annotations

import json
import os
import pickle
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from zmpkit.errors import InputFileError, ParameterError

__all__ = [
    "CHECKPOINT_FILE",
    "CHECKPOINT_FORMAT",
    "HISTORY_FILE",
    "Checkpoint",
    "GenerationRecord",
    "check_fingerprint",
    "load_checkpoint",
    "save_checkpoint",
]

CHECKPOINT_FILE = "checkpoint.pkl"
HISTORY_FILE = "history.json"
CHECKPOINT_FORMAT = "zmpkit-simfit-checkpoint/1"


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


@dataclass
class Checkpoint:
    """Everything needed to continue a fit after its last finished generation.

    Attributes:
        fingerprint: what the fit is (robot, parameters, experiments, seed, options).
        strategy: the ``cma.CMAEvolutionStrategy``.
        rng_state: numpy's global random state the strategy samples from.
        generation: finished generations.
        best_unit: best candidate so far, normalised coordinates [-].
        best_cost: its cost [-].
        history: the finished generations.
        restart: the run the strategy is: 0 the first, k the k-th IPOP restart.
        run_start: generations finished before this run began.
        best_restart: the run that found the best candidate.
        best_run_std: that run's final standard deviation per parameter, normalised [-],
            once a later run replaced it (None while the best is the current run's).
    """

    fingerprint: dict[str, Any]
    strategy: Any
    rng_state: Any
    generation: int
    best_unit: list[float]
    best_cost: float
    history: list[GenerationRecord]
    restart: int = 0
    run_start: int = 0
    best_restart: int = 0
    best_run_std: list[float] | None = None


def _atomic(path: Path, data: bytes) -> None:
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_bytes(data)
    os.replace(tmp, path)


def save_checkpoint(checkpoint: Checkpoint, folder: Path) -> Path:
    """Write the checkpoint and the history into ``folder``; return the checkpoint file."""
    payload = {"format": CHECKPOINT_FORMAT, "checkpoint": checkpoint}
    path = folder / CHECKPOINT_FILE
    _atomic(path, pickle.dumps(payload, protocol=pickle.HIGHEST_PROTOCOL))
    history = [asdict(r) for r in checkpoint.history]
    _atomic(folder / HISTORY_FILE, (json.dumps(history, indent=1) + "\n").encode("utf-8"))
    return path


def load_checkpoint(folder: str | Path) -> Checkpoint:
    """Read the checkpoint of a fit folder.

    Raises:
        InputFileError: if the folder has no readable checkpoint of this format.
    """
    path = Path(folder) / CHECKPOINT_FILE
    try:
        payload = pickle.loads(path.read_bytes())
    except FileNotFoundError:
        raise InputFileError(
            path,
            "no checkpoint here; expected the folder of an earlier "
            "'zmpkit identify sim' run (its --out)",
        ) from None
    except (OSError, pickle.UnpicklingError, EOFError, AttributeError, ImportError) as exc:
        raise InputFileError(path, f"cannot read the checkpoint: {exc}") from None
    if not isinstance(payload, dict) or payload.get("format") != CHECKPOINT_FORMAT:
        raise InputFileError(path, f"not a checkpoint of format {CHECKPOINT_FORMAT}")
    return payload["checkpoint"]


def check_fingerprint(saved: dict[str, Any], current: dict[str, Any], folder: Path) -> None:
    """Refuse to resume a checkpoint of another fit.

    Raises:
        ParameterError: naming the settings that differ.
    """
    keys = sorted(set(saved) | set(current))
    differ = [k for k in keys if saved.get(k) != current.get(k)]
    if differ:
        detail = "; ".join(f"{k}: {saved.get(k)!r} there, {current.get(k)!r} now" for k in differ)
        raise ParameterError(f"cannot resume {folder}: it is another fit ({detail})")
