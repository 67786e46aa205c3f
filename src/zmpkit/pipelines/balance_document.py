"""The report of ``zmpkit balance``: paper A's bars per plane, identification, Table 1, figures.

The verdict states each of paper A's bars per plane (met, missed, or undefined and why), the
transient counts, and the warnings (:mod:`zmpkit.pipelines.balance_checks`); each plane's
identification, controller and Table 1 come from :mod:`zmpkit.pipelines.balance_sections`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from zmpkit.analysis.balance_verdict import PlaneVerdict
from zmpkit.analysis.provenance import capture_run
from zmpkit.analysis.report_document import (
    Figure,
    ReportDocument,
    Section,
    Text,
    Video,
)
from zmpkit.pipelines.balance import BalanceConfig, BalanceResult, PlaneResult
from zmpkit.pipelines.balance_checks import balance_checks
from zmpkit.pipelines.balance_sections import (
    controller_blocks,
    identification_blocks,
    table1_table,
)

__all__ = ["balance_document", "balance_figures", "step_trial_videos"]


def balance_document(
    result: BalanceResult,
    figures: Sequence[Figure],
    verdicts: dict[str, PlaneVerdict],
    extra_sections: Sequence[Section] = (),
    videos: Sequence[Video] = (),
) -> ReportDocument:
    """The balance run's report: verdict, then one section per plane, then the data."""
    c = result.config
    title = c.robot.title
    sections = [
        _plane_section(plane, [f for f in figures if f"_{plane.plane}" in f.path.name])
        for plane in result.planes.values()
    ]
    if videos:
        sections.append(Section("The robot", tuple(videos)))
    sections += [*extra_sections, _data_section()]
    return ReportDocument(
        title=f"zmpkit balance: LIPM vs gain-scheduled DLIPM on the virtual {title} (paper A §4)",
        summary=_summary(c, title),
        checks=balance_checks(result, verdicts),
        sections=tuple(sections),
        provenance=capture_run(
            c,
            result.started_s,
            (
                ("hold", _hold(c)),
                ("pacing", _pace(c)),
                ("DLIPM ζ", f"{c.zeta:g}"),
                ("ZMP feedback", _feedback(c)),
            ),
        ),
    )


def _summary(c: BalanceConfig, title: str) -> str:
    fitted = set(np.round(c.fit_targets_m, 6))
    held_out = [x for x in c.targets_m if round(x, 6) not in fitted]
    return (
        f"Paper A's balance experiment on the virtual {title}, {_effects(c.effects)}"
        f"{c.robot.simulated_effects_note(c.effects, c.truth)}: LIPM "
        "step trials; identification of the steady-state error model from the force–torque "
        f"ZMP, fitted on the LIPM steps at **{_targets(c.fit_targets_m)} m**; then every target "
        "under the gain-scheduled DLIPM (paper A eq. 7–11, ζ = "
        f"{c.zeta:g}, scheduled on the error model) and under one linear correction. Held out "
        f"from the fit: **{_targets(held_out) + ' m' if held_out else 'no target'}**. "
        f"Trials: {_hold(c)}; DLIPM {_pace(c)}."
        + (
            " With `--dlipm-feedback`, also the LIPM and the DLIPM each with a clamped PI on "
            f"the measured ZMP (LIPM+PID, DLIPM+feedback); {_feedback(c)}."
            if c.dlipm_feedback
            else ""
        )
    )


def _feedback(c: BalanceConfig) -> str:
    if not c.dlipm_feedback:
        return "off"
    if not c.faults:
        return "on, clean F-T readings"
    return f"on, F-T faults injected into its readings: {', '.join(c.faults)}"


def _effects(effects: str) -> str:
    return {"all": "every effect on", "none": "a rigid robot (effects off)"}.get(
        effects, f"effects {effects}"
    )


def _targets(values: Sequence[float]) -> str:
    return ", ".join(f"{x:g}" for x in values)


