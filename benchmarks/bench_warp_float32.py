"""Float32 (MuJoCo Warp) against float64 (CPU MuJoCo) costs on a full-length walk.

Usage::

    python benchmarks/bench_warp_float32.py [--device cpu|cuda:0] [--duration S]
                                            [--threads N] [--json PATH]

One recorded walk (10 s at 0.2 m/s, every effect on; :mod:`long_walk`) replayed by 8
candidates (the hidden truth scaled by 0.8-1.1, and the nominal values) on the CPU batch
(float64, the serial path's numbers bit for bit) and on MuJoCo Warp (float32, default
solver settings). Printed:

- per candidate, each cost term and the total on both, and the relative difference of the
  total, ``|warp - cpu| / cpu``;
- the same for a cost of per-step aggregates (a less timing-sensitive formulation, defined
  here, not the fit's): per walking step (``step_duration_s`` windows), the mean and the
  standard deviation of every encoder, of the ZMP's x and y and of the trunk pitch, their
  differences normalised by the fit's own scales (:mod:`zmpkit.simfit.cost`) and summed
  in squares; the spectrum term is one such aggregate already;
- for the hidden truth, how far the two runs' signals drift apart over the walk (RMS per
  second of the encoders [rad], the ZMP [m], the pitch [rad]) — chaotic growth shows as
  a difference that rises by orders of magnitude from the start.

Reported, never asserted. Without ``mujoco_warp`` it says so and exits 0.
"""

from __future__ import annotations

import tempfile
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from harness import base_parser, print_table, write_run
from long_walk import long_walk, long_walk_arguments

__all__ = ["aggregate_cost", "main"]


def _rms(x: np.ndarray) -> float:
    x = x[np.isfinite(x)]
    return float(np.sqrt(np.mean(np.square(x)))) if x.size else 0.0


