"""The robustness matrix, and the same matrix scaled to a smaller robot."""

from __future__ import annotations

import pytest

from zmpkit.experiments.robustness import PUSH_FORCES_N, robustness_matrix
from zmpkit.pipelines.walk_sweep import SweepConfig


def test_the_matrix_holds_116_cases_a_controller_at_paper_b_s_figures() -> None:
    cases = robustness_matrix(("zmpip", "dcm"))
    assert len(cases) == 232
    zmpip = [c for c in cases if c.controller == "zmpip"]
    assert sorted({c.push_n for c in zmpip if c.push_n}) == list(PUSH_FORCES_N)
    assert max(c.speed_mps for c in zmpip) == 0.3
    assert {c.speed_mps for c in zmpip if c.push_n or c.fault or c.turn_rad_s} == {0.2}
    assert len({c.key for c in zmpip}) == 116  # every case its own row


@pytest.mark.slow
def test_a_robot_is_judged_on_its_own_speed_and_pushes_per_kilogram() -> None:
    """The OP3 walks at 0.1 m/s and weighs about 3.2 kg against paper B's robot's 0.2 m/s and
    5.3 kg: its matrix walks at half the speeds, pushed with the same force per kilogram."""
    nao, op3 = SweepConfig(robot="nao"), SweepConfig(robot="op3")
    assert [c.key for c in nao.full_matrix()] == [c.key for c in robustness_matrix(nao.controllers)]
    mass = {
        name: float(config.robot.ik_model().body_subtreemass[0])
        for name, config in (("nao", nao), ("op3", op3))
    }
    scaled = op3.full_matrix()
    assert len(scaled) == 3 * 116
    pushes = sorted({c.push_n for c in scaled if c.push_n})
    assert pushes == pytest.approx([f * mass["op3"] / mass["nao"] for f in PUSH_FORCES_N], abs=0.01)
    speeds = sorted({c.speed_mps for c in scaled if not (c.lateral_mps or c.push_n or c.fault)})
    assert speeds == pytest.approx([0.025, 0.05, 0.075, 0.1, 0.125, 0.15])
    assert {abs(c.lateral_mps) for c in scaled if c.lateral_mps} == {0.025}
