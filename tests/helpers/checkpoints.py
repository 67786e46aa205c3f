"""Checkpoints to damage: a cheap fit (CMA-ES on a sphere, no simulation), and payloads.

:func:`write_fit` runs the real optimiser (:func:`~zmpkit.simfit.optimizer.run_cma`) with
:class:`SphereEvaluator`, so its folder holds a genuine ``checkpoint.json`` and
``checkpoint.npz``; :func:`rewrite` writes a changed document and arrays back, consistent
(the JSON records the new arrays' SHA-256) unless asked otherwise. :class:`Trap` pickles to a
payload that creates a marker file when unpickled: a checkpoint holding it must never be
unpickled.
"""

from __future__ import annotations

import hashlib
import io
import json
import pickle
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from hypothesis import strategies as st

from zmpkit.robots.fit_parameter import FitParameter
from zmpkit.robots.registry import get_robot
from zmpkit.simfit.checkpoint import ARRAYS_FILE, CHECKPOINT_FILE
from zmpkit.simfit.cost import CostTerms
from zmpkit.simfit.optimizer import CmaOptions, CmaResult, run_cma
from zmpkit.simfit.parameters import ParameterValues
from zmpkit.simfit.problem import FitProblem

TARGET = 0.7
"""Where the sphere's minimum is, in every parameter [-]."""


class SphereEvaluator:
    """One experiment whose cost is the squared distance to :data:`TARGET` (joint term)."""

    def costs(self, candidates: Sequence[ParameterValues]) -> list[list[CostTerms]]:
        d = [float(np.linalg.norm(np.asarray(c, dtype=float) - TARGET)) for c in candidates]
        return [[CostTerms(x, 0.0, 0.0, 1.0, 0.0)] for x in d]

    def close(self) -> None:
        """Nothing to release."""


def sphere_problem(n: int = 3) -> FitProblem:
    """n parameters in [0, 1] starting at 0.3, no experiments (the evaluator is the cost)."""
    params = tuple(FitParameter(f"x{i}", f"x{i}", 0.3, 0.0, 1.0, "-") for i in range(n))
    return FitProblem(get_robot("nao"), "M", params, {}, ())


def write_fit(folder: Path, n: int = 3, resume: Path | None = None, **options: Any) -> CmaResult:
    """Run the sphere fit into ``folder`` (CmaOptions ``options``); its checkpoint stays."""
    problem, options_ = sphere_problem(n), CmaOptions(**options)
    return run_cma(problem, SphereEvaluator(), options_, folder, resume=resume)


def read_pair(folder: Path) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
    """(the checkpoint's JSON document, its arrays)."""
    doc = json.loads((folder / CHECKPOINT_FILE).read_text())
    with np.load(folder / ARRAYS_FILE, allow_pickle=False) as npz:
        return doc, {name: npz[name] for name in npz.files}


def npz_of(arrays: dict[str, Any]) -> bytes:
    """The arrays as ``.npz`` bytes, as ``numpy.savez`` writes them (object arrays pickled)."""
    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    return buffer.getvalue()


def rewrite(
    folder: Path, doc: dict[str, Any], npz: bytes, *, rehash: bool = True, names: bool = True
) -> None:
    """Write ``doc`` and ``npz`` as the checkpoint of ``folder``.

    With ``rehash`` the JSON records the new bytes' SHA-256, with ``names`` their members,
    so a reader gets past the consistency check to the values.
    """
    doc = json.loads(json.dumps(doc))
    if rehash and isinstance(doc.get("arrays"), dict):
        doc["arrays"]["sha256"] = hashlib.sha256(npz).hexdigest()
        if names:
            try:
                with np.load(io.BytesIO(npz), allow_pickle=False) as loaded:
                    doc["arrays"]["names"] = sorted(loaded.files)
            except Exception:  # a broken npz: keep the names the document had
                pass
    (folder / CHECKPOINT_FILE).write_text(json.dumps(doc, indent=1))
    (folder / ARRAYS_FILE).write_bytes(npz)


class Trap:
    """Unpickling it creates ``marker`` (``open(marker, "w")``): proof that code ran.

    Args:
        marker: the file unpickling creates.
    """

    def __init__(self, marker: Path) -> None:
        self.marker = str(marker)

    def __reduce__(self) -> tuple[Any, ...]:
        return (open, (self.marker, "w"))