def _hold(c: BalanceConfig) -> str:
    if c.max_hold_s is None:
        return f"hold {c.hold_s:g} s"
    return f"hold {c.hold_s:g} s, extended until settled up to {c.max_hold_s:g} s"


def _pace(c: BalanceConfig) -> str:
    if c.servo_paced:
        return f"paced by the servos' acceleration limit (time scale ≥ {c.time_scale:.3g})"
    return f"at a fixed time scale {c.time_scale:.3f}"


def step_trial_videos(result: BalanceResult, paths: Sequence[Path]) -> tuple[Video, ...]:
    """The step-trial videos of a run, captioned."""
    plane = next(iter(result.planes), "sagittal")
    target = max(result.config.targets_m, key=abs)
    return tuple(
        Video(
            path,
            f"The virtual robot under the scheduled DLIPM, stepping its ZMP to {target:g} m "
            f"({plane}), rendered from the recorded joint angles; time is simulated time.",
        )
        for path in paths
    )


def _plane_section(plane: PlaneResult, figures: Sequence[Figure]) -> Section:
    name = plane.plane
    return Section(
        f"{name.capitalize()} plane",
        subsections=(
            Section(
                "Identification",
                identification_blocks(
                    plane.identification.planes[name], plane.plane, plane.lean_length_m
                ),
            ),
            Section("The controller that ran", controller_blocks(plane)),
            Section("Table 1", (table1_table(plane.rows),)),
            Section("Figures", tuple(figures)),
        ),
    )


def _data_section() -> Section:
    return Section(
        "Data",
        (
            Text(
                "`table1.csv` (Table 1 with every column, empty where undefined), "
                "`params.yaml` (the identified DLIPM parameters per plane), and every trial's "
                "recorded sensors under `datasets/` (read them with "
                "`zmpkit.experiments.read_step_dataset`)."
            ),
        ),
    )


_CAPTIONS = {
    "fig16": "Identification ({plane}): the settled force–torque ZMP x_FT [m] of each LIPM step "
    "against the commanded ZMP x_cmd [m], with the fitted error model (left), and the error "
    "x_FT − x_cmd [mm] (right); paper A Fig. 16. Filled: identification trials the model was "
    "fitted on; open squares: the validation LIPM trials at targets the fit did not use; red ×: "
    "trials that did not settle, left out of the fit, at the mean of their last second.",
    "fig20": "Measured ZMP [m] against the reference [m] under each controller ({plane}); the "
    "shaded region lies outside the fitted range, where the controllers extrapolate; × marks "
    "a trial that did not settle, at the mean of its last second (paper A Fig. 20).",
    "fig21": "Step responses of the measured ZMP [m] over time after the step [s] for each target "
    "(one colour per target, dashed: the target) under the LIPM and the DLIPM, and both at one "
    "target ({plane}, paper A Fig. 21); a red × ends a trial that did not settle, with its "
    "status in the legend.",
    "fig18": "Planned ankle lean [rad] over time [s] for the {target} ZMP step under the DLIPM and "
    "the linear correction, before the servo limits ({plane}; paper A Fig. 18 at 0.09 m).",
}


def balance_figures(
    paths: Sequence[Path], planned_targets_m: Mapping[str, float] | None = None
) -> tuple[Figure, ...]:
    """The balance figures with their captions (by the paper's figure number in the name).

    ``planned_targets_m``: plane → the ZMP step of its planned-lean figure [m].
    """
    figures = []
    for path in paths:
        key, _, rest = path.stem.partition("_")
        plane = rest.split("_")[0]
        template = _CAPTIONS.get(key, "{plane}: " + path.stem.replace("_", " ") + ".")
        planned = (planned_targets_m or {}).get(plane)
        target = "largest" if planned is None else f"{planned:g} m"
        figures.append(Figure(path, template.format(plane=plane, target=target)))
    return tuple(figures)
