"""The fit's simulated sensors as expected readings: no noise, no quantisation, the
deterministic chain kept; the fit's fingerprint tells the two apart; bad values are one line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from zmpkit.errors import ParameterError
from zmpkit.pipelines.identify_sim import IdentifySimConfig
from zmpkit.robots.registry import get_robot
from zmpkit.simfit.experiments import read_experiments
from zmpkit.simfit.optimizer import CmaOptions, fingerprint
from zmpkit.simfit.parameters import default_parameters
from zmpkit.simfit.problem import FitProblem, simulate
from zmpkit.simfit.truth_doc import (
    EXPECTED_READINGS_ZEROED,
    base_truth_path,
    expected_readings,
    load_robot_truth,
    load_truth_doc,
)

NAO = get_robot("nao")


@pytest.fixture(scope="module")
def nao_walk_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from helpers.simfit_data import record_walk

    return record_walk(tmp_path_factory.mktemp("expected_readings_walk"))


@pytest.mark.parametrize("robot", ["nao", "teo", "op3"])
def test_only_the_random_and_quantising_parts_are_zeroed(robot: str) -> None:
    doc = load_truth_doc(base_truth_path(get_robot(robot), None))
    out = expected_readings(doc)
    for key, value in doc.get("sensors", {}).items():
        if key not in EXPECTED_READINGS_ZEROED:
            assert out["sensors"][key] == value, key  # offsets, gain, filter, rate kept
    sensors = load_robot_truth(
        get_robot(robot), out
    ).sensors  # the op3's file has no sensors section
    for key in EXPECTED_READINGS_ZEROED:
        assert np.all(np.asarray(getattr(sensors, key)) == 0.0), key
    assert {k: v for k, v in out.items() if k != "sensors"} == {
        k: v for k, v in doc.items() if k != "sensors"
    }
    assert doc == load_truth_doc(base_truth_path(get_robot(robot), None))  # the input is untouched


@pytest.mark.slow
def test_expected_encoders_are_not_quantised(nao_walk_folder: Path) -> None:
    experiments = tuple(read_experiments([nao_walk_folder], NAO))
    params = default_parameters(NAO, "M")
    doc = load_truth_doc(base_truth_path(NAO, None))
    resolution = float(doc["sensors"]["encoder_resolution"])
    values = [p.nominal for p in params]
    runs = {}
    for readings in ("sampled", "expected"):
        problem = FitProblem(NAO, "M,S", params, doc, experiments, sensor_readings=readings)
        runs[readings] = simulate(problem, values, 0).q_meas_rad
    quanta = runs["sampled"] / resolution
    np.testing.assert_allclose(quanta, np.round(quanta), atol=1e-6)  # whole quanta
    off_grid = np.abs(runs["expected"] / resolution - np.round(runs["expected"] / resolution))
    assert np.mean(off_grid > 1e-3) > 0.9  # the angle itself
    # within half a quantum (and the noise-free F-T's effect on the walk) of each other
    assert np.max(np.abs(runs["expected"] - runs["sampled"])) < 0.05


def test_the_fit_knows_which_readings_it_ran_with() -> None:
    params = default_parameters(NAO, "M")
    doc = load_truth_doc(base_truth_path(NAO, None))
    sampled = FitProblem(NAO, "M,S", params, doc, ())
    expected = FitProblem(NAO, "M,S", params, doc, (), sensor_readings="expected")
    options = CmaOptions()
    assert "sensor_readings" not in fingerprint(sampled, options)  # old checkpoints resume
    assert fingerprint(expected, options)["sensor_readings"] == "expected"


def test_bad_sensor_readings_name_the_valid_ones(tmp_path: Path, capsys) -> None:
    with pytest.raises(ParameterError, match="sensor readings must be one of sampled, expected"):
        IdentifySimConfig(self_test=True, sensor_readings="mean")
    with pytest.raises(ParameterError, match="got 'mean'"):
        FitProblem(NAO, "M", (), {}, (), sensor_readings="mean")
    from zmpkit.cli import main

    code = main(
        ["identify", "sim", "--self-test", "--sensor-readings", "mean", "--out", str(tmp_path)]
    )
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1
    assert "sampled" in err
    assert "expected" in err