def trap_payload(marker: Path) -> bytes:
    """A pickle that creates ``marker`` when loaded."""
    return pickle.dumps({"format": "zmpkit-simfit-checkpoint/1", "checkpoint": Trap(marker)})


def trap_npz(arrays: dict[str, Any], name: str, marker: Path) -> bytes:
    """``arrays`` with ``name`` replaced by an object array holding a :class:`Trap`."""
    hostile = np.empty(1, dtype=object)
    hostile[0] = Trap(marker)
    return npz_of({**arrays, name: hostile})


WRONG_VALUES: tuple[Any, ...] = (
    "x", "", -1, 0, 1, 1.5, 2**63, 10**30, None, True, False, [], {}, [1, 2], {"a": 1},
    float("nan"), float("inf"), float("-inf"), "zmpkit-simfit-checkpoint/1",
    {"array": "strategy.mean", "type": "ndarray"}, {"same_as": "mean"}, {"int64": 5},
    {"array": "strategy.mean", "type": "list"}, [[[[[]]]]],
)  # fmt: skip
"""Values a damaged or hand-edited checkpoint may hold where another belongs."""


def json_paths(doc: Any, prefix: tuple = (), depth: int = 6) -> list[tuple]:
    """Paths to every value of ``doc`` (lists: their first three items), outermost first."""
    paths = [prefix] if prefix else []
    if depth == 0:
        return paths
    if isinstance(doc, dict):
        for key, value in doc.items():
            paths += json_paths(value, (*prefix, key), depth - 1)
    elif isinstance(doc, list):
        for k, value in enumerate(doc[:3]):
            paths += json_paths(value, (*prefix, k), depth - 1)
    return paths


def _at(doc: Any, path: tuple) -> tuple[Any, Any]:
    """(the container holding ``path``'s last step, that step), or (None, None)."""
    for step in path[:-1]:
        try:
            doc = doc[step]
        except (KeyError, IndexError, TypeError):
            return None, None
    if isinstance(doc, dict) and path[-1] in doc:
        return doc, path[-1]
    if isinstance(doc, list) and isinstance(path[-1], int) and path[-1] < len(doc):
        return doc, path[-1]
    return None, None


def _array_change(array: np.ndarray, how: str, where: float) -> Any:
    if array.dtype.kind not in "biuf":  # an object or text array an earlier step put there
        return array
    flat = array.reshape(-1).copy()
    k = int(where * flat.size) if flat.size else 0
    if how in ("nan", "inf", "-inf", "negative", "huge"):
        value = {"nan": np.nan, "inf": np.inf, "-inf": -np.inf, "negative": -1.0}.get(how, 1e308)
        if not flat.size:
            return np.full((*array.shape[:-1], 1) if array.ndim else (1,), value)
        if flat.dtype.kind == "f":
            flat[k] = value
        else:
            flat = flat.astype(float)
            flat[k] = value
        return flat.reshape(array.shape)
    changes = {
        "int": lambda: array.astype(np.int64),
        "float32": lambda: array.astype(np.float32),
        "bool": lambda: array.astype(bool),
        "complex": lambda: array.astype(complex),
        "text": lambda: np.array(["abc"] * max(array.size, 1)),
        "drop": lambda: flat[:-1] if array.ndim < 2 else array[:, :-1],
        "axis": lambda: array[None, ...],
        "scalar": lambda: np.float64(1.0),
        "empty": lambda: np.zeros((0,)),
        "zeros": lambda: np.zeros_like(array),
        "random": lambda: np.random.default_rng(int(where * 1e6)).random(array.shape),
    }
    return changes[how]()


DELETE = "<delete>"
"""The value of a ``json`` step that deletes the key or item."""


