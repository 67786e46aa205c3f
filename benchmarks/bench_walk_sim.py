"""Walking simulation speed: the virtual NAO walking 10 s with every effect on vs off.

The IK trajectory is solved once; each case times ``simulate_walk`` on a fresh simulation
(best of the repeats) and reports simulated seconds per wall second and the cost ratio
against effects off, measured in the same run. Target (issue 5): effects-on cost ≤ 1.5×.

Run: ``python benchmarks/bench_walk_sim.py [--json PATH] [--repeats N]``
"""

from __future__ import annotations

import time
from typing import Any

from harness import base_parser, environment, print_table, write_json
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_trial import simulate_walk
from zmpkit.robots.nao import make_nao
from zmpkit.robots.registry import get_robot
from zmpkit.walking import generate_pattern
from zmpkit.walking.ik import solve_walking_ik

TARGET_RATIO = 1.5
CASES = ("none", "M,I", "G", "F", "all")


def best_wall(effects: str, trajectory: Any, repeats: int) -> tuple[float, float]:
    """(best wall time [s], simulated time [s]) of walking ``trajectory`` with ``effects``."""
    best, simulated = float("inf"), 0.0
    for _ in range(repeats):
        sim = make_nao(effects, seed=0)
        start = time.perf_counter()
        record = simulate_walk(sim, trajectory)
        best = min(best, time.perf_counter() - start)
        simulated = float(record.time_s[-1] - record.time_s[0])
    return best, simulated


def main(argv: list[str] | None = None) -> dict[str, Any]:
    """Run the benchmark, print a table, write JSON if asked; returns the results."""
    parser = base_parser(__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3, help="runs per case (best kept)")
    args = parser.parse_args(argv)
    pattern = generate_pattern(WalkConfig(get_robot("nao")).pattern_config())
    nao = get_robot("nao")
    trajectory = solve_walking_ik(pattern, nao.ik_model(), nao.ik_settings)
    cases = {}
    for effects in CASES:
        wall, simulated = best_wall(effects, trajectory, args.repeats)
        cases[effects] = {"wall_s": wall, "simulated_s": simulated, "rate": simulated / wall}
    for case in cases.values():
        case["cost_vs_none"] = case["wall_s"] / cases["none"]["wall_s"]
    results = {"env": environment(), "cases": cases, "target_ratio": TARGET_RATIO}
    rows = [
        (name, f"{c['wall_s']:.3f}", f"{c['rate']:.1f}", f"{c['cost_vs_none']:.2f}x")
        for name, c in cases.items()
    ]
    print_table(
        f"virtual NAO walking 10 s at 0.2 m/s (target: all ≤ {TARGET_RATIO}x none)",
        ("effects", "wall [s]", "sim s / wall s", "cost vs none"),
        rows,
    )
    if args.json:
        write_json(args.json, results)
    return results


if __name__ == "__main__":
    main()
