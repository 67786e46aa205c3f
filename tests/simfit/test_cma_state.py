"""A ``cma`` strategy rebuilt from its plain data asks, tells and stops bit for bit as the one
it was written from, and holds every attribute the saved one did (but caches and logs).

Each case runs a strategy for ``cut`` generations, writes it (:func:`strategy_data`, through
JSON text and ``.npz`` bytes as a checkpoint does), rebuilds it, then runs both on until
``cma`` stops them or 400 generations: every candidate, step size, mean, covariance and stop
dictionary must be identical. The costs: a multimodal one whose minimum lies inside the
bounds, one beyond them (candidates pile on a bound, ``cma`` rescales coordinates) and one
of plateaus (``tolflatfitness``); populations 4 and 5 exercise ``cma``'s selective mirrors.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from zmpkit.simfit.checkpoint_data import ArrayFile, npz_bytes, read_arrays
from zmpkit.simfit.cma_state import new_strategy, rebuild_strategy, strategy_data


def rastrigin(u: np.ndarray) -> float:
    """Rastrigin's function around u = 0.3, >= 0 [-]."""
    x = (np.asarray(u) - 0.3) * 10.24
    return float(10 * x.size + np.sum(x**2 - 10 * np.cos(2 * np.pi * x)))


def beyond(u: np.ndarray) -> float:
    """A sphere centred outside the bounds, at 1.3 [-]."""
    return float(np.sum((np.asarray(u) - 1.3) ** 2))


def plateaus(u: np.ndarray) -> float:
    """A sphere rounded to 0.01: flat steps [-]."""
    return float(np.round(np.sum((np.asarray(u) - 0.5) ** 2), 2))


COSTS: dict[str, Callable[[np.ndarray], float]] = {
    "rastrigin": rastrigin,
    "beyond": beyond,
    "plateaus": plateaus,
}


def _run(es: Any, cost: Callable, generations: int) -> list[bytes | str]:
    """What the strategy does next: its stop dictionary, candidates and new distribution."""
    trail: list[bytes | str] = []
    for _ in range(generations):
        stop = es.stop()
        trail.append(repr(sorted(stop.items())))
        if stop:
            break
        candidates = es.ask()
        trail.append(np.asarray(candidates).tobytes())
        es.tell(candidates, [cost(x) for x in candidates])
        trail.append(np.float64(es.sigma).tobytes() + es.mean.tobytes() + es.sm.C.tobytes())
    return trail


def _cut(n: int, popsize: int | None, cut: int, cost: Callable) -> tuple[Any, Any] | None:
    """(the strategy after ``cut`` generations, its sampler), or None if it stopped first."""
    draws = np.random.RandomState(7)
    np.random.seed(11)  # noqa: NPY002 - cma may draw from the global generator
    es = new_strategy(np.linspace(0.2, 0.8, n), 0.2, popsize, draws)
    for k in range(cut):
        if k and es.stop():
            return None
        candidates = es.ask()
        es.tell(candidates, [cost(x) for x in candidates])
    return es, draws


def _rebuilt(es: Any, tmp_path: Path) -> Any:
    """``es`` written as a checkpoint writes it, then rebuilt (a fresh ``RandomState``)."""
    doc, arrays = strategy_data(es)
    doc = json.loads(json.dumps(doc))
    npz = tmp_path / "strategy.npz"
    npz.write_bytes(npz_bytes(arrays))
    meta = {"file": npz.name, "sha256": hashlib.sha256(npz.read_bytes()).hexdigest()}
    arrays_file = read_arrays(npz, {**meta, "names": sorted(arrays)}, tmp_path / "c.json")
    return rebuild_strategy(doc, arrays_file, np.random.RandomState(), tmp_path / "c.json")


CASES = [
    (2, None, "rastrigin", 1),
    (2, 4, "beyond", 5),
    (3, 5, "rastrigin", 20),
    (3, 6, "plateaus", 9),
    (5, None, "beyond", 30),
    (12, None, "rastrigin", 3),
]
SLOW_CASES = [
    (n, popsize, cost, cut)
    for n, popsize in ((2, None), (2, 4), (3, 5), (3, 6), (5, None), (12, None), (4, 40))
    for cost in COSTS
    for cut in (1, 2, 3, 7, 20, 60, 150)
]


