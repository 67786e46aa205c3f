"""The Ray backend, run live on local Ray instances: the serial backend's costs exactly, a
clean close, Ctrl-C cancels the pending tasks, a wrong address fails fast."""

from __future__ import annotations

import socket
import time
from collections.abc import Iterator
from types import SimpleNamespace

import pytest

ray = pytest.importorskip("ray")

from helpers.simfit_data import record_walk, small_case  # noqa: E402
from zmpkit.errors import ParameterError  # noqa: E402
from zmpkit.robots.registry import get_robot  # noqa: E402
from zmpkit.simfit.backends import RayEvaluator, make_evaluator  # noqa: E402
from zmpkit.simfit.experiments import read_experiments  # noqa: E402
from zmpkit.simfit.problem import FitProblem  # noqa: E402

NAO = get_robot("nao")

CANDIDATES = [[0.7, 1200.0], [0.8, 1500.0], [0.36, 310.0]]
"""pid_gain_scale [-], gear_stiffness [N·m/rad] of the small case."""


@pytest.fixture(scope="module")
def problem(tmp_path_factory: pytest.TempPathFactory) -> FitProblem:
    params, doc, _ = small_case()
    folder = record_walk(tmp_path_factory.mktemp("simfit_ray"))
    return FitProblem(NAO, "M,G,S", params, doc, tuple(read_experiments([folder], NAO)))


@pytest.fixture
def no_ray() -> None:
    if ray.is_initialized():
        ray.shutdown()


@pytest.fixture
def callers_ray(no_ray: None) -> Iterator[None]:
    """Ray initialised by the caller, as a user of the library might."""
    ray.init(num_cpus=2, include_dashboard=False)
    yield
    ray.shutdown()


@pytest.mark.usefixtures("callers_ray")
@pytest.mark.slow
def test_ray_costs_equal_serial_costs_and_ctrl_c_cancels(problem: FitProblem) -> None:
    serial = make_evaluator(problem, "serial").costs(CANDIDATES)
    evaluator = make_evaluator(problem, "ray")
    try:
        assert evaluator.costs(CANDIDATES) == serial
        assert evaluator.costs(CANDIDATES[:1]) == serial[:1]
        cancelled: list[object] = []

        def interrupted_get(refs: list[object]) -> None:
            raise KeyboardInterrupt

        real = evaluator._ray
        evaluator._ray = SimpleNamespace(get=interrupted_get, cancel=cancelled.append)
        with pytest.raises(KeyboardInterrupt):
            evaluator.costs(CANDIDATES)
        assert len(cancelled) == len(CANDIDATES) * len(problem.experiments)
        evaluator._ray = real
    finally:
        evaluator.close()
    assert ray.is_initialized()  # the caller's Ray is left running
    with pytest.raises(ParameterError, match="closed"):
        evaluator.costs(CANDIDATES)


@pytest.mark.slow  # starts a second Ray instance: ~6 s, the module ~22 s with it
@pytest.mark.usefixtures("no_ray")
def test_private_instance_stops_on_close(problem: FitProblem) -> None:
    evaluator = RayEvaluator(problem, address=None)
    assert ray.is_initialized()
    evaluator.close()
    assert not ray.is_initialized()
    evaluator.close()  # twice is harmless


@pytest.mark.usefixtures("no_ray")
def test_address_where_nothing_listens_fails_fast(problem: FitProblem) -> None:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    start = time.perf_counter()
    with pytest.raises(ParameterError, match=rf"no Ray cluster at --address 127.0.0.1:{port}"):
        make_evaluator(problem, "ray", address=f"127.0.0.1:{port}")
    assert time.perf_counter() - start < 10.0
    assert not ray.is_initialized()


@pytest.mark.usefixtures("no_ray")
def test_bad_address_format_is_a_parameter_error(problem: FitProblem) -> None:
    with pytest.raises(ParameterError, match="cannot join Ray at address 'nonsense'"):
        make_evaluator(problem, "ray", address="nonsense")
