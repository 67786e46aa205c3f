"""Benchmark of batched rollouts: MuJoCo Warp (:func:`rollout_warp`) against CPU MuJoCo.

Usage::

    python benchmarks/bench_warp_batch.py [--device cpu|cuda:0] [--nbatch N] [--steps S]
                                          [--record-every K] [--record full|cost]
                                          [--steps-per-launch L] [--repeats R] [--json PATH]

A batch is ``--nbatch`` NAO models (M, G and S on: dcmotor actuators, tendon gears), one
per candidate of a CMA-ES generation (PID gain scale and gear stiffness spread over their
bounds), rolled out ``--steps`` steps of 1 ms from standing under a 2 Hz setpoint wave.
Measured in the same run, best of ``--repeats``:

1. ``mujoco.rollout`` on ``os.cpu_count()`` threads (the CPU baseline);
2. :func:`~zmpkit.sim.warp_batch.rollout_warp` on ``--device``, ``--steps-per-launch``
   steps per captured graph on CUDA; its first call (kernel compilation or cache load,
   the Warp model and data, graph capture on CUDA) is reported apart: the later calls
   reuse the model, data and graphs (the candidates' fields and states copied in).

Both record state and sensordata after every step by default (``mujoco.rollout`` always
does; ``--record-every`` thins Warp's records only). ``--record cost`` records on Warp
what the fit's signals read instead: ``qpos``, ``sensordata`` and the site kinematics
every ``--record-every`` steps, no full state. Throughput is in physics steps per second
summed over the batch. Ratios are reported, never asserted. Without ``mujoco_warp``
installed it says so and exits 0.

Candidates drawn over the bounds include unstable ones (a low P gain on a soft gear), whose
rollouts diverge and restart at every step, flooding the log with MuJoCo's QACC warnings
(a batch of 4096 did not end in 60 s). They are excluded before timing: every drawn
candidate is rolled out once on the CPU (MuJoCo's warnings routed to a debug logger), one
that diverged (its time went back) is dropped, and candidates are drawn until ``--nbatch``
stable ones remain; the table's title says how many were dropped.
"""

from __future__ import annotations

import importlib.util
import os
import time
from typing import Any

import mujoco
import numpy as np
from mujoco import rollout

from harness import base_parser, print_table, write_run
from zmpkit.robots.nao import make_nao
from zmpkit.robots.registry import get_robot
from zmpkit.sim.mujoco_messages import route_mujoco_warnings
from zmpkit.simfit.parameters import default_parameters
from zmpkit.simfit.truth_doc import (
    base_truth_path,
    load_robot_truth,
    load_truth_doc,
    truth_doc_with,
)

__all__ = ["main"]

EFFECTS = "M,G,S"
FULL = mujoco.mjtState.mjSTATE_FULLPHYSICS


def batch(
    nbatch: int, nstep: int, nthread: int
) -> tuple[list[mujoco.MjModel], np.ndarray, np.ndarray, int]:
    """``nbatch`` stable candidate models, the standing state, ``nstep`` steps of setpoints,
    and how many unstable candidates were drawn and dropped."""
    params = default_parameters(get_robot("nao"), "M,G", ("pid_gain_scale", "gear_stiffness"))
    doc = load_truth_doc(base_truth_path(get_robot("nao"), None))
    rng = np.random.default_rng(0)
    sim = make_nao(EFFECTS, None, seed=0)
    state = np.empty(mujoco.mj_stateSize(sim.model, FULL))
    mujoco.mj_getState(sim.model, sim.data, state, FULL)
    t = (np.arange(nstep) + 1) * sim.dt
    control = 0.05 * np.outer(np.sin(2 * np.pi * 2.0 * t), sim.model.actuator_gear[:, 0])
    models: list[mujoco.MjModel] = []
    dropped = 0
    while len(models) < nbatch:
        drawn = []
        for _ in range(min(SCREEN_CHUNK, nbatch - len(models))):
            values = [p.from_unit(float(rng.uniform(0.1, 0.9))) for p in params]
            truth = load_robot_truth(get_robot("nao"), truth_doc_with(doc, params, values))
            drawn.append(make_nao(EFFECTS, truth, seed=0).model)
        keep = stable(drawn, state, control, nthread)
        models += [m for m, k in zip(drawn, keep, strict=True) if k]
        dropped += int(np.count_nonzero(~keep))
    return models, state, control, dropped


SCREEN_CHUNK = 256
"""Candidates screened per CPU rollout (bounds the recorded states' memory)."""


