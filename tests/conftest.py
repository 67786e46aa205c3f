"""Fixtures and hooks shared by every test; shared helper functions are in ``helpers/``."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

from helpers.ft_data import FEET_YAML


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Skip the tests marked ``needs_warp`` where MuJoCo Warp is not installed."""
    if importlib.util.find_spec("mujoco_warp") is not None:
        return
    skip = pytest.mark.skip(reason="needs MuJoCo Warp: pip install 'zmpkit[gpu]'")
    for item in items:
        if item.get_closest_marker("needs_warp") is not None:
            item.add_marker(skip)


@pytest.fixture
def feet_yaml(tmp_path: Path) -> Path:
    path = tmp_path / "feet.yaml"
    path.write_text(FEET_YAML)
    return path


_WORKER_CENSUSES_KEY = "fuzz_censuses"


def pytest_sessionfinish(session: pytest.Session) -> None:
    """On a pytest-xdist worker, hand this worker's fuzz censuses to the controller."""
    workeroutput = getattr(session.config, "workeroutput", None)
    if workeroutput is None:  # not a worker
        return
    from helpers.fuzz import CENSUSES

    workeroutput[_WORKER_CENSUSES_KEY] = [census.as_plain() for census in CENSUSES]


def pytest_testnodedown(node, error) -> None:
    """On the xdist controller, take in the censuses a finished worker counted."""
    from helpers.fuzz import Census

    for plain in getattr(node, "workeroutput", {}).get(_WORKER_CENSUSES_KEY, ()):
        Census.from_plain(plain)


def pytest_terminal_summary(terminalreporter) -> None:
    """Print each fuzz test's case count and bad endings (the issue asks CI to show them).

    Run in parallel (pytest-xdist), the workers' counts reach the controller through
    :func:`pytest_testnodedown`.
    """
    from helpers.fuzz import CENSUSES

    if not CENSUSES:
        return
    terminalreporter.section("fuzz census")
    for census in sorted(CENSUSES, key=lambda c: c.name):
        terminalreporter.write_line(census.summary())
        for cause, example in census.examples.items():
            terminalreporter.write_line(f"  {cause}: {example}")
    total = sum(c.cases for c in CENSUSES)
    bad = sum(c.bad for c in CENSUSES)
    terminalreporter.write_line(f"total: {total} fuzzed cases, {bad} ended badly")
