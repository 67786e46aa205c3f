"""Fuzzing ``zmpkit zmp``: malformed logs, feet files, column maps and thresholds.

Every generated case must end well in the sense of :mod:`helpers.fuzz`: exit 0 with only
finite numbers written, or exit 2 with one short line and no output folder. The fast test
runs a bounded number of cases in the default suite; the slow one runs thousands.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings

from helpers.ft_data import FEET_YAML
from helpers.fuzz import Census, problems, run_cli
from helpers.fuzz_inputs import CsvCase, column_map_yaml, feet_yaml, ft_log_csv, threshold_option
from zmpkit.io import FT_LOG_COLUMNS

_SETTINGS = {
    "deadline": None,
    "database": None,
    "derandomize": True,
    "suppress_health_check": [HealthCheck.too_slow, HealthCheck.data_too_large],
}


def _zmp_case(
    log: CsvCase, feet: str, columns: str | None, threshold: str | None, census: Census
) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        (root / "log.csv").write_bytes(log.data)
        (root / "feet.yaml").write_text(feet, encoding="utf-8", errors="surrogatepass")
        argv = ["zmp", str(root / "log.csv"), "--feet", str(root / "feet.yaml")]
        if columns is not None:
            (root / "columns.yaml").write_text(columns, encoding="utf-8")
            argv += ["--columns", str(root / "columns.yaml")]
        if threshold is not None:
            argv += ["--contact-threshold", threshold]
        out = root / "out"
        outcome = run_cli([*argv, "--out", str(out)])
        census.record(problems(outcome, out, root), (log, feet, columns, threshold))


def _run(examples: int, name: str) -> Census:
    census = Census(name)

    @settings(max_examples=examples, **_SETTINGS)
    @given(ft_log_csv(), feet_yaml(), column_map_yaml(), threshold_option())
    def fuzz(log: CsvCase, feet: str, columns: str | None, threshold: str | None) -> None:
        _zmp_case(log, feet, columns, threshold, census)

    fuzz()
    return census


@pytest.mark.slow
def test_fuzz_zmp_fast() -> None:
    census = _run(120, "zmp (fast)")
    assert census.cases >= 120
    assert census.bad == 0, census.summary()


@pytest.mark.slow
def test_fuzz_zmp_many() -> None:
    census = _run(3000, "zmp")
    assert census.cases >= 3000
    assert census.bad == 0, census.summary()


def test_tiny_thresholds_with_tiny_forces_never_write_non_finite() -> None:
    header = ",".join(FT_LOG_COLUMNS).encode()
    log = CsvCase(header + b"\n0.0,0,0,-1e-300,1,1,0,0,0,0,0,0,0\n", ("tiny F_z",))
    census = Census("tiny threshold")
    for threshold in ("1e-300", "5e-324", "1e-30", "0.001"):
        _zmp_case(log, FEET_YAML, None, threshold, census)
    assert census.cases == 4
    assert census.bad == 0, census.summary()
