"""Benchmark of one balance-controller tick: 2-sensor ZMP + scheduled DLIPM step.

Usage::

    python benchmarks/bench_controller.py [--json PATH] [--number N]

Measures in one run, with :mod:`timeit` (best of several repeats), in µs per call:

1. one tick: the double-support ZMP of two ankle F-T samples
   (:class:`zmpkit.sensors.DoubleSupportZmp`) and one :meth:`DlipmController.step` (the gain
   schedule is evaluated on target changes only, by :meth:`DlipmController.set_target`);
2. its parts: the ZMP alone, the DLIPM step alone (with its rate and angle limits);
3. the baseline: a bare 2×2 state-space update on plain floats in a method call, the least
   a Python controller tick can cost;
4. a target change (:meth:`DlipmController.set_target`: schedule + exact ZOH), for scale.

The target is 2 µs per tick. Speed is reported, never asserted.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from harness import base_parser, best_of, environment, print_table, write_json
from zmpkit.control import DlipmController, GainSchedule
from zmpkit.identify import ErrorModel
from zmpkit.sensors import DoubleSupportZmp, SensorMount

__all__ = ["BareStateSpace", "main"]

REPEATS = 7
TARGET_US = 2.0
PAPER_A = ErrorModel("quadratic", (0.834, 1.024, -0.0004))  # paper A eq. 13
TEO_MASS_KG, TEO_LENGTH_M = 62.6, 0.893  # paper A §4.1


class BareStateSpace:
    """x ← A x + B u for a 2×2 A on plain floats: the baseline tick."""

    __slots__ = ("a00", "a01", "a10", "a11", "b0", "b1", "u", "x0", "x1")

    def __init__(self, ad: np.ndarray, bd: np.ndarray, u: float) -> None:
        self.a00, self.a01, self.a10, self.a11 = (float(v) for v in ad.ravel())
        self.b0, self.b1 = (float(v) for v in bd.ravel())
        self.u, self.x0, self.x1 = u, 0.0, 0.0

    def step(self) -> float:
        """One update; returns the first state."""
        x0, x1 = self.x0, self.x1
        self.x0 = self.a00 * x0 + self.a01 * x1 + self.b0 * self.u
        self.x1 = self.a10 * x0 + self.a11 * x1 + self.b1 * self.u
        return self.x0


def best_us(stmt: str, namespace: dict[str, object], number: int) -> float:
    """Best time of one execution of ``stmt`` over :data:`REPEATS` repeats [µs]."""
    return best_of(stmt, number, REPEATS, namespace) * 1e6


def teo_wrenches() -> tuple[DoubleSupportZmp, list[float], list[float]]:
    """TEO-like mounts (rotated π about x) and one sample of each sensor, 300 N per foot."""
    right = SensorMount.from_rpy((0.0, -0.1285, 0.01), (math.pi, 0.0, 0.0), 0.01, "right")
    left = SensorMount.from_rpy((0.0, 0.1285, 0.01), (math.pi, 0.0, 0.0), 0.01, "left")
    wrenches = []
    for mount in (right, left):
        point = np.array([0.03, mount.position[1], mount.ground_height])
        force = np.array([2.0, -1.0, 300.0])
        moment = np.cross(point - mount.position, force)
        wrenches.append(np.concatenate([mount.rotation.T @ force, mount.rotation.T @ moment]))
    return DoubleSupportZmp(right, left), wrenches[0].tolist(), wrenches[1].tolist()


def run(number: int) -> dict[str, Any]:
    """All timings of the module docstring [µs]."""
    zmp, wr, wl = teo_wrenches()
    schedule = GainSchedule(PAPER_A, TEO_MASS_KG, TEO_LENGTH_M)
    controller = DlipmController(
        schedule, 0.001, angle_limit_rad=0.3, rate_limit_rad_s=1.0, support_polygon=(-0.1, 0.15)
    )
    controller.set_target(0.05)
    system = schedule.dlipm(0.05).discretize(0.001)
    bare = BareStateSpace(system.Ad, system.Bd, 0.05)
    namespace = {
        "zmp": zmp.compute,
        "wr": wr,
        "wl": wl,
        "step": controller.step,
        "bare": bare.step,
        "set_target": controller.set_target,
    }
    results = {
        "tick_us": best_us("zmp(wr, wl); step()", namespace, number),
        "zmp_us": best_us("zmp(wr, wl)", namespace, number),
        "dlipm_step_us": best_us("step()", namespace, number),
        "bare_2x2_us": best_us("bare()", namespace, number),
        "set_target_us": best_us("set_target(0.05)", namespace, max(number // 1000, 10)),
        "zmp_m": list(zmp(wr, wl) or ()),
    }
    results["tick_over_bare"] = results["tick_us"] / results["bare_2x2_us"]
    results["meets_target"] = results["tick_us"] <= TARGET_US
    return results


def report(results: dict[str, Any]) -> None:
    """Print the results as a small table (rich if available)."""
    rows = [
        ("tick: 2-sensor ZMP + DLIPM step", f"{results['tick_us']:.3f} µs",
         f"target ≤ {TARGET_US} µs: {'met' if results['meets_target'] else 'NOT met'}"),
        ("  DoubleSupportZmp", f"{results['zmp_us']:.3f} µs", ""),
        ("  DlipmController.step", f"{results['dlipm_step_us']:.3f} µs", "with rate/angle limits"),
        ("bare 2×2 update (baseline)", f"{results['bare_2x2_us']:.3f} µs",
         f"tick = {results['tick_over_bare']:.1f}× baseline"),
        ("set_target (schedule + ZOH)", f"{results['set_target_us']:.1f} µs", "per target change"),
    ]  # fmt: skip
    title = f"zmpkit controller tick ({results['python']}, {results['machine']})"
    print_table(title, ("case", "time", "note"), rows)


def main(argv: list[str] | None = None) -> dict[str, Any]:
    """Run the benchmark, print a table, write JSON if asked; returns the results."""
    parser = base_parser(__doc__.splitlines()[0])
    parser.add_argument("--number", type=int, default=200_000, help="calls per repeat")
    args = parser.parse_args(argv)
    results = {
        **environment(),
        "repeats": REPEATS,
        "number": args.number,
        **run(args.number),
    }
    report(results)
    if args.json is not None:
        write_json(args.json, results)
    return results


if __name__ == "__main__":
    main()
