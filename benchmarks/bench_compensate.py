"""Benchmark of the multibody ZMP and of one Algorithm 1 iteration.

Usage::

    python benchmarks/bench_compensate.py [--json PATH] [--duration S]

Measures in one run, with :mod:`timeit` (best of several repeats), on the IK trajectory of
paper B's walk (0.2 m/s, 0.5 s steps, 10 ms frames) on the virtual NAO's design model:

1. the bare ``mj_inverse`` call per sample (contacts, constraints, sensors disabled);
2. the whole multibody ZMP per sample: finite differences (``mj_differentiatePos``), the
   ``mj_inverse`` loop with its state copies, and the centre of pressure;
3. one Algorithm 1 iteration over the walk: pattern with offset, whole-body IK, multibody ZMP.

The issue's target is <= 5 µs per sample for (2). Speed is reported, never asserted.
"""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np

from harness import base_parser, best_of, environment, print_table, write_json
from zmpkit.robots.registry import DEFAULT_WALK_ROBOT, get_robot
from zmpkit.walking import GaitParameters, PatternConfig, WalkCommand, generate_pattern
from zmpkit.walking.ik import solve_walking_ik
from zmpkit.walking.multibody_zmp import InverseDynamicsZmp, trajectory_qpos

__all__ = ["main"]

REPEATS = 5
#: The issue's target for the multibody ZMP per sample [µs].
TARGET_PER_SAMPLE_US = 5.0


def measure(duration_s: float) -> dict[str, Any]:
    """Times of every case for a walk of ``duration_s`` seconds."""
    config = PatternConfig(command=WalkCommand(0.2), duration_s=duration_s,
                           gait=GaitParameters(step_duration_s=0.5), com_height_m=0.25)  # fmt: skip
    robot = get_robot(DEFAULT_WALK_ROBOT, needs="walking")
    model, settings = robot.ik_model(), robot.ik_settings
    pattern = generate_pattern(config)
    trajectory = solve_walking_ik(pattern, model, settings)
    zmp = InverseDynamicsZmp(model)
    n = trajectory.time_s.size
    qpos = trajectory_qpos(model, trajectory)
    m, d = zmp.model, zmp.data
    d.qpos[:] = qpos[n // 2]

    def bare() -> None:
        for _ in range(n):
            mujoco.mj_inverse(m, d)

    offset = np.zeros((n, 2))

    def iteration() -> None:
        p = generate_pattern(config, offset, gains=pattern.gains)
        zmp.from_trajectory(solve_walking_ik(p, model, settings))

    bare_s = best_of(bare, 1, REPEATS) / n
    full_s = best_of(lambda: zmp.from_trajectory(trajectory), 1, REPEATS) / n
    iteration_s = best_of(iteration, 1, 3)
    return {"samples": n, "bare_mj_inverse_us": bare_s * 1e6,
            "multibody_zmp_per_sample_us": full_s * 1e6, "algorithm1_iteration_s": iteration_s,
            "target_per_sample_us": TARGET_PER_SAMPLE_US}  # fmt: skip


def main(argv: list[str] | None = None) -> dict[str, Any]:
    """Run the benchmark, print a table, optionally write JSON."""
    parser = base_parser(__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=10.0, help="walking time [s]")
    args = parser.parse_args(argv)
    results = {"environment": environment(), **measure(args.duration)}
    rows = [
        ["bare mj_inverse", f"{results['bare_mj_inverse_us']:.2f} µs / sample"],
        ["multibody ZMP", f"{results['multibody_zmp_per_sample_us']:.2f} µs / sample "
                          f"(target <= {TARGET_PER_SAMPLE_US} µs)"],
        ["Algorithm 1 iteration", f"{results['algorithm1_iteration_s']:.3f} s "
                                  f"({results['samples']} samples)"],
    ]  # fmt: skip
    print_table("zmpkit compensation", ["case", "time"], rows)
    if args.json:
        write_json(args.json, results)
    return results


if __name__ == "__main__":
    main()