class Damage:
    """Steps that damage a genuine checkpoint, applied in order by :meth:`write`.

    Steps on the content: ``("json", path, value)`` (value :data:`DELETE` deletes),
    ``("add", path)`` (an unknown key), ``("array", name, how, where)``, ``("drop", name)``,
    ``("extra",)``, ``("object", name)`` (an object array holding a :class:`Trap`),
    ``("compress",)``, ``("unhashed",)`` (the JSON keeps the old SHA-256). Steps on the
    written files: ``("bytes", file, data)``, ``("pickle", file)`` (a :class:`Trap`
    payload), ``("truncate", file, fraction)``, ``("delete", file)``.

    Args:
        steps: the steps, as :func:`damage` draws them.
    """

    def __init__(self, steps: Sequence[tuple[Any, ...]]) -> None:
        self.steps = tuple(steps)

    def __repr__(self) -> str:
        return f"Damage({self.steps!r})"

    def write(self, doc: dict, arrays: dict, folder: Path, marker: Path) -> None:
        """Write the damaged checkpoint into ``folder`` (a payload would create ``marker``)."""
        doc, arrays = json.loads(json.dumps(doc)), dict(arrays)
        for kind, *args in self.steps:
            self._content(kind, args, doc, arrays, marker)
        kinds = {step[0] for step in self.steps}
        npz = npz_of(arrays)
        if "compress" in kinds:
            packed = io.BytesIO()
            np.savez_compressed(packed, **arrays)
            npz = packed.getvalue()
        rewrite(folder, doc, npz, rehash="unhashed" not in kinds)
        for kind, *args in self.steps:
            path = folder / args[0] if args and isinstance(args[0], str) else folder
            if kind == "bytes":
                path.write_bytes(args[1])
            elif kind == "pickle":
                path.write_bytes(trap_payload(marker))
            elif kind == "truncate" and path.exists():
                data = path.read_bytes()
                path.write_bytes(data[: int(args[1] * len(data))])
            elif kind == "delete":
                path.unlink(missing_ok=True)

    @staticmethod
    def _content(kind: str, args: list, doc: dict, arrays: dict, marker: Path) -> None:
        if kind in ("json", "add"):
            container, step = _at(doc, args[0])
            if container is None:
                return
            if kind == "add":
                if isinstance(container[step], dict):
                    container[step]["zz"] = 1
            elif args[1] == DELETE:
                del container[step]
            else:
                container[step] = args[1]
        elif kind == "array" and args[0] in arrays:
            arrays[args[0]] = _array_change(np.asarray(arrays[args[0]]), args[1], args[2])
        elif kind == "drop":
            arrays.pop(args[0], None)
        elif kind == "extra":
            arrays["extra"] = np.zeros(2)
        elif kind == "object":
            hostile = np.empty(1, dtype=object)
            hostile[0] = Trap(marker)
            arrays[args[0]] = hostile


FILES = ("checkpoint.json", "checkpoint.npz", "checkpoint.pkl")
HOW = ("nan", "inf", "-inf", "negative", "huge", "int", "float32", "bool", "complex", "text")
HOW += ("drop", "axis", "scalar", "empty", "zeros", "random")


@st.composite
def damage(draw: st.DrawFn, paths: Sequence[tuple], names: Sequence[str]) -> Damage:
    """One to three damaging steps (:class:`Damage`) on a checkpoint with these JSON paths
    and array names."""
    steps = []
    for _ in range(draw(st.integers(1, 3))):
        kind = draw(st.sampled_from(
            ("json", "json", "json", "add", "array", "array", "array", "drop", "extra",
             "object", "compress", "unhashed", "bytes", "pickle", "truncate", "delete")
        ))  # fmt: skip
        if kind == "json":
            value = draw(st.sampled_from((*WRONG_VALUES, DELETE)))
            steps.append((kind, draw(st.sampled_from(paths)), value))
        elif kind == "add":
            steps.append((kind, draw(st.sampled_from(paths))))
        elif kind == "array":
            how, where = draw(st.sampled_from(HOW)), draw(st.floats(0.0, 0.999))
            steps.append((kind, draw(st.sampled_from(names)), how, where))
        elif kind in ("drop", "object"):
            steps.append((kind, draw(st.sampled_from(names))))
        elif kind == "bytes":
            steps.append((kind, draw(st.sampled_from(FILES[:2])), draw(st.binary(max_size=64))))
        elif kind in ("pickle", "delete"):
            steps.append((kind, draw(st.sampled_from(FILES))))
        elif kind == "truncate":
            steps.append((kind, draw(st.sampled_from(FILES[:2])), draw(st.floats(0.0, 0.99))))
        else:
            steps.append((kind,))
    return Damage(steps)
