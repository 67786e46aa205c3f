"""Paper A's method on robots it was not tuned on: the virtual TEO's truth variants.

Usage::

    python examples/balance_variants.py OUT [--variants shipped,soft_flex,...] [--repeats N]

For the shipped truth and each variant of :mod:`zmpkit.robots.teo.truth_variants` (softer
and stiffer flex, more backlash, extra payload, combined, trial-to-trial variability), runs
``zmpkit balance --quick --dlipm-feedback --truth FILE`` and tabulates, per plane: the LIPM,
DLIPM and DLIPM+feedback errors at the largest target, the mean |error| ratio DLIPM / LIPM
(paper A's bars), the verdict, and how many targets ≥ 0.03 m the DLIPM settles sooner and
overshoots less than the LIPM. Then ``--repeats`` LIPM trials at one target (0.06 m, the
sweep's earlier targets before it, seeds 0…N−1: stance, F-T drift and the previous lean
differ) give the trial-to-trial scatter, against paper A's LIPM errors (8.2, 6.0, 2.2, 4.8,
9.4 %: a standard deviation of 2.9 points). Each run writes into ``OUT/<truth>/``; a rerun
skips truths whose ``table1.csv`` exists. Writes ``OUT/variants.csv`` and
``OUT/scatter.csv`` and prints both tables.
"""

from __future__ import annotations

import argparse
import csv
import math
import statistics
from pathlib import Path

from zmpkit.experiments import StepExperimentConfig, run_step_trial
from zmpkit.experiments.response import measured_zmp
from zmpkit.io import feet_from_mapping
from zmpkit.pipelines.balance import BalanceConfig, run_balance
from zmpkit.pipelines.balance_files import write_balance
from zmpkit.robots.teo.truth_variants import TRUTH_VARIANTS, write_truth_variant
from zmpkit.signals import StepTrial
from zmpkit.signals.steady_state import steady_state

PAPER_A_LIPM_ERRORS_PCT = (8.2, 6.0, 2.2, 4.8, 9.4)
"""Paper A's LIPM errors at its validation targets [%]."""
SCATTER_TARGET_M = 0.06
TRANSIENT_FROM_M = 0.03


def _float(cell: str) -> float | None:
    return None if cell == "" else float(cell)


def _plane_figures(rows: list[dict[str, str]], plane: str) -> dict[str, object]:
    rows = [r for r in rows if r["plane"] == plane]
    far = max(rows, key=lambda r: float(r["zmp_ref"]))
    figures: dict[str, object] = {"plane": plane, "far_target_m": float(far["zmp_ref"])}
    for kind in ("lipm", "dlipm", "lipm_pid", "dlipm_fb"):
        figures[f"{kind}_far_error_pct"] = _float(far[f"{kind}_error_pct"])
        errors = [_float(r[f"{kind}_error_pct"]) for r in rows if float(r["zmp_ref"]) != 0.0]
        figures[f"{kind}_mean_abs_error_pct"] = (
            None
            if any(e is None for e in errors)
            else statistics.fmean(abs(e) for e in errors if e is not None)
        )
        figures[f"{kind}_unsettled"] = sum(r[f"{kind}_status"] != "settled" for r in rows)
    lipm, dlipm = figures["lipm_mean_abs_error_pct"], figures["dlipm_mean_abs_error_pct"]
    figures["mean_error_ratio"] = (
        None if lipm is None or dlipm is None or lipm == 0 else float(dlipm) / float(lipm)
    )
    transient = [r for r in rows if float(r["zmp_ref"]) >= TRANSIENT_FROM_M]
    figures["dlipm_settles_sooner"] = sum(
        _sooner(r["dlipm_settling_s"], r["lipm_settling_s"]) for r in transient
    )
    figures["dlipm_overshoots_less"] = sum(
        _sooner(r["dlipm_overshoot_pct"], r["lipm_overshoot_pct"]) for r in transient
    )
    figures["transient_targets"] = len(transient)
    return figures


def _sooner(ours: str, theirs: str) -> bool:
    a, b = _float(ours), _float(theirs)
    return a is not None and b is not None and a < b


def run_truth(name: str, out: Path) -> list[dict[str, object]]:
    """One truth's balance run (resumed when its table exists) and its figures per plane."""
    folder = out / name
    truth = None if name == "shipped" else str(write_truth_variant(name, out / "truths"))
    table = folder / "table1.csv"
    if not table.exists():
        config = BalanceConfig.quick(truth=truth, dlipm_feedback=True)
        result = run_balance(config, folder, echo=lambda line: print(f"[{name}] {line}"))
        write_balance(result, folder)
    with table.open(encoding="utf-8") as handle:
        rows = list(csv.DictReader(handle))
    return [{"truth": name, **_plane_figures(rows, p)} for p in ("sagittal", "frontal")]


