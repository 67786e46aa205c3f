"""The fit's checkpoint: CMA-ES state after every generation, and the cost history.

Files in the output folder, replaced atomically after each generation (a temporary file
renamed over the old one), so an interruption (Ctrl-C, kill) at any moment leaves the last
finished generation on disk:

- :data:`CHECKPOINT_FILE` — JSON: the format tag (:data:`CHECKPOINT_FORMAT`), the ``cma``
  version, the fingerprint of the fit it belongs to, the generations finished, the IPOP
  bookkeeping (which restart, where it began, which run found the best), the strategy's
  integer state and the names of its arrays (:mod:`~zmpkit.simfit.cma_state`), the random
  generators' positions, the history, and the SHA-256 of
- :data:`ARRAYS_FILE` — NumPy ``.npz`` (uncompressed, no object arrays): every float of the
  state (mean, step size, covariance, evolution paths, the last generation's candidates and
  costs, the cost histories, the best candidate) and the random generators' words;
- :data:`HISTORY_FILE` — JSON list of :class:`GenerationRecord`, one per generation, each
  with its restart and population.

Both checkpoint files hold data only: reading them runs no code (no pickle; NumPy arrays
with ``allow_pickle=False``). :func:`load_checkpoint` validates every value and refuses a
damaged checkpoint, an older format (the pickled :data:`OLD_CHECKPOINT_FILE` of zmpkit
before format 2, never opened) or a checkpoint of another ``cma`` version with one
:class:`~zmpkit.errors.InputFileError` line. The ``.npz`` is written first; its SHA-256 in
the JSON tells a pair mixed by a crash between the two renames, or a partial copy, as
damaged. A resumed fit checks that its fingerprint equals the checkpoint's
(:func:`check_fingerprint`).
"""

from __future__ import annotations

import hashlib
import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import InputFileError, ParameterError
from zmpkit.simfit.checkpoint_data import (
    ArrayFile,
    damaged,
    echo,
    generator_data,
    generator_state,
    npz_bytes,
    one_line,
    read_arrays,
)
from zmpkit.simfit.checkpoint_history import GenerationRecord, history_from_json
from zmpkit.simfit.cma_state import CMA_VERSION, rebuild_strategy, strategy_data

__all__ = [
    "ARRAYS_FILE",
    "CHECKPOINT_FILE",
    "CHECKPOINT_FORMAT",
    "HISTORY_FILE",
    "OLD_CHECKPOINT_FILE",
    "Checkpoint",
    "GenerationRecord",
    "check_fingerprint",
    "load_checkpoint",
    "save_checkpoint",
]

CHECKPOINT_FILE = "checkpoint.json"
ARRAYS_FILE = "checkpoint.npz"
OLD_CHECKPOINT_FILE = "checkpoint.pkl"
HISTORY_FILE = "history.json"
CHECKPOINT_FORMAT = "zmpkit-simfit-checkpoint/2"
_KEYS = frozenset(
    {"format", "cma", "fingerprint", "generation", "restart", "run_start", "best_restart"}
    | {"best_run_std", "strategy", "random", "arrays", "history"}
)
_MAX_RUNS = 64
_ECHO = 30


