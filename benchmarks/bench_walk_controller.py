"""Benchmark of one walking-controller tick (10 ms motion frame) against the open-loop step.

Usage::

    python benchmarks/bench_walk_controller.py [--json PATH] [--number N]

Measures in one run, with :mod:`timeit` (best of several repeats), in µs per call, on the
virtual NAO standing in its first walking pose (sensor readings from the simulator):

1. the baseline: :meth:`OpenLoopWalk.step` (a row of the planned trajectory);
2. the kinematic state estimator alone (forward kinematics, CoM, ZMP from the F-T wrenches);
3. each feedback law on top of the estimate: ZMP/IP (observer + preview) and DCM;
4. the same with the step adjustment at work (its trigger at 0: the capture step solved,
   the swing re-planned every tick), in a frame of single support;
5. a whole feedback tick: estimator, law and the whole-body IK of the frame (mink, QP).

The target for a tick's estimator and law is 30 µs. Speed is reported, never asserted.
"""

from __future__ import annotations

from typing import Any

from harness import base_parser, best_of, environment, print_table, write_json
from zmpkit.experiments.walk import sensor_layout
from zmpkit.experiments.walk_trial import read_measurement, start_pose
from zmpkit.robots.registry import get_robot
from zmpkit.walking import GaitParameters, PatternConfig, WalkCommand, generate_pattern
from zmpkit.walking.ik import solve_walking_ik
from zmpkit.walking.measurement import WalkMeasurement
from zmpkit.walking.step_adjustment import StepAdjustmentParameters
from zmpkit.walking.walk_controllers import DcmWalk, OpenLoopWalk, ZmpIpWalk

__all__ = ["main"]

REPEATS = 5
TARGET_US = 30.0


def run(number: int) -> dict[str, Any]:
    """All timings of the module docstring [µs]."""
    pattern = generate_pattern(
        PatternConfig(
            command=WalkCommand(v_x=0.2),
            duration_s=2.0,
            gait=GaitParameters(step_duration_s=0.5),
        )
    )
    robot = get_robot("nao")
    model, settings = robot.ik_model(), robot.ik_settings
    trajectory = solve_walking_ik(pattern, model, settings)
    sim = robot.make_simulation("all", None, seed=0)
    start_pose(sim, trajectory)
    layout = sensor_layout(sim, settings.sole_sites)
    measurement = WalkMeasurement.empty(sim.joint_names, tuple(layout.sole_sites))
    read_measurement(sim, measurement)
    open_loop = OpenLoopWalk(trajectory)
    zmpip = ZmpIpWalk(pattern, model, settings, layout, sim.joint_names)
    dcm = DcmWalk(pattern, model, settings, layout, sim.joint_names)
    soles = zmpip._soles[10]
    frame = 11

    def estimate() -> None:
        zmpip.estimator.update(measurement, soles)

    def zmpip_law() -> None:
        zmpip.estimator.update(measurement, soles)
        zmpip._correct(frame)

    def dcm_law() -> None:
        dcm.estimator.update(measurement, soles)
        dcm._correct(frame)

    def zmpip_tick() -> None:
        zmpip.step(frame, measurement)

    always = StepAdjustmentParameters(trigger_dcm_error_m=(0.0, 0.0))
    stepping = {
        "zmpip": ZmpIpWalk(pattern, model, settings, layout, sim.joint_names, stepping=always),
        "dcm": DcmWalk(pattern, model, settings, layout, sim.joint_names, stepping=always),
    }
    swing = 125  # a frame of single support (the first swing: frames 111-150)
    for walk in stepping.values():
        walk.ik.set_targets = lambda *a: None  # type: ignore[method-assign]
        walk.ik.solve = lambda *a: None  # type: ignore[method-assign]
        for k in range(1, swing):
            walk.step(k, measurement)

    def stepping_law(name: str) -> None:
        walk = stepping[name]
        walk.estimator.update(measurement, walk._soles[swing - 1])
        com, velocity = walk.estimator.com_in_world, walk.estimator.com_velocity_in_world
        w = walk.omega
        walk.stepping.update(swing, swing - 1, com[0] + velocity[0] / w, com[1] + velocity[1] / w)
        walk._correct(swing)

    def us(stmt, n: int) -> float:
        return best_of(stmt, n, REPEATS) * 1e6

    results = {
        "open_step_us": us(lambda: open_loop.step(frame, measurement), number),
        "estimator_us": us(estimate, number // 10),
        "zmpip_law_us": us(zmpip_law, number // 10),
        "dcm_law_us": us(dcm_law, number // 10),
        "zmpip_stepping_law_us": us(lambda: stepping_law("zmpip"), number // 10),
        "dcm_stepping_law_us": us(lambda: stepping_law("dcm"), number // 10),
        "zmpip_tick_with_ik_us": us(zmpip_tick, max(number // 1000, 20)),
    }
    results["zmpip_over_open"] = results["zmpip_law_us"] / results["open_step_us"]
    results["dcm_over_open"] = results["dcm_law_us"] / results["open_step_us"]
    laws = ("zmpip_law_us", "dcm_law_us", "zmpip_stepping_law_us", "dcm_stepping_law_us")
    results["meets_target"] = max(results[k] for k in laws) <= TARGET_US
    return results


def report(results: dict[str, Any]) -> None:
    """Print the results as a small table."""
    rows = [
        ("open loop: a planned row (baseline)", f"{results['open_step_us']:.2f} µs", ""),
        ("state estimator (FK, CoM, ZMP)", f"{results['estimator_us']:.1f} µs", ""),
        ("zmpip: estimator + observer + preview", f"{results['zmpip_law_us']:.1f} µs",
         f"{results['zmpip_over_open']:.0f}× baseline; target ≤ {TARGET_US:g} µs"),
        ("dcm: estimator + DCM law", f"{results['dcm_law_us']:.1f} µs",
         f"{results['dcm_over_open']:.0f}× baseline"),
        ("zmpip, step adjustment at work", f"{results['zmpip_stepping_law_us']:.1f} µs",
         "single support, capture solved and swing re-planned"),
        ("dcm, step adjustment at work", f"{results['dcm_stepping_law_us']:.1f} µs", ""),
        ("zmpip tick with the whole-body IK", f"{results['zmpip_tick_with_ik_us']:.0f} µs",
         "of the 10 ms frame"),
    ]  # fmt: skip
    met = "met" if results["meets_target"] else "NOT met"
    title = f"walking-controller tick ({results['python']}; target {met})"
    print_table(title, ("case", "time", "note"), rows)


def main(argv: list[str] | None = None) -> dict[str, Any]:
    """Run the benchmark, print a table, write JSON if asked; returns the results."""
    parser = base_parser(__doc__.splitlines()[0])
    parser.add_argument("--number", type=int, default=20_000, help="open-loop calls per repeat")
    args = parser.parse_args(argv)
    results = {**environment(), "repeats": REPEATS, "number": args.number, **run(args.number)}
    report(results)
    if args.json is not None:
        write_json(args.json, results)
    return results


if __name__ == "__main__":
    main()
