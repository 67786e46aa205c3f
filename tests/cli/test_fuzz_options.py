"""Fuzzing the options of every command that simulates: ranges are checked at the boundary.

The pipelines are replaced by a stub that stops the run where the work would start, so a
case takes milliseconds: it either ends with exit 2 and one line (and no output folder), or
reaches the stub, and then every physical option must lie in its physical range (the
oracle below, written from the robots' numbers, not from the code under test).
"""

from __future__ import annotations

import contextlib
import math
import tempfile
from collections.abc import Iterator
from pathlib import Path
from unittest import mock

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from helpers.fuzz import Census, problems, run_cli

_SETTINGS = {
    "deadline": None,
    "database": None,
    "derandomize": True,
    "suppress_health_check": [HealthCheck.too_slow],
}
TEO_SOLES_M = {"sagittal": (-0.07, 0.175), "frontal": (-0.1985, 0.1985)}  # heel/toe, outer edges
NAO_MAX_STEP_M = 0.12  # the walking pattern's longest step (StepLimits)
CLAMPED_SPEED_FACTOR = 2.0  # commands up to twice the longest step per step walk shortened


class StubReachedError(Exception):
    """Raised by the stub where the pipeline's work would start."""


def _reached(*args: object, **kwargs: object) -> None:
    raise StubReachedError


_STUBS = (
    "zmpkit.cli.walk.run_walk",
    "zmpkit.cli.walk.run_walk_compensate",
    "zmpkit.cli.sim.run_sim_push",
    "zmpkit.cli.balance.run_balance",
    "zmpkit.cli.identify.run_identify_balance",
    "zmpkit.pipelines.identify_sim.FitProblem",
    "zmpkit.pipelines.identify_sim.record_experiments",
)


@contextlib.contextmanager
def stubbed() -> Iterator[None]:
    with contextlib.ExitStack() as stack:
        for target in _STUBS:
            stack.enter_context(mock.patch(target, _reached))
        yield


def value() -> st.SearchStrategy[str]:
    """An option value as typed: plain, negative, zero, huge, tiny, non-finite or text."""
    return st.one_of(
        st.sampled_from(("0", "-1", "0.2", "0.5", "1", "2", "5", "15", "1e9", "1e-300", "3e-2")),
        st.sampled_from(("nan", "inf", "-inf", "abc", "", "1,5", "-0")),
        st.floats(-1e4, 1e4).map(lambda x: f"{x:.4g}"),
        st.integers(-5, 300).map(str),
    )


def targets() -> st.SearchStrategy[str]:
    """``--targets`` as typed: ranges and lists, in and out of reach."""
    number = st.sampled_from(("0", "0.01", "0.05", "0.1", "0.17", "0.2", "0.5", "-0.05", "-0.1"))
    return st.one_of(
        st.tuples(number, number, st.sampled_from(("0.01", "0.1", "0", "-0.1"))).map(":".join),
        st.lists(number, min_size=1, max_size=3).map(",".join),
        value(),
    )