def stable(
    models: list[mujoco.MjModel], state: np.ndarray, control: np.ndarray, nthread: int
) -> np.ndarray:
    """Whether each model's rollout from ``state`` under ``control`` stays stable.

    MuJoCo resets a diverging simulation (time back to its start) and warns; a rollout
    whose last time is not its start plus its steps diverged. The warnings go to zmpkit's
    debug logger, not to the console.
    """
    route_mujoco_warnings()
    n, nstep = len(models), len(control)
    datas = [mujoco.MjData(models[0]) for _ in range(nthread)]
    with rollout.Rollout(nthread=nthread) as pool:
        states, _ = pool.rollout(models, datas, np.tile(state, (n, 1)), np.tile(control, (n, 1, 1)))
    end = state[0] + nstep * models[0].opt.timestep
    return np.isclose(states[:, -1, 0], end, atol=0.5 * models[0].opt.timestep)


def best_wall(run: Any, repeats: int) -> float:
    """Best wall time of ``run()`` over ``repeats`` calls [s]."""
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        best = min(best, time.perf_counter() - start)
    return best


COST_RECORDS = ("qpos", "sensordata", "site_xpos", "site_xmat")
"""What the fit's signals read of each row (``zmpkit.simfit.warp_batched``)."""


def measure(
    device: str, nbatch: int, nstep: int, every: int, repeats: int, record: str, per_launch: int
) -> dict[str, Any]:
    """Walls of the CPU baseline and of MuJoCo Warp, and Warp's first call [s]."""
    from zmpkit.sim.warp_batch import rollout_warp

    names = ("state", "sensordata") if record == "full" else COST_RECORDS

    def warp() -> Any:
        return rollout_warp(
            models, state, control, every, device, record=names, steps_per_launch=per_launch
        )

    nthread = os.cpu_count() or 1
    models, state, control, dropped = batch(nbatch, nstep, nthread)
    datas = [mujoco.MjData(models[0]) for _ in range(nthread)]
    states, controls = np.tile(state, (nbatch, 1)), np.tile(control, (nbatch, 1, 1))
    with rollout.Rollout(nthread=nthread) as pool:
        cpu_s = best_wall(lambda: pool.rollout(models, datas, states, controls), repeats)
    start = time.perf_counter()
    out = warp()
    first_s = time.perf_counter() - start
    warp_s = best_wall(warp, repeats)
    steps = nbatch * (nstep // every) * every
    return {
        "device": out.device,
        "rows": [
            {"backend": f"mujoco.rollout ({nthread} threads)", "wall_s": cpu_s, "steps": steps},
            {
                "backend": f"rollout_warp ({out.device}, record {record}, {per_launch}/launch)",
                "wall_s": warp_s,
                "steps": steps,
            },
        ],
        "warp_first_call_s": first_s,
        "warp_diverged": int(out.diverged.sum()),
        "unstable_dropped": dropped,
    }


def show(result: dict[str, Any], nbatch: int, nstep: int) -> None:
    """Print the rows as a table (rich if available)."""
    base = result["rows"][0]["wall_s"]
    cells = [
        (
            r["backend"],
            f"{r['wall_s']:.3f}",
            f"{r['steps'] / r['wall_s']:,.0f}",
            f"{base / r['wall_s']:.2f}x",
        )
        for r in result["rows"]
    ]
    title = (
        f"batched rollouts: {nbatch} NAO ({EFFECTS}) candidates x {nstep} steps of 1 ms; "
        f"Warp first call {result['warp_first_call_s']:.1f} s, "
        f"{result['warp_diverged']} diverged; {result['unstable_dropped']} unstable "
        "candidates dropped before timing"
    )
    print_table(
        title,
        ("backend", "wall (s)", "steps / s", "vs CPU"),
        cells,
        justify=("left", "right", "right", "right"),
    )


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark, print a table, write JSON if asked; returns the exit status."""
    parser = base_parser(__doc__.splitlines()[0])
    parser.add_argument("--device", default=None, help="Warp device; default: Warp's default")
    parser.add_argument("--nbatch", type=int, default=16)
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--record-every", type=int, default=1)
    parser.add_argument("--record", choices=("full", "cost"), default="full")
    parser.add_argument("--steps-per-launch", type=int, default=50)
    parser.add_argument("--repeats", type=int, default=2)
    args = parser.parse_args(argv)
    if importlib.util.find_spec("mujoco_warp") is None:
        print("mujoco_warp is not installed: nothing to measure (pip install 'zmpkit[gpu]')")
        return 0
    result = measure(
        args.device,
        args.nbatch,
        args.steps,
        args.record_every,
        args.repeats,
        args.record,
        args.steps_per_launch,
    )
    show(result, args.nbatch, args.steps)
    write_run(args, result)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
