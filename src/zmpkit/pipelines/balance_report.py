"""Artefacts of ``zmpkit balance``: params, Table 1, figures and ``report.md``."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

from zmpkit.analysis.balance_plots import (
    plot_error_fit,
    plot_step_responses_by_target,
    plot_zmp_ref_vs_measured,
)
from zmpkit.analysis.balance_targets import BalanceTargets, balance_targets
from zmpkit.analysis.balance_verdict import PlaneVerdict, plane_verdict
from zmpkit.analysis.step_plot import Curve, plot_step_responses
from zmpkit.analysis.table1 import table1_markdown, unsettled_lines, write_table1_csv
from zmpkit.experiments import CONTROL_PERIOD_S
from zmpkit.identify import TERMS
from zmpkit.pipelines.balance import BalanceResult, PlaneResult
from zmpkit.pipelines.videos import write_step_trial_video

__all__ = ["BalanceArtifacts", "write_balance_outputs"]

_PLANNED_TARGET_M = 0.09  # paper A Fig. 18 and 21b
_PLANNED_DURATION_S = 15.0


@dataclass(frozen=True)
class BalanceArtifacts:
    """Paths written by :func:`write_balance_outputs`, each plane's figures and verdict.

    ``videos`` holds the step trial's video when the config asked for one (``step_trial.mp4``,
    or the GIF or keyframes written instead).
    """

    report: Path
    table1: Path
    params: Path
    figures: tuple[Path, ...]
    targets: dict[str, BalanceTargets]
    verdicts: dict[str, PlaneVerdict]
    videos: tuple[Path, ...] = ()

    @property
    def met(self) -> bool:
        """Whether every bar of every plane was met."""
        return all(v.met for v in self.verdicts.values())


def write_balance_outputs(result: BalanceResult, out_dir: str | Path) -> BalanceArtifacts:
    """Write ``params.yaml`` (+ one per plane), ``table1.csv``, figures and ``report.md``."""
    out = Path(out_dir)
    rows = [row for plane in result.planes.values() for row in plane.rows]
    table1 = write_table1_csv(rows, out / "table1.csv")
    params = _write_params(result, out)
    figures: list[Path] = []
    for plane in result.planes.values():
        figures += _plane_figures(plane, out)
    verdicts = {name: plane_verdict(name, plane.rows) for name, plane in result.planes.items()}
    video = write_step_trial_video(result, out) if result.config.video else None
    videos = () if video is None or video.path is None else (video.path,)
    report = _write_report(result, out, figures, verdicts, videos)
    targets = {name: balance_targets(name, plane.rows) for name, plane in result.planes.items()}
    return BalanceArtifacts(report, table1, params, tuple(figures), targets, verdicts, videos)


def _write_params(result: BalanceResult, out: Path) -> Path:
    doc = {}
    for name in result.planes:
        params = result.params(name)
        params.to_yaml(out / f"params_{name}.yaml")
        doc[name] = params.to_dict()
    path = out / "params.yaml"
    header = (
        "# Identified DLIPM parameters per plane (zmpkit balance). com_height_m is the\n"
        "# pendulum length the controller uses: ankle pivot to CoM, from the design model.\n"
        "# params_<plane>.yaml hold the same, one plane each, loadable by BalanceParams.\n"
    )
    path.write_text(header + yaml.safe_dump(doc, sort_keys=False), encoding="utf-8")
    return path


def _plane_figures(plane: PlaneResult, out: Path) -> list[Path]:
    name, ident = plane.plane, plane.identification.planes[plane.plane]
    fit = ident.error_fit
    used = [True] * len(fit.x_cmd)
    figures = [
        plot_error_fit(fit.x_cmd, fit.x_measured, used, fit, out / f"fig16_{name}.png", plane=name),
        plot_zmp_ref_vs_measured(plane.rows, out / f"fig20_{name}.png", plane=name),
        plot_step_responses_by_target(plane.rows, out / f"fig21_{name}.png", plane=name),
        _planned_angles(plane, out / f"fig18_{name}_planned_angle.png"),
    ]
    return figures


def _planned_angles(plane: PlaneResult, path: Path) -> Path:
    """The ankle-angle plans of the scheduled DLIPM and the linear correction at 0.09 m."""
    n = round(_PLANNED_DURATION_S / CONTROL_PERIOD_S)
    t = np.arange(n + 1, dtype=np.float64) * CONTROL_PERIOD_S
    curves = []
    for kind, factory in plane.factories.items():
        controller = factory()
        controller.set_target(_PLANNED_TARGET_M)
        angles = np.array([0.0] + [controller.step() for _ in range(n)])
        curves.append(Curve(f"{kind} plan (before the servo limits)", t, angles))
    lipm = math.asin(_PLANNED_TARGET_M / plane.lean_length_m)
    return plot_step_responses(
        curves,
        path,
        title=f"Planned lean for a {100 * _PLANNED_TARGET_M:.0f} cm ZMP step, {plane.plane}",
        reference_deg=math.degrees(lipm),
    )


def _identification_text(plane: PlaneResult) -> str:
    ident = plane.identification.planes[plane.plane]
    fit = ident.error_fit
    shares = fit.weight_shares
    near = sum(float(w) for u, w in zip(fit.x_cmd, shares, strict=True) if abs(u) <= 0.0201)
    low, high = fit.fitted_range
    terms = ", ".join(
        f"{name} = {value:.4g} (95 % CI {lo:.4g} … {hi:.4g})"
        for name, value, (lo, hi) in zip(
            TERMS[fit.kind], fit.model.coefficients, fit.confidence_intervals, strict=True
        )
    )
    loo = ", ".join(
        f"{k} {1e3 * v:.3f} mm" if v is not None else f"{k} –" for k, v in fit.loo_rmse.items()
    )
    p = ident.params
    transient = (
        f"ζ = {p.zeta:.3f}, ω_n = {p.omega_n:.2f} rad/s"
        if p.zeta is not None and p.omega_n is not None
        else "no transient fit succeeded"
    )
    excluded = "; ".join(ident.excluded) or "none"
    return (
        f"- error model: **{fit.kind}**, {fit.model.equation}: {terms}; R² = {fit.r_squared:.5f}\n"
        f"- why: {fit.reason}\n- leave-one-out RMSE: {loo}\n"
        f"- weights: {fit.weighting}, between-trial scatter τ = {fit.scatter:.3g}; the trials "
        f"at |x_cmd| ≤ 0.02 m hold {100 * near:.1f} % of the weight\n"
        f"- fitted range (measured ZMP): {low:.4g} … {high:.4g} m; beyond it the controllers "
        "extrapolate the model (marked † in Table 1, shaded in Fig. 20)\n"
        f"- mean transient of the LIPM steps: {transient}\n"
        f"- trials left out of the fit: {excluded}\n"
        f"- pendulum: design lean length {plane.lean_length_m:.4f} m (ankle pivot to CoM)\n"
    )


def _hold(config) -> str:
    if config.max_hold_s is None:
        return f"hold {config.hold_s} s"
    return (
        f"hold {config.hold_s} s, extended until settled (creep included) up to "
        f"{config.max_hold_s} s"
    )


def _pace(config) -> str:
    if config.servo_paced:
        return (
            f"paced by the servos' acceleration limit (time scale ≥ {config.time_scale:.3g}, "
            "chosen per target)"
        )
    return f"fixed time scale {config.time_scale:.3f}"


def _unsettled_text(plane: PlaneResult) -> str:
    lines = unsettled_lines(plane.rows)
    if not lines:
        return "\nEvery trial settled (creep check included).\n"
    return "\n### Trials that did not settle\n\n" + "".join(f"- {line}\n" for line in lines)


def _write_report(
    result: BalanceResult,
    out: Path,
    figures: list[Path],
    verdicts: dict[str, PlaneVerdict],
    videos: tuple[Path, ...] = (),
) -> Path:
    c = result.config
    parts = [
        "# zmpkit balance: LIPM vs gain-scheduled DLIPM (paper A §4)\n",
        f"Robot `{c.robot}` (virtual), effects `{c.effects}`, seed {c.seed}, {_hold(c)}, "
        f"DLIPM ζ = {c.zeta}, {_pace(c)}. Fit on targets "
        f"{', '.join(f'{x:g}' for x in c.fit_targets_m)} m (LIPM steps); validated on "
        f"{', '.join(f'{x:g}' for x in c.targets_m)} m.\n",
        "\n## Verdict (paper A's bars)\n\n",
        "".join(f"    {line}\n" for v in verdicts.values() for line in v.lines()),
    ]
    for plane in result.planes.values():
        name = plane.plane
        parts += [
            f"\n## {name.capitalize()} plane\n\n### Identification\n",
            _identification_text(plane),
            "\n### Table 1\n\n",
            table1_markdown(plane.rows),
            _unsettled_text(plane),
            "\n### Against the targets\n\n",
            "".join(f"- {line}\n" for line in balance_targets(name, plane.rows).lines()),
            "\n### Figures\n\n",
            "".join(f"![{p.stem}]({p.name})\n\n" for p in figures if f"_{name}" in p.name),
        ]
    parts += [f"\nVideo of a step trial (DLIPM): [{v.name}]({v.name})\n" for v in videos]
    parts.append(
        "\nData: `table1.csv`, `params.yaml`, and every trial's recorded sensors under "
        "`datasets/` (read them with `zmpkit.experiments.read_step_dataset`).\n"
    )
    path = out / "report.md"
    path.write_text("".join(parts), encoding="utf-8")
    return path
