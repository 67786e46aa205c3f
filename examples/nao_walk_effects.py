"""Paper B Fig. 6: the 10 s, 0.2 m/s walk of the virtual NAO per effect set, per controller.

Run: ``python examples/nao_walk_effects.py [OUT_DIR] [--controller open|zmpip|dcm]``
(about 15 s open loop, 60 s with feedback). A fallen walk's metrics are "-".
"""

from __future__ import annotations

import argparse
from pathlib import Path

from zmpkit.analysis.walk_plots import plot_effect_comparison
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.pipelines.walk import run_walk
from zmpkit.pipelines.walk_files import write_walk
from zmpkit.robots.registry import get_robot

EFFECT_SETS = ("none", "M", "M,I", "G", "F", "I,G,F", "M,G", "M,F", "M,G,F", "all")


def _f(value: float | None, spec: str) -> str:
    return "-" if value is None else format(value, spec)


def main(out: Path, controller: str) -> None:
    runs = {}
    for effects in EFFECT_SETS:
        config = WalkConfig(
            get_robot("nao"),
            effects=effects,
            controller=controller,
            figures=effects in ("none", "all"),
        )
        result = write_walk(run_walk(config), out / effects.replace(",", ""))
        s = result.summary
        runs[effects] = (result.record.time_s, result.record.trunk_pitch_rad)
        fell = f"{s.fall_kind}@{s.fall_time_s:.2f}s" if s.fell else "no"
        print(
            f"{controller:5s} {effects:7s} fell={fell} v={_f(s.mean_speed_mps, '.4f')} m/s "
            f"peak={_f(s.trunk_pitch_peak_hz, '.2f')} Hz "
            f"A={_f(s.trunk_pitch_peak_amplitude_rad, '.4f')} rad "
            f"std={_f(s.trunk_pitch_std_rad, '.4f')} rad "
            f"ds={_f(s.mean_double_support_foot_distance_m, '.4f')} m "
            f"slip_x={_f(s.foot_slip_x_m, '+.4f')} m",
            flush=True,
        )
    plot_effect_comparison(
        runs, out / "fig6_effects.png", f"NAO 0.2 m/s, {controller}: trunk pitch per effect set"
    )


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default="walk_effects", type=Path)
    parser.add_argument("--controller", default="open", choices=("open", "zmpip", "dcm"))
    args = parser.parse_args()
    main(args.out, args.controller)
