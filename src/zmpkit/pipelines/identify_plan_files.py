"""Write an ``identify plan``: its tables and the chosen experiments' protocols.

- ``plan.csv``: one row per candidate experiment and parameter, judged alone: the
  conditional and marginal resolution [%] and whether it pins the parameter;
- ``selection.csv``: one row per experiment the greedy choice added, in order, with the
  set's marginal resolution per parameter [%] and how many it pins;
- ``protocols/<experiment>/``: ``targets.csv`` and ``manifest.yaml`` of each chosen
  experiment (:func:`~zmpkit.simfit.design_experiments.write_protocol`);
- ``loose_directions.csv``: the recommended set's combinations of parameters it leaves
  loose (the Hessian's directions coarser than the identifiable limit);
- ``design_costs.csv``: every experiment's cost at every candidate (``candidates.csv``), to
  judge other sets without simulating again
  (:func:`~zmpkit.simfit.experiment_design.judge_set`);
- ``plan.md``: the same as a short report, with what the plan assumed.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

from zmpkit.pipelines.identify_plan import IdentifyPlanResult
from zmpkit.simfit.cost_hessian import sloppy_directions
from zmpkit.simfit.design_experiments import write_protocol
from zmpkit.simfit.identifiability import IDENTIFIABLE_WITHIN
from zmpkit.simfit.outputs import write_sloppy_directions_csv

__all__ = ["percent", "write_identify_plan"]


def percent(fraction: float) -> str:
    """A resolution as a percentage, ``inf`` for none."""
    return f"{100.0 * fraction:.3g}" if math.isfinite(fraction) else "inf"


def write_identify_plan(result: IdentifyPlanResult, out_dir: str | Path) -> dict[str, Path]:
    """Write the plan's files into ``out_dir``; returns them by role."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    names = [p.name for p in result.parameters]
    files = {"plan": out / "plan.csv", "selection": out / "selection.csv"}
    with files["plan"].open("w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f)
        writer.writerow(("experiment", "parameter", "conditional_pct", "marginal_pct", "pins"))
        for judged in result.alone:
            for k, name in enumerate(names):
                writer.writerow(
                    (judged.experiments[0], name, percent(judged.conditional[k]),
                     percent(judged.marginal[k]), str(judged.pinned[k]).lower())
                )  # fmt: skip
    with files["selection"].open("w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f)
        writer.writerow(("rank", "experiment", "pinned", *(f"{n}_marginal_pct" for n in names)))
        for rank, judged in enumerate(result.chosen, start=1):
            writer.writerow(
                (rank, judged.experiments[-1], sum(judged.pinned),
                 *(percent(m) for m in judged.marginal))
            )  # fmt: skip
    _write_costs(result, out, files)
    if result.chosen:
        best = result.chosen[-1]
        loose = sloppy_directions(best.hessian, best.rise, names, IDENTIFIABLE_WITHIN)
        files["loose"] = write_sloppy_directions_csv(out / "loose_directions.csv", loose)
    chosen = result.chosen[-1].experiments if result.chosen else ()
    for name in chosen:
        design = result.designs.get(name)
        if design is not None:
            write_protocol(result.config.robot, design, out / "protocols" / name)
            files["protocols"] = out / "protocols"
    files["report"] = out / "plan.md"
    files["report"].write_text(_report(result), encoding="utf-8")
    return files


def _write_costs(result: IdentifyPlanResult, out: Path, files: dict[str, Path]) -> None:
    """Write ``candidates.csv`` (index, each parameter) and ``design_costs.csv``."""
    names = [p.name for p in result.parameters]
    files["candidates"] = out / "candidates.csv"
    with files["candidates"].open("w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f)
        writer.writerow(("candidate", *names))
        for k, values in enumerate(result.candidates):
            writer.writerow((k, *(f"{v:.10g}" for v in values)))
    files["costs"] = out / "design_costs.csv"
    with files["costs"].open("w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f)
        writer.writerow(("experiment", "candidate", "cost"))
        for experiment in result.costs:
            for k, cost in enumerate(experiment.costs):
                writer.writerow((experiment.name, k, f"{cost:.10g}"))


def _report(result: IdentifyPlanResult) -> str:
    """The plan as Markdown."""
    names = [p.name for p in result.parameters]
    config = result.config
    lines = [
        f"# Which experiments to record: {config.robot.name}, effects {config.effects}",
        "",
        f"Every candidate was recorded once from the nominal robot (the catalogue's nominal "
        f"values), and the fit's cost (expected sensor readings) evaluated on one batch of "
        f"{len(result.alone[0].marginal) if result.alone else 0} parameters' moves. A "
        f"parameter is pinned when its marginal resolution (every other parameter free) is "
        f"within {100 * IDENTIFIABLE_WITHIN:g} %. This is a local design: it says what the "
        f"experiments show on a robot near the nominal values; the fit judges the recorded "
        f"data again. {result.seconds:.0f} s.",
        "",
        "## Each experiment alone (marginal resolution, %)",
        "",
        "| experiment | " + " | ".join(names) + " | pins |",
        "|---|" + "---|" * (len(names) + 1),
    ]
    for judged in result.alone:
        cells = " | ".join(percent(m) for m in judged.marginal)
        lines.append(f"| {judged.experiments[0]} | {cells} | {sum(judged.pinned)} |")
    lines += ["", "## The recommended set, as it grows", ""]
    lines += ["| added | " + " | ".join(names) + " | pins |", "|---|" + "---|" * (len(names) + 1)]
    for judged in result.chosen:
        cells = " | ".join(percent(m) for m in judged.marginal)
        lines.append(f"| {judged.experiments[-1]} | {cells} | {sum(judged.pinned)} |")
    if result.chosen:
        best = result.chosen[-1]
        loose = sloppy_directions(best.hessian, best.rise, names, IDENTIFIABLE_WITHIN)
        lines += ["", "## What the recommended set leaves loose", ""]
        lines += [
            f"- ±{percent(d.resolution)} %: "
            + ", ".join(f"{name} {value:+.2f}" for name, value in d.components)
            for d in loose
        ] or ["- nothing: every direction is pinned within the limit"]
        lines += [
            "",
            f"The recommended set's cost at the nominal values is {best.level:.3g}, its scatter "
            f"under 0.5 % moves {best.roughness:.3g}; a rise of {best.rise:.3g} counts as visible.",
        ]
    if result.dropped:
        lines += ["", "Not recorded: " + "; ".join(result.dropped) + "."]
    return "\n".join(lines) + "\n"