def _window_stats(t: np.ndarray, x: np.ndarray, window_s: float) -> np.ndarray:
    """Per window of ``window_s``: mean and std of each column of ``x`` (NaN rows left out)."""
    index = np.floor((t - t[0]) / window_s).astype(int)
    out = []
    for w in range(index.max() + 1):
        rows = x[index == w]
        with np.errstate(invalid="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # a window without contact
            out.append(np.concatenate([np.nanmean(rows, axis=0), np.nanstd(rows, axis=0)]))
    return np.array(out)


def aggregate_cost(recorded: Any, simulated: Any, window_s: float) -> tuple[float, ...]:
    """(joint, ZMP, pitch, total) of the per-step aggregate cost (module docstring) [-]."""
    from zmpkit.simfit.cost import _detrended

    t = recorded.time_s
    q_scale = _rms(recorded.q_meas_rad - recorded.q_cmd_rad)
    both = np.all(np.isfinite(recorded.zmp_m), axis=1)
    p = recorded.zmp_m[both]
    zmp_scale = np.hypot(_rms(_detrended(t[both], p[:, 0])), _rms(_detrended(t[both], p[:, 1])))
    tilt_scale = _rms(_detrended(t, recorded.trunk_tilt_rad))
    terms = []
    for name, scale in (("q_meas_rad", q_scale), ("zmp_m", zmp_scale)):
        a = _window_stats(t, getattr(simulated, name), window_s)
        b = _window_stats(t, getattr(recorded, name), window_s)
        terms.append(_rms(a - b) / scale)
    a = _window_stats(t, simulated.trunk_tilt_rad[:, None], window_s)
    b = _window_stats(t, recorded.trunk_tilt_rad[:, None], window_s)
    terms.append(_rms(a - b) / tilt_scale)
    return (*terms, float(sum(x * x for x in terms)))


def _drift(cpu: Any, warp: Any) -> list[dict[str, float]]:
    """Per second of the walk: RMS differences of encoders, ZMP and pitch."""
    t = cpu.time_s
    out = []
    for second in range(int(np.ceil(t[-1] - t[0]))):
        rows = (t - t[0] >= second) & (t - t[0] < second + 1)
        out.append(
            {
                "from_s": float(second),
                "encoders_rad": _rms(warp.q_meas_rad[rows] - cpu.q_meas_rad[rows]),
                "zmp_m": _rms(warp.zmp_m[rows] - cpu.zmp_m[rows]),
                "pitch_rad": _rms(warp.trunk_tilt_rad[rows] - cpu.trunk_tilt_rad[rows]),
            }
        )
    return out


def measure(device: str, duration_s: float, threads: int) -> dict[str, Any]:
    """Both runs' costs per candidate, their relative differences, and the truth's drift."""
    from zmpkit.simfit.batched import simulate_batch
    from zmpkit.simfit.cost import experiment_cost
    from zmpkit.simfit.warp_batched import simulate_batches_warp

    with tempfile.TemporaryDirectory() as tmp:
        case = long_walk(Path(tmp), duration_s)
    problem: Any = case.problem
    (experiment,) = problem.experiments
    truths = [problem.truth(list(c)) for c in case.candidates]
    cpu = simulate_batch(experiment, truths, problem.sim_effects, threads)
    (warp,) = simulate_batches_warp([experiment], truths, problem.sim_effects, device)
    rec, weights = experiment.signals, problem.weights
    rows = []
    for label, c, w in zip(case.labels, cpu, warp, strict=True):
        tc = experiment_cost(rec, c, problem.models_loads)
        tw = experiment_cost(rec, w, problem.models_loads)
        row: dict[str, Any] = {
            "candidate": label,
            "completed_cpu": tc.completed,
            "completed_warp": tw.completed,
            "cpu": [tc.joint, tc.zmp, tc.spectrum, tc.total(weights)],
            "warp": [tw.joint, tw.zmp, tw.spectrum, tw.total(weights)],
        }
        if tc.completed == tw.completed == 1.0:
            ac = aggregate_cost(rec, c, experiment.step_duration_s)
            aw = aggregate_cost(rec, w, experiment.step_duration_s)
            row["aggregate_cpu"], row["aggregate_warp"] = list(ac), list(aw)
            row["rel_total"] = abs(tw.total(weights) - tc.total(weights)) / tc.total(weights)
            row["rel_terms"] = [
                abs(a - b) / b for a, b in zip(row["warp"], row["cpu"], strict=True)
            ]
            row["rel_aggregate"] = abs(aw[-1] - ac[-1]) / ac[-1]
        rows.append(row)
    return {
        "rows": rows,
        "drift_truth": _drift(cpu[0], warp[0]),
        "duration_s": duration_s,
        "device": device,
    }


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark, print the tables, write JSON if asked; returns the exit status."""
    args = long_walk_arguments(base_parser(__doc__.splitlines()[0]), argv)
    if args is None:
        return 0
    result = measure(args.device, args.duration, args.threads or 2)
    cells = []
    for r in result["rows"]:
        if "rel_total" not in r:
            done = f"cpu {r['completed_cpu']:.2f} / warp {r['completed_warp']:.2f}"
            cells.append((r["candidate"], "fell: " + done, "", "", "", "", "", ""))
            continue
        cells.append(
            (
                r["candidate"],
                f"{r['cpu'][3]:.4g}",
                f"{r['warp'][3]:.4g}",
                f"{100 * r['rel_total']:.2f}",
                "/".join(f"{100 * x:.2f}" for x in r["rel_terms"][:3]),
                f"{r['aggregate_cpu'][3]:.4g}",
                f"{r['aggregate_warp'][3]:.4g}",
                f"{100 * r['rel_aggregate']:.2f}",
            )
        )
    print_table(
        f"float32 (MuJoCo Warp, {args.device}) vs float64 (CPU) costs, {args.duration:g} s walk",
        (
            "candidate",
            "cost cpu",
            "cost warp",
            "d total %",
            "d joint/zmp/spec %",
            "aggregate cpu",
            "aggregate warp",
            "d aggregate %",
        ),
        cells,
    )
    drift = [
        (
            f"{d['from_s']:.0f}",
            f"{d['encoders_rad']:.2e}",
            f"{d['zmp_m']:.2e}",
            f"{d['pitch_rad']:.2e}",
        )
        for d in result["drift_truth"]
    ]
    print_table(
        "hidden truth: RMS difference warp - cpu per second of the walk",
        ("second", "encoders (rad)", "ZMP (m)", "pitch (rad)"),
        drift,
    )
    write_run(args, result)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
