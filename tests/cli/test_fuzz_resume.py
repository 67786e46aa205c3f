"""Fuzzing ``zmpkit identify sim --resume``: damaged, truncated, mistyped, non-finite and
hostile checkpoints.

Each case damages a genuine checkpoint (:class:`helpers.checkpoints.Damage`: JSON values of
the wrong type or NaN, keys missing or unknown, arrays with NaN or infinity, of the wrong
shape or dtype, missing or extra, object arrays and pickles that would create a marker file,
truncated or random files, compressed members, a stale SHA-256) and resumes it. The data
folder does not exist, so a checkpoint the damage left valid ends at the data instead: every
case must end with exit 2, one short line and no output folder, and the marker must never
appear. The fast test runs a bounded number of cases in the default suite; the slow one
runs thousands.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings

from helpers.checkpoints import Damage, damage, json_paths, read_pair, write_fit
from helpers.fuzz import Census, problems, run_cli

_SETTINGS = {
    "deadline": None,
    "database": None,
    "derandomize": True,
    "suppress_health_check": [HealthCheck.too_slow, HealthCheck.data_too_large],
}


@pytest.fixture(scope="module")
def genuine(tmp_path_factory: pytest.TempPathFactory) -> tuple[dict, dict]:
    """(JSON document, arrays) of a sphere fit's checkpoint: run 1 of two, mid-run."""
    folder = tmp_path_factory.mktemp("genuine")
    write_fit(folder, n=3, generations=3, popsize=5, restarts=1, seed=2)
    return read_pair(folder)


def _resume_case(genuine: tuple[dict, dict], case: Damage, census: Census) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        folder, marker, out = root / "fit", root / "marker", root / "out"
        folder.mkdir()
        case.write(*genuine, folder, marker)
        argv = ["identify", "sim", str(root / "data"), "--resume", str(folder)]
        outcome = run_cli([*argv, "--out", str(out)])
        found = problems(outcome, out, root)
        if outcome.code != 2:
            found.append(f"exit code {outcome.code}, not 2")
        if len(outcome.stderr.strip().splitlines()) != 1:
            found.append(f"{len(outcome.stderr.strip().splitlines())} lines on stderr")
        if marker.exists():
            found.append("pickle ran: the marker file exists")
        census.record(found, case)


def _run(genuine: tuple[dict, dict], examples: int, name: str) -> Census:
    census = Census(name)
    doc, arrays = genuine
    strategy = damage(json_paths(doc), sorted(arrays))

    @settings(max_examples=examples, **_SETTINGS)
    @given(strategy)
    def fuzz(case: Damage) -> None:
        _resume_case(genuine, case, census)

    fuzz()
    return census


@pytest.mark.slow
def test_fuzz_resume_fast(genuine: tuple[dict, dict]) -> None:
    census = _run(genuine, 60, "identify sim --resume (fast)")
    assert census.cases >= 60
    assert census.bad == 0, census.summary()


@pytest.mark.slow
def test_fuzz_resume_many(genuine: tuple[dict, dict]) -> None:
    census = _run(genuine, 2000, "identify sim --resume")
    assert census.cases >= 2000
    assert census.bad == 0, census.summary()