def _check_continues(n: int, popsize: int | None, cost_name: str, cut: int, tmp: Path) -> None:
    cost = COSTS[cost_name]
    start = _cut(n, popsize, cut, cost)
    if start is None:
        return  # cma stopped the run before the cut: nothing to resume
    es, draws = start
    rebuilt = _rebuilt(es, tmp)
    rebuilt.opts["randn"].__self__.set_state(draws.get_state())
    outer = np.random.get_state()  # noqa: NPY002
    expected = _run(es, cost, 400)
    np.random.set_state(outer)  # noqa: NPY002
    got = _run(rebuilt, cost, 400)
    assert len(got) == len(expected)
    first = next((k for k, (a, b) in enumerate(zip(got, expected, strict=True)) if a != b), None)
    assert first is None, f"differs at step {first} of {len(expected)}"


@pytest.mark.parametrize(("n", "popsize", "cost", "cut"), CASES)
@pytest.mark.slow
def test_a_rebuilt_strategy_continues_bit_for_bit(
    n: int, popsize: int | None, cost: str, cut: int, tmp_path: Path
) -> None:
    _check_continues(n, popsize, cost, cut, tmp_path)


@pytest.mark.slow
def test_every_rebuilt_strategy_continues_bit_for_bit(tmp_path: Path) -> None:
    for n, popsize, cost, cut in SLOW_CASES:
        _check_continues(n, popsize, cost, cut, tmp_path)


NOT_STATE = {
    "opts", "inopts", "inputargs", "_es_opts", "randn", "eigenmethod", "integer_centering",
    "logger", "timer", "more_to_write",  # options (the same), logging, wall time
    "_tell2_args", "_stopdict",  # the last tell's arguments; stop() recomputes its dictionary
    "_parameters", "bounds_tf",  # caches keyed by their inputs; the bounds' lazy expansion
    "_stall_sigma_change_on_divergence_events", "data", "data_with_same_key",  # records
    "_round_integer_variables",  # rounding of integer variables: a fit has none
}  # fmt: skip


def leaves(obj: Any, prefix: str = "", out: dict | None = None, seen: set | None = None) -> dict:
    """Every attribute of a strategy and of the ``cma`` objects it holds, by dotted path."""
    out = {} if out is None else out
    seen = set() if seen is None else seen
    seen.add(id(obj))
    for name, value in vars(obj).items():
        path = f"{prefix}{name}"
        if name in NOT_STATE or id(value) in seen:
            continue
        if type(value).__module__.startswith("cma") and hasattr(value, "__dict__"):
            leaves(value, path + ".", out, seen)
        elif isinstance(value, np.ndarray):
            out[path] = (value.dtype.str, value.shape, value.tobytes())
        elif isinstance(value, list | range):  # lists by value: cma reads their numbers
            out[path] = [float(x) if np.isscalar(x) else np.asarray(x).tobytes() for x in value]
        else:
            out[path] = (type(value).__name__, repr(value))
    return out


@pytest.mark.parametrize(("n", "popsize", "cost", "cut"), CASES[1:4])
def test_a_rebuilt_strategy_holds_every_attribute_of_the_saved_one(
    n: int, popsize: int | None, cost: str, cut: int, tmp_path: Path
) -> None:
    start = _cut(n, popsize, cut, COSTS[cost])
    assert start is not None
    saved, rebuilt = leaves(start[0]), leaves(_rebuilt(start[0], tmp_path))
    differ = sorted(p for p in set(saved) | set(rebuilt) if saved.get(p) != rebuilt.get(p))
    assert differ == []


def test_an_array_file_hands_each_array_out_once(tmp_path: Path) -> None:
    arrays = ArrayFile(tmp_path / "a.npz", {"x": np.zeros(3), "y": np.ones(2)})
    assert arrays.take("x", (3,)).shape == (3,)
    with pytest.raises(ValueError, match=r"a\.npz: lacks the array 'x' \(damaged\)"):
        arrays.take("x", (3,))
    with pytest.raises(ValueError, match=r"a\.npz: holds an unknown array 'y'"):
        arrays.finish()
