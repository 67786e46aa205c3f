"""Settling time measured fairly: candidate DLIPM pacings against the LIPM step.

Usage::

    python examples/balance_pacing.py RUN OUT

``RUN`` is the folder of a ``zmpkit balance --quick`` run (its ``params_<plane>.yaml`` give
the identified error models, its ``table1.csv`` the LIPM's settling and overshoot). For each
candidate pacing of the scheduled DLIPM (ζ and time scale, servo-paced or fixed) the DLIPM
trials at the targets ≥ 0.03 m are run again on the same virtual robot, and per plane the
script counts the targets where the DLIPM settles (5 % band) sooner than the LIPM and where
it overshoots no more than the LIPM. A fixed time scale can ask more angular acceleration
than the servos give: each candidate's largest planned acceleration
(:math:`\\beta\\,|\\Delta\\theta| / s^2` at the step, the DLIPM's peak from rest) is printed
against the servos' limit; such a plan is clipped by the servos' trajectory limiter
(:class:`~zmpkit.sim.servo.TrajectoryLimiter`), through which the LIPM's step also goes.
Writes ``OUT/pacing.csv`` and ``OUT/pacing.png`` (mean 5 %
settling time against mean overshoot, one marker per candidate, the LIPM's marked).
"""

from __future__ import annotations

import argparse
import csv
import statistics
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from zmpkit.analysis.balance_validation import evaluate_trial
from zmpkit.control import PAPER_A_TIME_SCALE
from zmpkit.experiments import (
    StepExperimentConfig,
    dataset_trials,
    design_lean_model,
    run_step_sweep,
)
from zmpkit.experiments.lean import lean_angle
from zmpkit.experiments.lean_controllers import LeanControllerFactory
from zmpkit.identify import BalanceParams
from zmpkit.pipelines.balance import BalanceConfig, support_polygon

TARGETS_M = (0.03, 0.04, 0.06, 0.08, 0.09, 0.1)
CANDIDATES = (  # label, ζ, time scale (minimum when servo-paced), servo-paced
    ("servo-paced ζ 0.8 (default)", 0.8, 1.0, True),
    ("servo-paced ζ 0.7", 0.7, 1.0, True),
    ("servo-paced ζ 1.0", 1.0, 1.0, True),
    ("fixed s 1, ζ 0.8", 0.8, 1.0, False),
    ("fixed s 1.5, ζ 0.8", 0.8, 1.5, False),
    ("fixed s 2, ζ 0.8", 0.8, 2.0, False),
    ("paper A s 7.57, ζ 0.8", 0.8, PAPER_A_TIME_SCALE, False),
    ("fixed s 2, ζ 1.0", 1.0, 2.0, False),
    ("fixed s 3, ζ 0.8", 0.8, 3.0, False),
)
_REACH_FRACTION = 0.3  # as the balance pipeline: lean to at most 0.3 l of ZMP


def _float(cell: str) -> float | None:
    return None if cell == "" else float(cell)


def _peak_acceleration(factory: LeanControllerFactory, x: float, limit: float | None) -> float:
    """The DLIPM's planned peak angular acceleration for a step from upright to ``x`` [rad/s²].

    β |Δθ| / s² with the time scale s the controller uses (servo-paced: grown until this
    is within ``limit``; see :mod:`zmpkit.control.dlipm_controller`).
    """
    schedule = factory.schedule()
    beta, swing = float(schedule.beta(x)), abs(float(schedule.steady_angle(x)))
    scale = factory.time_scale
    if limit is not None:
        scale = max(scale, (beta * swing / limit) ** 0.5)
    return beta * swing / scale**2