def repeated_lipm_errors(name: str, out: Path, repeats: int, plane: str) -> list[float | None]:
    """LIPM errors [%] of ``repeats`` trials at :data:`SCATTER_TARGET_M` (seeds 0…N−1)."""
    truth = None if name == "shipped" else str(write_truth_variant(name, out / "truths"))
    quick = BalanceConfig.quick()
    errors: list[float | None] = []
    for seed in range(repeats):
        config = StepExperimentConfig(
            robot=quick.robot, targets_m=quick.targets_m, plane=plane, hold_s=quick.hold_s,
            max_hold_s=quick.max_hold_s, truth=truth, seed=seed,
        )  # fmt: skip
        record = run_step_trial(config, SCATTER_TARGET_M)
        mounts = feet_from_mapping(config.robot.feet_mounts())
        startup = (record.t_step_s - config.startup_window_s, record.t_step_s)
        zmp = measured_zmp(record, mounts, startup, config.robot.contact_force_threshold_n)
        trial = StepTrial(
            time=record.time - record.t_step_s, zmp_measured=zmp, zmp_ref=SCATTER_TARGET_M,
            t_step=0.0, plane=plane,
        )  # fmt: skip
        steady = steady_state(trial)
        errors.append(
            None
            if steady.value is None or not steady.settled
            else 100.0 * (steady.value - SCATTER_TARGET_M) / SCATTER_TARGET_M
        )
    return errors


def _text(value: object) -> str:
    if value is None:
        return "–"
    if isinstance(value, float):
        return f"{value:.3g}"
    return str(value)


def main() -> None:
    """Run the study (module docstring)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path)
    parser.add_argument(
        "--variants",
        default="shipped,stiff_flex,soft_flex,backlash_x3,payload_plus3,combined,variability",
        help="comma-separated: shipped and names of TRUTH_VARIANTS",
    )
    parser.add_argument("--repeats", type=int, default=8, help="LIPM trials for the scatter")
    args = parser.parse_args()
    names = [n.strip() for n in args.variants.split(",") if n.strip()]
    unknown = [n for n in names if n != "shipped" and n not in TRUTH_VARIANTS]
    if unknown:
        parser.error(f"unknown variants {unknown}; valid: shipped, {', '.join(TRUTH_VARIANTS)}")
    out: Path = args.out
    out.mkdir(parents=True, exist_ok=True)
    figures = [row for name in names for row in run_truth(name, out)]
    with (out / "variants.csv").open("w", encoding="utf-8", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(figures[0]))
        writer.writeheader()
        writer.writerows(figures)
    columns = (
        "truth", "plane", "lipm_far_error_pct", "dlipm_far_error_pct", "dlipm_fb_far_error_pct",
        "lipm_pid_far_error_pct", "mean_error_ratio", "dlipm_fb_mean_abs_error_pct",
        "dlipm_settles_sooner", "dlipm_overshoots_less", "transient_targets", "lipm_unsettled",
        "dlipm_fb_unsettled",
    )  # fmt: skip
    print("| " + " | ".join(columns) + " |")
    print("|" + "---|" * len(columns))
    for row in figures:
        print("| " + " | ".join(_text(row[c]) for c in columns) + " |")
    paper_std = statistics.stdev(PAPER_A_LIPM_ERRORS_PCT)
    print(f"\nscatter of repeated LIPM trials at {SCATTER_TARGET_M} m (paper A: ±{paper_std:.1f})")
    with (out / "scatter.csv").open("w", encoding="utf-8", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["truth", "plane", "seed", "lipm_error_pct"])
        for name in [n for n in names if n in ("shipped", "variability")]:
            for plane in ("sagittal", "frontal"):
                errors = repeated_lipm_errors(name, out, args.repeats, plane)
                writer.writerows([name, plane, k, e] for k, e in enumerate(errors))
                settled = [e for e in errors if e is not None and math.isfinite(e)]
                spread = statistics.stdev(settled) if len(settled) > 1 else float("nan")
                mean = statistics.fmean(settled) if settled else float("nan")
                print(
                    f"  {name} {plane}: {mean:.2f} ± {spread:.2f} % "
                    f"({len(settled)} of {len(errors)} settled)"
                )


if __name__ == "__main__":
    main()