def _float(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        return math.nan


def _in(text: str | None, low: float, high: float, default: float, open_low: bool = False) -> bool:
    x = default if text is None else _float(text)
    return math.isfinite(x) and (low < x if open_low else low <= x) and x <= high


def _targets_in_reach(text: str, plane: str) -> bool:
    low, high = TEO_SOLES_M[plane]
    if ":" in text:
        start, stop, step = (_float(v) for v in text.split(":"))
        if not (step > 0 and stop >= start):
            return False
        values = [start + k * step for k in range(int((stop - start) / step + 1e-9) + 1)]
    else:
        values = [_float(v) for v in text.split(",")]
    return all(low < v < high for v in values)


def _population_fits(popsize: str | None, restarts: str | None) -> bool:
    """IPOP doubles the population at each restart: the last run's must be <= 65,536."""
    first = 8 if popsize is None else _float(popsize)
    return first * 2 ** _float(restarts or "0") <= 65_536


def physical(command: str, options: dict[str, str]) -> bool:
    """Whether the oracle accepts the options' physical values."""
    o = options.get
    if command == "walk":
        step = _float(o("--step-duration", "0.5"))
        fastest = CLAMPED_SPEED_FACTOR * NAO_MAX_STEP_M / step
        return (
            _in(o("--step-duration"), 0.2, 2.0, 0.5)
            and _in(o("--speed"), 0.0, fastest, 0.2)
            and _in(o("--lateral-speed"), -fastest, fastest, 0.0)
            and _in(o("--turn-rate"), -2.0, 2.0, 0.0)
            and _in(o("--duration"), step, 3600.0, 10.0)
        )
    if command == "walk compensate":
        step = _float(o("--step-duration", "0.5"))
        fastest = CLAMPED_SPEED_FACTOR * NAO_MAX_STEP_M / step
        return (
            _in(o("--step-duration"), 0.2, 2.0, 0.5)
            and _in(o("--speed"), 0.0, fastest, 0.2, open_low=True)
            and _in(o("--workers"), 1, 256, 2)
        )
    if command == "sim push":
        push = (o("--push-force") is None) == (o("--push-duration") is None)
        return (
            push
            and _in(o("--hold"), 0.0, 600.0, 15.0, open_low=True)
            and _in(o("--push-force"), -2000.0, 2000.0, 0.0)
            and _in(o("--push-duration"), 0.0, 10.0, 1.0, open_low=True)
            and _in(o("--workers"), 1, 256, 2)
            and _targets_in_reach(o("--targets", "0:0.10:0.01"), o("--plane", "sagittal"))
        )
    if command == "identify balance":
        return _in(o("--mass"), 0.0, 1000.0, 1.0, open_low=True) and _in(
            o("--length"), 0.0, 5.0, 1.0, open_low=True
        )
    if command == "identify sim":
        return (
            _in(o("--generations"), 1, 100_000, 40)
            and _in(o("--popsize"), 4, 65_536, 8)
            and _in(o("--restarts"), 0, 9, 0)
            and _in(o("--workers"), 1, 256, 2)
            and _population_fits(o("--popsize"), o("--restarts"))
        )
    return _in(o("--workers"), 1, 256, 2)  # balance


COMMANDS: dict[str, tuple[str, ...]] = {
    "walk": (
        "--speed",
        "--step-duration",
        "--lateral-speed",
        "--turn-rate",
        "--duration",
        "--seed",
    ),
    "walk compensate": ("--speed", "--workers", "--seed"),
    "sim push": ("--targets", "--hold", "--push-force", "--push-duration", "--workers", "--seed"),
    "identify balance": ("--mass", "--length"),
    "identify sim": ("--generations", "--popsize", "--restarts", "--workers", "--seed"),
    "balance": ("--workers", "--seed"),
}


@st.composite
def command_line(draw: st.DrawFn) -> tuple[str, dict[str, str]]:
    command = draw(st.sampled_from(sorted(COMMANDS)))
    names = draw(st.lists(st.sampled_from(COMMANDS[command]), max_size=3, unique=True))
    options = {n: draw(targets() if n == "--targets" else value()) for n in names}
    if command == "sim push" and draw(st.booleans()):
        options["--plane"] = draw(st.sampled_from(("sagittal", "frontal")))
    return command, options


def _case(command: str, options: dict[str, str], census: Census) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        argv = command.split()
        if command == "identify balance":
            (root / "data").mkdir()
            argv.append(str(root / "data"))
        if command == "identify sim":
            argv.append(str(root / "missing"))
        for name, text in options.items():
            argv.append(f"{name}={text}")
        out = root / "out"
        with stubbed():
            outcome = run_cli([*argv, "--out", str(out)])
        if isinstance(outcome.exception, StubReachedError):
            found = [] if physical(command, options) else ["accepted outside the physical range"]
        else:
            found = problems(outcome, out, root)
        census.record(found, (command, options))


def _run(examples: int, name: str) -> Census:
    census = Census(name)

    @settings(max_examples=examples, **_SETTINGS)
    @given(command_line())
    def fuzz(case: tuple[str, dict[str, str]]) -> None:
        _case(*case, census)

    fuzz()
    return census


@pytest.mark.slow
def test_fuzz_options_fast() -> None:
    census = _run(150, "options (fast)")
    assert census.cases >= 150
    assert census.bad == 0, census.summary()


@pytest.mark.slow
def test_fuzz_options_many() -> None:
    census = _run(3000, "options")
    assert census.cases >= 3000
    assert census.bad == 0, census.summary()
