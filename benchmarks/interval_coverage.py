"""Do the simulator fit's 95 % intervals cover a hidden truth? One truth per run.

Usage::

    python benchmarks/interval_coverage.py --out DIR [--robot R] [--pid-scale A]
                                           [--gear-scale B] [--workers W] [--logs-only]

A truth is the robot's shipped one with its quick fit parameters (PID gain scale, gear
stiffness) multiplied by ``--pid-scale`` and ``--gear-scale``. It walks three default
closed-loop walks of 6 s at 0.1, 0.15 and 0.2 m/s (M, G, S, seed 3: ``zmpkit walk``); their
``walk_log.csv`` are fitted with ``zmpkit identify sim --effects M,G --quick`` (multiple
shooting; the intervals bias-corrected from replicas walked through the same pipeline).
With ``--logs-only`` the logs are copied away from their walk folders first, as a real
robot's logs would come: the fit cannot walk them again and its intervals come from the
windows replayed again (``window_refits``).
Printed per parameter: the truth, the fit, the interval, its kind, and whether it covers
the truth. About 15–20 min on one worker. Coverage is reported, never asserted: the README
gives the measured table and the truths it was judged on.
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

from zmpkit.cli.app import main
from zmpkit.robots.registry import get_robot
from zmpkit.simfit.parameters import default_parameters
from zmpkit.simfit.truth_doc import base_truth_path, load_truth_doc, truth_doc_with, write_truth_doc

SPEEDS_MPS = (0.1, 0.15, 0.2)


def _truth(robot: str, pid_scale: float, gear_scale: float, out: Path) -> dict[str, float]:
    """Write the hidden truth to ``out/truth.yaml``; its fitted parameters' values."""
    rob = get_robot(robot, needs="fit")
    params = default_parameters(rob, "M,G", ("pid_gain_scale", "gear_stiffness"))
    values = [params[0].nominal * pid_scale, params[1].nominal * gear_scale]
    doc = truth_doc_with(load_truth_doc(base_truth_path(rob, None)), params, values)
    write_truth_doc(doc, out / "truth.yaml")
    return {p.name: v for p, v in zip(params, values, strict=True)}


def run(
    robot: str, pid_scale: float, gear_scale: float, out: Path, workers: int, logs_only: bool
) -> None:
    """Record, fit and print the coverage table (module docstring)."""
    out.mkdir(parents=True, exist_ok=True)
    hidden = _truth(robot, pid_scale, gear_scale, out)
    logs = []
    for speed in SPEEDS_MPS:
        walk = out / f"walk_{speed:g}"
        argv = ["walk", "--robot", robot, "--truth", str(out / "truth.yaml"), "--speed", str(speed)]
        argv += ["--duration", "6", "--effects", "M,G,S", "--seed", "3", "--report", "md"]
        assert main([*argv, "--out", str(walk)]) == 0
        log = walk / "walk_log.csv"
        if logs_only:
            alone = out / "logs" / f"walk_{speed:g}.csv"
            alone.parent.mkdir(exist_ok=True)
            alone.write_bytes(log.read_bytes())
            log = alone
        logs.append(str(log))
    fit = out / "fit"
    argv = ["identify", "sim", *logs, "--robot", robot, "--effects", "M,G", "--quick"]
    assert main([*argv, "--workers", str(workers), "--report", "md", "--out", str(fit)]) == 0
    with (fit / "intervals.csv").open(encoding="utf-8") as f:
        for row in csv.DictReader(f):
            truth = hidden[row["parameter"]]
            covers = float(row["lower"]) <= truth <= float(row["upper"])
            print(
                f"{row['parameter']}: truth {truth:.5g}, fit {float(row['value']):.5g}, "
                f"[{float(row['lower']):.5g}, {float(row['upper']):.5g}] ({row['kind']}) "
                f"{'covers' if covers else 'MISSES'}"
            )


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--robot", default="nao")
    parser.add_argument("--pid-scale", type=float, default=1.05)
    parser.add_argument("--gear-scale", type=float, default=0.85)
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--logs-only", action="store_true")
    args = parser.parse_args()
    run(args.robot, args.pid_scale, args.gear_scale, args.out, args.workers, args.logs_only)
