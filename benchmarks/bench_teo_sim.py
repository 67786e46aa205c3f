"""Benchmark of the virtual TEO: simulated seconds per wall second, standing 10 s.

Usage::

    python benchmarks/bench_teo_sim.py [--json PATH] [--seconds S] [--repeats N]

Measures in one run (best of ``--repeats``), TEO standing upright under its joint controllers:

1. ``all effects``: :func:`zmpkit.robots.teo.make_teo` with M, I, G, F, S on, stepped by
   :meth:`~zmpkit.sim.Simulation.run` (servo interpolation, F-T sampling with sensor errors,
   divergence checks: the per-step Python of the simulator);
2. ``all effects, C loop``: the same MJCF stepped by ``mujoco.mj_step(m, d, nstep=N)`` with the
   setpoints held — the native part of (1) alone, to show where its cost goes;
3. ``effects off``: ``make_teo("none")`` stepped by :meth:`Simulation.run`;
4. ``bare rigid MJCF, C loop``: the rigid model (effects off: native ``pid`` joint servos)
   stepped by ``mujoco.mj_step(m, d, nstep=N)`` — the reference, with no Python per step.

``mujoco.mj_step`` takes ``nstep`` in MuJoCo 4.0.0 and loops in C. Ratios are the wall-time
cost of each row relative to the bare rigid C loop. Speed is reported, never asserted.
Target of issue 3: all effects cost <= 1.5x the rigid model (stretch 1.2x).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import mujoco

from harness import base_parser, environment, print_table, write_json
from zmpkit.robots.teo import make_teo, teo_mjcf

__all__ = ["main"]

DEFAULT_SECONDS = 10.0
DEFAULT_REPEATS = 3


def best_wall(run: Callable[[], None], make: Callable[[], object], repeats: int) -> float:
    """Best wall time of ``run`` over ``repeats`` fresh set-ups made by ``make`` [s]."""
    best = float("inf")
    for _ in range(repeats):
        state = make()
        start = time.perf_counter()
        run(state)  # type: ignore[call-arg]
        best = min(best, time.perf_counter() - start)
    return best


def c_loop(effects: str, seconds: float, repeats: int) -> float:
    """Wall time of ``seconds`` of standing, stepped by ``mj_step(..., nstep)`` in C [s]."""
    model = mujoco.MjModel.from_xml_string(teo_mjcf(effects))
    nstep = round(seconds / model.opt.timestep)

    def make() -> mujoco.MjData:
        data = mujoco.MjData(model)
        data.ctrl[:] = 0.0  # setpoints of the upright pose: every joint at 0
        mujoco.mj_forward(model, data)
        return data

    return best_wall(lambda d: mujoco.mj_step(model, d, nstep=nstep), make, repeats)


def simulation(effects: str, seconds: float, repeats: int) -> float:
    """Wall time of ``seconds`` of standing through :meth:`Simulation.run` [s]."""
    return best_wall(lambda sim: sim.run(seconds), lambda: make_teo(effects), repeats)


def measure(seconds: float, repeats: int) -> list[dict[str, Any]]:
    """Rows: case, wall time [s], simulated s per wall s, cost relative to the bare C loop."""
    cases = {
        "all effects (Simulation.run)": lambda: simulation("all", seconds, repeats),
        "all effects, C loop (native part)": lambda: c_loop("all", seconds, repeats),
        "effects off (Simulation.run)": lambda: simulation("none", seconds, repeats),
        "bare rigid MJCF, C loop": lambda: c_loop("none", seconds, repeats),
    }
    walls = {name: run() for name, run in cases.items()}
    bare = walls["bare rigid MJCF, C loop"]
    return [
        {
            "case": name,
            "wall_s": wall,
            "sim_s_per_wall_s": seconds / wall,
            "cost_vs_bare_rigid": wall / bare,
        }
        for name, wall in walls.items()
    ]


def show(rows: list[dict[str, Any]], seconds: float) -> None:
    """Print the rows as a table (rich if available)."""
    cells = [
        (
            r["case"],
            f"{r['wall_s']:.3f}",
            f"{r['sim_s_per_wall_s']:.1f}",
            f"{r['cost_vs_bare_rigid']:.2f}x",
        )
        for r in rows
    ]
    print_table(
        f"virtual TEO standing {seconds:g} s (best of repeats)",
        ("case", "wall (s)", "sim s / wall s", "cost vs bare rigid"),
        cells,
        justify=("left", "right", "right", "right"),
    )


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark, print a table, write JSON if asked; returns the exit status."""
    parser = base_parser(__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=DEFAULT_SECONDS)
    parser.add_argument("--repeats", type=int, default=DEFAULT_REPEATS)
    args = parser.parse_args(argv)
    rows = measure(args.seconds, args.repeats)
    show(rows, args.seconds)
    if args.json is not None:
        env = environment()
        # "python" is the bare version here, as this JSON always had it.
        info = {"mujoco": mujoco.__version__, **env, "python": env["python_version"]}
        payload = {"seconds": args.seconds, "repeats": args.repeats, "env": info, "rows": rows}
        write_json(args.json, payload)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
