"""The ``cma`` strategy of a fit as plain data, and a strategy rebuilt from it.

A checkpoint holds no Python object: :func:`strategy_data` writes a
``cma.CMAEvolutionStrategy`` as its construction (initial mean, step size, population
option) and the entries of its state (:data:`~zmpkit.simfit.cma_entries.STATE`): a JSON
document of integers and flags plus named arrays. :func:`rebuild_strategy` builds a new
strategy from the construction and sets the state onto it, so it asks and tells exactly as
the saved one would have (bit for bit).

What is kept: the distribution (mean, step size, covariance and its eigen-decomposition,
coordinate scaling, evolution paths), the step-size adaptation, the counters, the last
generation's candidates and costs, directions it left for the next one (mirrors), the cost
histories the stop criteria read, and the best solution. What is not kept is rebuilt
identically from the construction, or is never read back: ``cma``'s options (the ``randn``
option is the fit's own ``RandomState``, :func:`new_strategy`), the recombination weights
and constants, the bound transformation and the caches keyed by their own inputs, the stop
dictionary (recomputed at the next ``stop()``: the optimiser writes its checkpoint before
it asks), the timer, the logger and its extra columns.

Which entries a strategy has depends on the ``cma`` version, so a checkpoint resumes only
under the version that wrote it (:data:`CMA_VERSION`), and reading it requires exactly the
entries a strategy of that construction has after one generation (a throwaway probe).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import cma
import numpy as np
from numpy.typing import NDArray

from zmpkit.simfit.checkpoint_data import ArrayFile, damaged, one_line
from zmpkit.simfit.cma_entries import STATE, decode_entry, encode_entry

__all__ = [
    "CMA_VERSION",
    "MAX_DIMENSION",
    "MAX_POPSIZE",
    "new_strategy",
    "rebuild_strategy",
    "strategy_data",
]

CMA_VERSION: str = str(cma.__version__).split()[0]
"""The ``cma`` version running here; a checkpoint records the one that wrote it."""
MAX_POPSIZE = 65_536
"""Largest population of any run, restarts included (a GPU batch of 64 k worlds)."""
MAX_DIMENSION = 1000
"""Most fitted parameters a checkpoint may hold (a 1000 × 1000 covariance is 8 MB)."""


def new_strategy(mean: NDArray[np.float64], sigma0: float, popsize: int | None, draws: Any) -> Any:
    """A ``cma`` strategy in [0, 1]^n sampling through ``draws`` (a ``RandomState``).

    Args:
        mean: initial mean, normalised [-].
        sigma0: initial step size, normalised [-].
        popsize: candidates per generation; None = ``cma``'s 4 + 3 ln n.
        draws: the ``RandomState`` whose ``randn`` the strategy samples with.
    """
    opts: dict[str, Any] = {"bounds": [0.0, 1.0], "seed": np.nan, "randn": draws.randn}
    opts["verbose"] = -9
    if popsize is not None:
        opts["popsize"] = popsize
    return cma.CMAEvolutionStrategy(np.asarray(mean, dtype=float).tolist(), sigma0, opts)


def _resolve(obj: Any, path: str) -> tuple[Any, str]:
    """(the object holding attribute ``path``'s last name, that name)."""
    *parents, name = path.split(".")
    for parent in parents:
        obj = getattr(obj, parent)
    return obj, name


def _lookup(es: Any, path: str) -> tuple[bool, Any]:
    """(whether ``es`` has attribute ``path``, its value)."""
    try:
        holder, name = _resolve(es, path)
    except AttributeError:
        return False, None
    return hasattr(holder, name), getattr(holder, name, None)


def strategy_data(es: Any) -> tuple[dict[str, Any], dict[str, NDArray[Any]]]:
    """The strategy as (JSON document, arrays named ``strategy.*``).

    Call it after a ``tell`` and before the next ``stop()``, as the optimiser does:
    ``stop()`` counts flat generations once per iteration, and a rebuilt strategy checks
    its criteria afresh. Before its first ``tell`` a strategy is its construction alone
    (``state`` null).
    """
    popsize = getattr(es, "inopts", {}).get("popsize")  # the option given, None: the default
    doc: dict[str, Any] = {"popsize": popsize, "state": None}
    arrays: dict[str, NDArray[Any]] = {
        "strategy.x0": np.array(es.x0, dtype=float),
        "strategy.sigma0": np.asarray(np.float64(es.sigma0)),
    }
    if int(es.countiter) == 0:
        return doc, arrays
    state: dict[str, Any] = {}
    saved: dict[int, str] = {}
    for path in STATE:
        present, value = _lookup(es, path)
        if present:  # else an attribute this cma version lacks
            state[path] = encode_entry(path, value, int(es.N), arrays, saved)
    doc["state"] = state
    return doc, arrays


def _construction(doc: dict[str, Any], arrays: ArrayFile, where: Path) -> tuple[Any, Any, Any]:
    """(x0, sigma0, popsize option) of the saved strategy, checked."""
    x0 = arrays.take("strategy.x0", (-1,))
    if not 1 <= x0.size <= MAX_DIMENSION or not np.all((x0 >= 0.0) & (x0 <= 1.0)):
        raise arrays.error("strategy.x0", f"expected 1 to {MAX_DIMENSION} numbers in [0, 1]")
    sigma0 = float(arrays.take("strategy.sigma0", ()))
    if not 0.0 < sigma0 < np.inf:
        raise arrays.error("strategy.sigma0", "expected a positive finite step size")
    popsize = doc["popsize"]
    if popsize is not None and (type(popsize) is not int or not 2 <= popsize <= MAX_POPSIZE):
        raise damaged(
            where, f"expected null or an integer in [2, {MAX_POPSIZE}]", key="strategy.popsize"
        )
    return x0, sigma0, popsize


def _quiet(call: Callable[[], Any], where: Path) -> Any:
    """Run ``call``, ``cma`` on a checkpoint's construction, keeping NumPy's global state.

    Any failure of ``cma`` there is the checkpoint's: an :class:`~zmpkit.errors.InputFileError`.
    """
    outer = np.random.get_state()  # noqa: NPY002 - cma draws from the legacy global generator
    try:
        return call()
    except Exception as exc:  # cma on numbers read from a file: whatever it raises
        message = f"cma cannot build its strategy ({one_line(exc)})"
        raise damaged(where, message, key="strategy") from None
    finally:
        np.random.set_state(outer)  # noqa: NPY002


def _probe(x0: NDArray[np.float64], sigma0: float, popsize: int | None) -> Any:
    """A strategy of the same construction after one generation: what its state holds."""
    probe = new_strategy(x0, sigma0, popsize, np.random.RandomState(0))
    candidates = probe.ask()  # costs around x0: the step size shrinks, no limit is met
    probe.tell(candidates, [float(np.sum((np.asarray(c) - x0) ** 2)) for c in candidates])
    return probe


def rebuild_strategy(doc: object, arrays: ArrayFile, draws: Any, where: Path) -> Any:
    """The strategy :func:`strategy_data` described, sampling through ``draws``.

    Args:
        doc: the strategy's JSON document.
        arrays: the checkpoint's arrays.
        draws: the ``RandomState`` it samples with (the caller sets its state).
        where: the JSON file, for messages.

    Raises:
        InputFileError: on any entry missing, unknown, of the wrong type or shape, or
            outside what is valid.
    """
    if not isinstance(doc, dict) or set(doc) != {"popsize", "state"}:
        raise damaged(where, "expected keys popsize and state", key="strategy")
    x0, sigma0, popsize = _construction(doc, arrays, where)
    es = _quiet(lambda: new_strategy(x0, sigma0, popsize, draws), where)
    state = doc["state"]
    if state is None:
        return es
    if not isinstance(state, dict):
        raise damaged(where, "expected null or an object", key="strategy.state")
    probe = _quiet(lambda: _probe(x0, sigma0, popsize), where)
    _check_entries(state, probe, where)
    restored: dict[str, Any] = {}
    sizes = (int(es.N), int(es.sp.popsize))
    for path in STATE:
        if path in state:
            like = _lookup(probe, path)[1]
            value = decode_entry(path, state[path], like, restored, arrays, where, sizes)
            try:
                holder, name = _resolve(es, path)
            except AttributeError:  # an entry of another cma version's strategy
                raise damaged(where, f"{path!r} is not this cma's", key="strategy.state") from None
            setattr(holder, name, value)
            restored[path] = value
    for name, value in vars(probe).items():  # what a first generation creates besides its
        if not hasattr(es, name):  # state (the timer, scratch lists): the probe's, unread
            setattr(es, name, value)
    return es


def _check_entries(state: dict[str, Any], probe: Any, where: Path) -> None:
    unknown = sorted(set(state) - set(STATE))
    if unknown:
        raise damaged(where, f"unknown entry {unknown[0][:60]!r}", key="strategy.state")
    missing = [p for p in STATE if p not in state and _lookup(probe, p)[0]]
    if missing:
        raise damaged(where, f"lacks the entry {missing[0]!r}", key="strategy.state")
