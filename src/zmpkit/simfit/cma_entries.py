"""The entries of a ``cma`` strategy's state a checkpoint keeps, each as plain data.

:data:`STATE` names every attribute of a ``cma.CMAEvolutionStrategy`` (by dotted path) that
changes as it runs and that its next ``ask``/``tell``/``stop`` reads, with its kind: how it
is stored and what is valid. :func:`encode_entry` writes one value as JSON (integers,
flags, null) or as a named array with its Python type; :func:`decode_entry` reads it back,
checked, as that same type. Kinds, with n the parameters and λ the population:

- ``int``, ``bool``: in the JSON (``{"int64": k}`` for a NumPy integer);
- ``float``, ``positive``, ``cost``: 0-d arrays, typed ``float``, ``float64`` or ``int``;
- ``vec``, ``positive_vec`` (n), ``scaling`` (1 or n, positive); ``symmetric``,
  ``orthonormal``, ``mat`` (n × n); ``pop`` (λ × n); ``directions`` (k × n, a list of
  vectors); ``costs``, ``index`` (λ); ``cost_list``, ``bool_list``, ``int_list`` (any
  length).

Numbers must be finite, except costs, which may be +inf (a rollout whose error
overflowed) but never NaN or negative. The sampler's facts are checked too: positive step
size and axis lengths, a symmetric covariance, orthonormal eigenvectors, the sort order a
permutation of the candidates. Lists come back as lists of Python numbers (``cma`` reads
them by value).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from zmpkit.simfit.checkpoint_data import ArrayFile, damaged, echo

__all__ = ["STATE", "decode_entry", "encode_entry"]

_MAX_INT = 2**53


class _Spec(NamedTuple):
    kind: str
    none_ok: bool = False  # cma may hold None there
    low: int = 0  # the smallest valid integer


def _each(spec: _Spec, *paths: str) -> dict[str, _Spec]:
    return dict.fromkeys(paths, spec)


_INT, _POSITIVE, _COST = _Spec("int"), _Spec("positive"), _Spec("cost")
_VEC, _POS_VEC, _BOOL = _Spec("vec"), _Spec("positive_vec"), _Spec("bool")

STATE: dict[str, _Spec] = {
    # the distribution N(mean, sigma^2 diag(s) C diag(s)), C = B diag(D^2) B^T; sm.* first:
    # the strategy's own C, B and D are the same arrays
    "sigma": _POSITIVE,
    "_sigma_old": _POSITIVE,
    **_each(_VEC, "mean", "mean_after_tell", "mean_old", "mean_old_old", "pc", "pc2", "pc_neg"),
    "_isotropic_mean_shift": _VEC,
    "_isotropic_mean_shift_iteration": _Spec("int", low=-1),
    "dC": _POS_VEC,
    "sm.C": _Spec("symmetric"),
    "sm.B": _Spec("orthonormal"),
    "sm.D": _POS_VEC,
    "sm._inverse_root_C": _Spec("mat", none_ok=True),
    **_each(_INT, "sm.count_tell", "sm.count_eigen", "sm.last_update"),
    "sm._corr_condition": _POSITIVE,
    "sm._corr_condition_count_eigen": _INT,
    "sm._beta_diagonal_acceleration": _POSITIVE,
    "C": _Spec("symmetric"),
    "B": _Spec("orthonormal"),
    "D": _POS_VEC,
    "sigma_vec.scaling": _Spec("scaling"),
    "sigma_vec.dim": _Spec("int", low=1),
    "sigma_vec.is_identity": _BOOL,
    # step-size adaptation (cumulative, CSA)
    "adapt_sigma.ps": _VEC,
    **_each(_POSITIVE, "adapt_sigma.delta", "adapt_sigma._last_multiplier", "adapt_sigma.cs"),
    **_each(_POSITIVE, "adapt_sigma.damps", "adapt_sigma.max_delta_log_sigma"),
    "adapt_sigma._ps_updated_iteration": _Spec("int", low=-1),
    **_each(_BOOL, "adapt_sigma.is_initialized", "adapt_sigma.disregard_length_setting"),
    # counters and bookkeeping
    **_each(_INT, "countiter", "countevals", "itereigenupdated", "count_eigen"),
    **_each(_INT, "number_of_solutions_asked", "number_of_injections_delivered"),
    **_each(_INT, "number_of_injections", "evaluations_per_f_value", "_mirrormethod1_done"),
    "_flgtelldone": _BOOL,
    **_each(_INT, "sent_solutions.last_iteration", "sent_solutions.last_solution_index"),
    **_each(_INT, "archive.last_iteration", "archive.last_solution_index"),
    # the last generation: candidates, sorted, and their costs; what the next one injects
    **_each(_Spec("pop"), "ary", "pop_sorted"),
    **_each(_Spec("directions"), "pop_injection_directions", "pop_injection_solutions"),
    "_indices_of_selective_mirrors": _Spec("int_list"),
    "_is_independent_sample": _Spec("bool_list"),
    "hsiglist": _Spec("int_list"),
    **_each(_Spec("costs"), "fit.fit", "fit.bndpen", "fit.fit_plus_pen"),
    "fit.idx": _Spec("index"),
    # cost histories of the stop criteria (tolfun, tolstagnation, tolflatfitness)
    **_each(_Spec("cost_list"), "fit.hist", "fit.histbest", "fit.histmedian"),
    **_each(_COST, "fit.median", "fit.median0", "fit.median_min", "fit.median_previous"),
    **_each(_INT, "fit.median_got_worse", "fit.flatfit_iterations"),
    **_each(_INT, "_stoptolxstagnation.count", "_stoptolxstagnation.count_x"),
    "_stoptolxstagnation.x": _VEC,
    # the best solution so far
    **_each(_Spec("vec", none_ok=True), "best.x", "best.x_geno", "best.last.x"),
    **_each(_COST, "best.f", "best.last.f"),
    **_each(_Spec("int", none_ok=True), "best.evals", "best.evalsall"),
    "best.compared": _INT,
}
"""Every entry of a strategy's state a checkpoint keeps, by attribute path, and its kind."""