@dataclass
class Checkpoint:
    """Everything needed to continue a fit after its last finished generation.

    Attributes:
        fingerprint: what the fit is (robot, parameters, experiments, seed, options).
        strategy: the ``cma.CMAEvolutionStrategy``.
        draws: the ``numpy.random.RandomState`` the strategy samples with (its ``randn``).
        rng_state: numpy's global random state, for any other draw ``cma`` makes.
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
    draws: Any
    rng_state: Any
    generation: int
    best_unit: list[float]
    best_cost: float
    history: list[GenerationRecord]
    restart: int = 0
    run_start: int = 0
    best_restart: int = 0
    best_run_std: list[float] | None = None


def _to_data(checkpoint: Checkpoint) -> tuple[dict[str, Any], dict[str, NDArray[Any]]]:
    """(JSON document without ``arrays``, arrays by name)."""
    strategy, arrays = strategy_data(checkpoint.strategy)
    draws, draw_arrays = generator_data(checkpoint.draws.get_state(), "random.draws")
    outer, outer_arrays = generator_data(checkpoint.rng_state, "random.global")
    arrays |= draw_arrays | outer_arrays
    arrays["fit.best_unit"] = np.asarray(checkpoint.best_unit, dtype=float)
    arrays["fit.best_cost"] = np.asarray(np.float64(checkpoint.best_cost))
    if checkpoint.best_run_std is not None:
        arrays["fit.best_run_std"] = np.asarray(checkpoint.best_run_std, dtype=float)
    doc = {
        "format": CHECKPOINT_FORMAT,
        "cma": CMA_VERSION,
        "fingerprint": checkpoint.fingerprint,
        "generation": checkpoint.generation,
        "restart": checkpoint.restart,
        "run_start": checkpoint.run_start,
        "best_restart": checkpoint.best_restart,
        "best_run_std": None if checkpoint.best_run_std is None else "fit.best_run_std",
        "strategy": strategy,
        "random": {"draws": draws, "global": outer},
        "history": [r.as_plain() for r in checkpoint.history],
    }
    return doc, arrays


def _temporary(path: Path, data: bytes) -> Path:
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_bytes(data)
    return tmp


def save_checkpoint(checkpoint: Checkpoint, folder: Path) -> Path:
    """Write the checkpoint and the history into ``folder``; return the checkpoint file."""
    doc, arrays = _to_data(checkpoint)
    npz = npz_bytes(arrays)
    digest = hashlib.sha256(npz).hexdigest()
    doc["arrays"] = {"file": ARRAYS_FILE, "sha256": digest, "names": sorted(arrays)}
    path = folder / CHECKPOINT_FILE
    text = json.dumps(doc) + "\n"  # no indent: json's C encoder (indent runs it in Python)
    npz_tmp = _temporary(folder / ARRAYS_FILE, npz)
    json_tmp = _temporary(path, text.encode("utf-8"))
    os.replace(npz_tmp, folder / ARRAYS_FILE)
    os.replace(json_tmp, path)
    history = ",\n".join(json.dumps(r.as_plain()) for r in checkpoint.history)  # a line each
    history_tmp = _temporary(folder / HISTORY_FILE, f"[\n{history}\n]\n".encode())
    os.replace(history_tmp, folder / HISTORY_FILE)
    return path


def load_checkpoint(folder: str | Path) -> Checkpoint:
    """Read the checkpoint of a fit folder; no code in it runs (module docstring).

    Raises:
        InputFileError: in one line, if the folder has no checkpoint, an older format, one
            of another ``cma`` version, or a damaged one.
    """
    folder = Path(folder)
    path = folder / CHECKPOINT_FILE
    doc = _read_document(folder, path)
    arrays = read_arrays(folder / ARRAYS_FILE, doc["arrays"], path)
    checkpoint = _from_data(doc, arrays, path)
    arrays.finish()
    return checkpoint


def _read_document(folder: Path, path: Path) -> dict[str, Any]:
    if not path.is_file():
        if (folder / OLD_CHECKPOINT_FILE).exists():
            raise InputFileError(
                folder / OLD_CHECKPOINT_FILE,
                "a checkpoint of an older zmpkit (a pickle, which can run code when opened); "
                "this zmpkit no longer opens it: start the fit again without --resume",
            )
        what = "no checkpoint here" if folder.is_dir() else "not a folder"
        raise InputFileError(
            path if folder.is_dir() else folder,
            f"{what}; expected the folder of an earlier 'zmpkit identify sim' run (its --out)",
        )
    try:
        doc = json.loads(path.read_bytes().decode("utf-8"))
    except OSError as exc:
        raise InputFileError(path, f"cannot read it: {exc.strerror or exc}") from None
    except (ValueError, RecursionError) as exc:  # JSON or UTF-8 errors, nesting too deep
        raise damaged(path, f"not JSON ({one_line(exc)})") from None
    if not isinstance(doc, dict):
        raise damaged(path, "expected a JSON object of a zmpkit fit checkpoint")
    _check_format(doc, path)
    return doc


def _check_format(doc: dict[str, Any], path: Path) -> None:
    tag = doc.get("format")
    if tag != CHECKPOINT_FORMAT:
        older = isinstance(tag, str) and tag.startswith("zmpkit-simfit-checkpoint/")
        what = "of another zmpkit version" if older else "not a zmpkit fit checkpoint"
        shown = repr(tag) if isinstance(tag, str) and len(tag) <= 40 else type(tag).__name__
        raise InputFileError(
            path,
            f"{what} (format {shown}); this zmpkit reads {CHECKPOINT_FORMAT!r}: "
            "start the fit again without --resume",
        )
    if set(doc) != _KEYS:
        missing, unknown = sorted(_KEYS - set(doc)), sorted(set(doc) - _KEYS)
        what = f"lacks the key {missing[0]!r}" if missing else f"unknown key {unknown[0][:_ECHO]!r}"
        raise damaged(path, what)
    if doc["cma"] != CMA_VERSION:
        raise InputFileError(
            path,
            f"written with cma {echo(doc['cma'], 20)} (this Python has cma {CMA_VERSION}, whose "
            "state differs): resume under that cma or start the fit again",
        )


def _from_data(doc: dict[str, Any], arrays: ArrayFile, where: Path) -> Checkpoint:
    fingerprint = doc["fingerprint"]
    if not isinstance(fingerprint, dict) or not _depth(fingerprint, 4):
        raise damaged(where, "expected an object of the fit's settings", key="fingerprint")
    counts = {k: doc[k] for k in ("generation", "restart", "run_start", "best_restart")}
    for key, value in counts.items():
        if type(value) is not int or not 0 <= value <= 2**31:
            raise damaged(where, "expected an integer >= 0", key=key)
    if counts["run_start"] > counts["generation"] or counts["restart"] > _MAX_RUNS:
        raise damaged(where, "run_start after generation, or restart over 64")
    if counts["best_restart"] > counts["restart"]:
        raise damaged(where, "best_restart after restart")
    random = doc["random"]
    if not isinstance(random, dict) or set(random) != {"draws", "global"}:
        raise damaged(where, "expected keys draws and global", key="random")
    draws = np.random.RandomState()  # cma's randn option: its state is set below
    strategy = rebuild_strategy(doc["strategy"], arrays, draws, where)
    draws.set_state(generator_state(random["draws"], arrays, "random.draws", where))
    rng_state = generator_state(random["global"], arrays, "random.global", where)
    best_unit, best_cost, best_run_std = _best(doc["best_run_std"], arrays, int(strategy.N))
    history = history_from_json(doc["history"], counts["generation"], where)
    return Checkpoint(
        fingerprint,
        strategy,
        draws,
        rng_state,
        counts["generation"],
        best_unit,
        best_cost,
        history,
        counts["restart"],
        counts["run_start"],
        counts["best_restart"],
        best_run_std,
    )


def _best(
    run_std: object, arrays: ArrayFile, n: int
) -> tuple[list[float], float, list[float] | None]:
    unit = arrays.take("fit.best_unit", (n,))
    if not np.all((unit >= 0.0) & (unit <= 1.0)):
        raise arrays.error("fit.best_unit", "expected numbers in [0, 1]")
    cost = float(arrays.take("fit.best_cost", ()))
    if not cost >= 0.0:
        raise arrays.error("fit.best_cost", "expected a cost >= 0")
    if run_std is None:
        return unit.tolist(), cost, None
    std = arrays.take(run_std, (n,))
    if not np.all(np.isfinite(std) & (std >= 0.0)):
        raise arrays.error(str(run_std), "expected finite numbers >= 0")
    return unit.tolist(), cost, std.tolist()


def _short(value: object) -> str | None:
    text = echo(value, 1000)
    return text if len(text) <= _ECHO and "..." not in text else None


def _depth(value: object, limit: int) -> bool:
    """Whether ``value`` (parsed JSON) nests no deeper than ``limit`` lists and objects."""
    level: list[object] = [value]
    for _ in range(limit + 1):
        level = [
            v
            for x in level
            if isinstance(x, list | dict)
            for v in (x.values() if isinstance(x, dict) else x)
        ]
        if not level:
            return True
    return False


def _same_robot_file(saved: object, current: object) -> bool:
    """Whether a saved robot reference is a relative path to the robot file ``current`` names.

    A fit records its robot's :attr:`~zmpkit.robots.robot.Robot.source` (a robot file's
    absolute path); checkpoints from before recorded the path as typed, which is found
    again from the folder the fit ran in.
    """
    if not isinstance(saved, str) or not isinstance(current, str) or not saved:
        return False
    return Path(current).is_absolute() and Path(saved).resolve() == Path(current)


def check_fingerprint(saved: dict[str, Any], current: dict[str, Any], folder: Path) -> None:
    """Refuse to resume a checkpoint of another fit.

    ``current`` is compared as JSON holds it (tuples as lists).

    Raises:
        ParameterError: naming the settings that differ.
    """
    current = json.loads(json.dumps(current))
    keys = sorted(set(saved) | set(current))
    differ = [k for k in keys if saved.get(k) != current.get(k)]
    if "robot" in differ and _same_robot_file(saved.get("robot"), current.get("robot")):
        differ.remove("robot")
    if differ:
        parts = []
        for k in differ[:3]:
            there, now, name = _short(saved.get(k)), _short(current.get(k)), k[:_ECHO]
            both = there is not None and now is not None
            parts.append(f"{name}: {there} there, {now} now" if both else f"different {name}")
        more = f"; {len(differ) - 3} more" if len(differ) > 3 else ""
        detail = "; ".join(parts) + more
        raise ParameterError(f"cannot resume {folder}: it is another fit ({detail})")