def main() -> None:
    """Run the study (module docstring)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="folder of a zmpkit balance --quick run")
    parser.add_argument("out", type=Path)
    parser.add_argument("--truth", help="the truth file RUN was made with (default: shipped)")
    parser.add_argument("--only", help="comma-separated candidate numbers (default: all)")
    args = parser.parse_args()
    out: Path = args.out
    out.mkdir(parents=True, exist_ok=True)
    quick = BalanceConfig.quick()
    robot = quick.robot
    limit = robot.servo_limits.max_acceleration
    with (args.run / "table1.csv").open(encoding="utf-8") as handle:
        lipm = {
            (r["plane"], round(float(r["zmp_ref"]), 6)): r
            for r in csv.DictReader(handle)
            if round(float(r["zmp_ref"]), 6) in TARGETS_M
        }
    rows = []
    for plane in ("sagittal", "frontal"):
        params = BalanceParams.from_yaml(args.run / f"params_{plane}.yaml")
        model = params.plane(plane).error_model
        length = design_lean_model(quick.robot, plane).lean_length_m
        experiment = StepExperimentConfig(
            robot=quick.robot, targets_m=TARGETS_M, plane=plane, hold_s=quick.hold_s,
            max_hold_s=quick.max_hold_s, truth=args.truth,
        )  # fmt: skip
        chosen = range(len(CANDIDATES)) if not args.only else map(int, args.only.split(","))
        for k in chosen:
            label, zeta, scale, paced = CANDIDATES[k]
            factory = LeanControllerFactory(
                kind="dlipm", error_model=model, mass_kg=params.mass, lean_length_m=length,
                zeta=zeta, time_scale=scale,
                angle_limit_rad=lean_angle(_REACH_FRACTION * length, length),
                rate_limit_rad_s=robot.servo_limits.max_velocity,
                support_polygon=support_polygon(plane, robot),
                max_acceleration_rad_s2=limit if paced else None,
            )  # fmt: skip
            peak = max(_peak_acceleration(factory, x, limit if paced else None) for x in TARGETS_M)
            dataset = run_step_sweep(
                experiment, out / "datasets" / f"{plane}_{k}", workers=2, controller=factory
            )
            ends = [(r.hold_end, r.hold_note) for r in dataset.trials]
            for trial, end in zip(dataset_trials(dataset), ends, strict=True):
                result = evaluate_trial("dlipm", trial, *end)
                reference = lipm[(plane, round(trial.zmp_ref, 6))]
                rows.append(
                    {
                        "plane": plane, "pacing": label, "zeta": zeta, "time_scale": scale,
                        "servo_paced": paced,
                        "peak_acceleration_rad_s2": peak,
                        "servo_limit_rad_s2": limit, "target_m": trial.zmp_ref,
                        "dlipm_settling_s": result.settling_time_s,
                        "dlipm_overshoot_pct": result.overshoot_pct,
                        "dlipm_error_pct": result.error_pct,
                        "lipm_settling_s": _float(reference["lipm_settling_s"]),
                        "lipm_overshoot_pct": _float(reference["lipm_overshoot_pct"]),
                    }
                )  # fmt: skip
    with (out / "pacing.csv").open("w", encoding="utf-8", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    _report(rows, out / "pacing.png")


def _report(rows: list[dict[str, object]], figure: Path) -> None:
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5), sharey=True)
    print("| plane | pacing | peak accel / limit | sooner | overshoot ≤ LIPM | mean settling [s] |")
    print("|---|---|---|---|---|---|")
    for ax, plane in zip(axes, ("sagittal", "frontal"), strict=True):
        mine = [r for r in rows if r["plane"] == plane]
        for label, *_ in CANDIDATES:
            cand = [r for r in mine if r["pacing"] == label]
            if not cand:
                continue
            settle = [r["dlipm_settling_s"] for r in cand]
            over = [r["dlipm_overshoot_pct"] for r in cand]
            sooner = sum(
                s is not None and r["lipm_settling_s"] is not None and s < r["lipm_settling_s"]
                for s, r in zip(settle, cand, strict=True)
            )
            less = sum(
                o is not None
                and r["lipm_overshoot_pct"] is not None
                and o <= r["lipm_overshoot_pct"]
                for o, r in zip(over, cand, strict=True)
            )
            valid_s = [float(s) for s in settle if s is not None]
            valid_o = [float(o) for o in over if o is not None]
            ratio = float(cand[0]["peak_acceleration_rad_s2"]) / float(
                cand[0]["servo_limit_rad_s2"]
            )
            mean_s = statistics.fmean(valid_s) if valid_s else float("nan")
            print(
                f"| {plane} | {label} | {ratio:.2f} | {sooner}/{len(cand)} | {less}/{len(cand)} "
                f"| {mean_s:.2f} |"
            )
            if valid_s and valid_o:
                marker = "o" if ratio <= 1.0 + 1e-9 else "x"
                ax.scatter(statistics.fmean(valid_o), mean_s, marker=marker, s=60, label=label)
        reference = [r for r in mine if r["pacing"] == mine[0]["pacing"]]
        lipm_s = [float(r["lipm_settling_s"]) for r in reference
                  if r["lipm_settling_s"] is not None]  # fmt: skip
        lipm_o = [float(r["lipm_overshoot_pct"]) for r in reference
                  if r["lipm_overshoot_pct"] is not None]  # fmt: skip
        ax.scatter(statistics.fmean(lipm_o), statistics.fmean(lipm_s), marker="s", s=80,
                   color="black", label="LIPM step")  # fmt: skip
        ax.set_title(f"{plane}: mean over targets 0.03–0.10 m")
        ax.set_xlabel("mean overshoot [%]")
        ax.grid(True, alpha=0.3)
    axes[0].set_ylabel("mean 5 % settling time [s]")
    axes[1].legend(
        fontsize=7, title="×: the plan asks more than the servos' limit", title_fontsize=7
    )
    fig.tight_layout()
    fig.savefig(figure, dpi=120)
    print(f"figure: {figure}")


if __name__ == "__main__":
    main()