_SCALARS = ("float", "positive", "cost")
_COSTS = ("cost", "costs", "cost_list")
_TYPES = {  # the Python types a kind may be held as, by the name the JSON gives them
    **dict.fromkeys(_SCALARS, ("float", "float64", "int")),
    **dict.fromkeys(("costs", "cost_list"), ("list", "ndarray")),
    **dict.fromkeys(("bool_list", "directions"), ("list",)),
    "int_list": ("list", "range"),
}
_DTYPES = {"bool_list": np.bool_, "index": np.int64, "int_list": np.int64}


def _type_name(value: object) -> str:
    if isinstance(value, np.floating):
        return "float64"
    if isinstance(value, int | np.integer):
        return "int"
    return type(value).__name__


def encode_entry(
    path: str, value: Any, n: int, arrays: dict[str, NDArray[Any]], saved: dict[int, str]
) -> Any:
    """One entry as JSON; its numbers, if any, go into ``arrays`` as ``strategy.<path>``.

    ``saved`` maps the id of each array already written to its path: an entry holding the
    same array is written as ``{"same_as": path}``.
    """
    kind = STATE[path].kind
    if value is None or kind == "bool":
        return None if value is None else bool(value)
    if kind == "int":
        return int(value) if type(value) is int else {"int64": int(value)}
    if isinstance(value, np.ndarray) and id(value) in saved:
        return {"same_as": saved[id(value)]}
    name = f"strategy.{path}"
    numbers = list(value) if isinstance(value, range) else value
    array: NDArray[Any] = np.array(numbers, dtype=_DTYPES.get(kind, np.float64))
    arrays[name] = array.reshape(-1, n) if kind == "directions" else array
    saved[id(value)] = path
    return {"array": name, "type": _type_name(value)}


