"""The step loop of a batched Warp rollout: one physics step of every world, and many.

Each step launches, around ``mujoco_warp.step``, the kernels of
:mod:`~zmpkit.sim.warp_kernels`: the controls, the divergence check, the records and the
squared joint errors, then the step counter. On CUDA the steps are captured as graphs of
``per_launch`` steps and replayed; on the CPU they run as a loop of launches.
"""

from collections.abc import Callable
from typing import Any

import mujoco
import numpy as np

from zmpkit.sim.warp_kernels import step_kernels
from zmpkit.sim.warp_session import Plan, Session
from zmpkit.sim.world import DIVERGED_SPEED_RAD_S

__all__ = ["NEVER_FAILED", "one_step", "run_steps"]

_FULL = int(mujoco.mjtState.mjSTATE_FULLPHYSICS)
NEVER_FAILED = np.iinfo(np.int32).max
"""The first failing step of a world that never failed."""


def one_step(wp: Any, mjw: Any, session: Session, plan: Plan) -> Callable[[], None]:
    """One physics step of every world: controls, step, divergence check, records."""
    k = step_kernels()
    m, d = session.m, session.d
    nworld, nu = d.nworld, session.template.nu
    launches = _record_launches(k, session, plan)
    limit, never = wp.float64(DIVERGED_SPEED_RAD_S), wp.int32(NEVER_FAILED)
    sq = plan.square

    def step() -> None:
        if nu:
            wp.launch(
                k["set_ctrl"],
                dim=(nworld, nu),
                inputs=[plan.control, plan.group, plan.counter],
                outputs=[d.ctrl],
            )
        mjw.step(m, d)
        wp.launch(
            k["check"],
            dim=nworld,
            inputs=[d.qpos, d.qvel, d.act, plan.counter, limit, never],
            outputs=[plan.first_bad],
        )
        if plan.scratch is not None:
            mjw.get_state(m, d, plan.scratch, _FULL, plan.every_world)
        for kernel, source, cols, out, ncols in launches:
            if not ncols:
                continue
            wp.launch(
                kernel,
                dim=(nworld, ncols),
                inputs=[source, cols, plan.counter, plan.row_of_step],
                outputs=[out],
            )
        if sq is not None:
            wp.launch(
                k["square_error"],
                dim=nworld,
                inputs=[
                    d.qpos,
                    sq.columns,
                    sq.quantum,
                    plan.group,
                    plan.counter,
                    sq.row_of_step,
                    sq.target,
                ],
                outputs=[sq.total],
            )
        wp.launch(k["advance"], dim=1, inputs=[plan.counter])

    return step


def _record_launches(
    k: dict[str, Any], session: Session, plan: Plan
) -> list[tuple[Any, Any, Any, Any, int]]:
    """Per recorded array: (kernel, source, columns, output, columns launched)."""
    d = session.d
    sources = {
        "qpos": d.qpos,
        "qvel": d.qvel,
        "act": d.act,
        "sensordata": d.sensordata,
        "state": plan.scratch,
    }
    launches = []
    for name, out in plan.outputs.items():
        cols = plan.columns[name]
        if name == "site_xpos":
            launches.append((k["record_vec3"], d.site_xpos, cols, out, cols.shape[0]))
        elif name == "site_xmat":
            launches.append((k["record_mat33"], d.site_xmat, cols, out, cols.shape[0]))
        else:
            launches.append((k["record"], sources[name], cols, out, cols.shape[0]))
    return launches


def run_steps(wp: Any, step: Callable[[], None], plan: Plan, nstep: int, per_launch: int) -> None:
    """``nstep`` steps: on CUDA as replays of captured graphs of ``per_launch`` steps."""
    if not wp.get_device().is_cuda:
        for _ in range(nstep):
            step()
        return
    done = 0
    if not plan.graphs:  # the first step runs eagerly: it compiles and loads the modules
        step()
        done = 1
    while done < nstep:
        count = min(per_launch, nstep - done)
        if count not in plan.graphs:
            with wp.ScopedCapture() as capture:
                for _ in range(count):
                    step()
            plan.graphs[count] = capture.graph
        wp.capture_launch(plan.graphs[count])
        done += count
