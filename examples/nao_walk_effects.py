"""Paper B Fig. 6: the 10 s, 0.2 m/s walk of the virtual NAO per effect set.

Run: ``python examples/nao_walk_effects.py [OUT_DIR]`` (about 15 s).
"""

from __future__ import annotations

import sys
from pathlib import Path

from zmpkit.analysis.walk_plots import plot_effect_comparison
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.pipelines.walk import run_walk, write_walk

EFFECT_SETS = ("none", "M", "M,I", "G", "F", "I,G,F", "M,G", "M,F", "M,G,F", "all")


def main(out: Path) -> None:
    runs = {}
    for effects in EFFECT_SETS:
        config = WalkConfig(effects=effects, figures=effects in ("none", "all"))
        result = write_walk(run_walk(config), out / effects.replace(",", ""))
        s = result.summary
        runs[effects] = (result.record.time_s, result.record.trunk_pitch_rad)
        print(
            f"{effects:7s} fell={s.fell} v={s.mean_speed_mps:.4f} m/s "
            f"peak={s.trunk_pitch_peak_hz:.2f} Hz A={s.trunk_pitch_peak_amplitude_rad:.4f} rad "
            f"std={s.trunk_pitch_std_rad:.4f} rad ds={s.mean_double_support_foot_distance_m:.4f} m"
        )
    plot_effect_comparison(
        runs, out / "fig6_effects.png", "NAO 0.2 m/s: trunk pitch per effect set"
    )


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else "walk_effects"))