def decode_entry(
    path: str,
    entry: object,
    like: Any,
    restored: dict[str, Any],
    arrays: ArrayFile,
    where: Path,
    sizes: tuple[int, int],
) -> Any:
    """One entry's value as ``cma`` held it, checked.

    Args:
        path: the entry's attribute path.
        entry: its JSON.
        like: the entry in a strategy of the same construction and ``cma`` after one
            generation, or None: a list there must come back as a list (``cma`` appends to
            it), an array as an array.
        restored: the entries decoded so far (``same_as`` names one of them).
        arrays: the checkpoint's arrays.
        where: the JSON file, for messages.
        sizes: (n, λ).

    Raises:
        InputFileError: naming the entry, on anything :data:`STATE` does not allow.
    """
    spec, key = STATE[path], f"strategy.state.{path}"
    if entry is None:
        if not spec.none_ok:
            raise damaged(where, "is null; expected a value", key=key)
        return None
    if spec.kind in ("int", "bool"):
        return _json_value(spec, entry, where, key)
    if isinstance(entry, dict) and set(entry) == {"same_as"}:
        target = entry["same_as"]
        known = isinstance(target, str) and restored.get(target) is not None
        if not known or STATE[target] != spec:
            raise damaged(where, "names no earlier entry of its kind", key=key)
        return restored[target]
    if not isinstance(entry, dict) or set(entry) != {"array", "type"}:
        raise damaged(where, 'expected {"array": NAME, "type": TYPE}', key=key)
    kind, name, type_name = spec.kind, entry["array"], entry["type"]
    allowed = _TYPES.get(kind, ("ndarray",))
    if like is not None and kind not in _SCALARS:
        allowed = (_type_name(like),)
    if type_name not in allowed:
        expected = " or ".join(allowed)
        raise damaged(where, f"type {echo(type_name, 24)}; expected {expected}", key=key)
    array = arrays.take(name, _shape(kind, arrays, name, *sizes), _DTYPES.get(kind, np.float64))
    _check_values(kind, array, arrays, str(name))
    return _as_type(array, type_name, arrays, str(name))


def _json_value(spec: _Spec, value: object, where: Path, key: str) -> Any:
    if spec.kind == "bool":
        if type(value) is not bool:
            raise damaged(where, "expected true or false", key=key)
        return value
    wide = isinstance(value, dict) and set(value) == {"int64"}
    number = value["int64"] if isinstance(value, dict) and wide else value
    if type(number) is not int or not spec.low <= number <= _MAX_INT:
        raise damaged(where, f"expected an integer >= {spec.low}", key=key)
    return np.int64(number) if wide else number


def _shape(kind: str, arrays: ArrayFile, name: object, n: int, lam: int) -> tuple[int, ...]:
    if kind in _SCALARS:
        return ()
    if kind in ("symmetric", "orthonormal", "mat"):
        return (n, n)
    if kind == "scaling":  # a scalar until cma first rescales a coordinate
        return () if arrays.ndim(name) == 0 else (n,)
    if kind in ("cost_list", "bool_list", "int_list"):
        return (-1,)
    return {"pop": (lam, n), "directions": (-1, n), "costs": (lam,), "index": (lam,)}.get(
        kind, (n,)
    )


def _check_values(kind: str, array: NDArray[Any], arrays: ArrayFile, name: str) -> None:
    """Refuse values ``cma`` would choke on (module docstring)."""
    if kind == "bool_list":
        return
    if kind in ("index", "int_list"):
        if kind == "index" and not np.array_equal(np.sort(array), np.arange(array.size)):
            raise arrays.error(name, "expected a permutation of the candidates' indices")
        if np.any(array < 0):
            raise arrays.error(name, "expected counts >= 0")
        return
    if kind in _COSTS:
        if not np.all(array >= 0.0):  # NaN fails too
            raise arrays.error(name, "holds NaN or a negative cost; expected costs >= 0")
        return
    if not np.all(np.isfinite(array)):
        raise arrays.error(name, "holds NaN or infinity; expected finite numbers")
    if kind in ("positive", "positive_vec", "scaling") and not np.all(array > 0.0):
        raise arrays.error(name, "expected positive numbers")
    scale = float(np.max(np.abs(array))) if array.size else 0.0
    if kind == "symmetric" and not np.allclose(array, array.T, rtol=0.0, atol=1e-9 * scale):
        raise arrays.error(name, "expected a symmetric covariance matrix")
    if kind == "orthonormal" and not np.allclose(array.T @ array, np.eye(len(array)), atol=1e-6):
        raise arrays.error(name, "expected orthonormal eigenvectors")


def _as_type(array: NDArray[Any], type_name: str, arrays: ArrayFile, name: str) -> Any:
    """``array`` as the Python type ``cma`` held: a number, a list, a range or an array."""
    if type_name == "float":
        return float(array)
    if type_name == "float64":
        return np.float64(array)
    if type_name == "int":
        if not (np.isfinite(array) and float(array) == np.round(array)):
            raise arrays.error(name, "typed int but not a whole number")
        return int(array)
    if type_name == "range":
        start = int(array[0]) if array.size else 0
        if not np.array_equal(array, np.arange(start, start + array.size)):
            raise arrays.error(name, "typed range but not consecutive integers")
        return range(start, start + array.size)
    if type_name == "list":
        return [row.copy() for row in array] if array.ndim == 2 else array.tolist()
    return np.array(array)
