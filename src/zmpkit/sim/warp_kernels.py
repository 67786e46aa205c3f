r"""The Warp kernels of a batched rollout's step loop (:mod:`zmpkit.sim.warp_batch`).

Each physics step of :func:`~zmpkit.sim.warp_batch.rollout_warp` launches, around
``mujoco_warp.step``, these kernels over the worlds (and columns):

- ``set_ctrl``: each world's ``ctrl`` from its control sequence at the step counter;
- ``check``: the first step at which a world's ``qpos``, ``qvel`` or ``act`` is non-finite
  or a ``|qvel|`` passes the divergence limit [rad/s];
- ``record``, ``record_vec3``, ``record_mat33``: the asked columns of a ``mjData`` array
  (scalars, ``site_xpos`` vectors, ``site_xmat`` matrices row-major) into the row of the
  current step, when that step is recorded: one kernel per value type, the branch of its
  width chosen when Warp builds it (``wp.static``);
- ``square_error``: a world's :math:`\sum_j (q_j - q^{target}_j)^2` at its target rows,
  each :math:`q_j` rounded to its encoder quantum first, added to its total (float64);
- ``advance``: the step counter, on the device, so a captured graph replays unchanged.

The step counter lives on the device: nothing in a step depends on the host, which is
what lets CUDA capture many steps in one graph.

This module does not import ``from __future__ import annotations``: Warp reads the
annotations of the kernels at run time.
"""

import functools
from typing import Any

__all__ = ["step_kernels"]


@functools.cache
def step_kernels() -> dict[str, Any]:
    """The Warp kernels of the step loop, by name, built once per process."""
    import warp as wp

    control, records = _control_kernels(wp), _record_kernels(wp)
    return {
        "set_ctrl": control["set_ctrl"],
        "check": control["check"],
        **records,
        "square_error": _square_error(wp),
        "advance": control["advance"],
    }


# Warp's kernel DSL reads the kernels' annotations at run time: its array types are calls,
# which no static checker accepts as types, hence the ignores on each kernel parameter.


def _control_kernels(wp: Any) -> dict[str, Any]:
    """``set_ctrl``, ``check`` and ``advance``: a step's controls, its check, its counter."""

    @wp.kernel(enable_backward=False)
    def set_ctrl(
        control: wp.array3d(dtype=float),  # type: ignore[valid-type]  # Warp's kernel DSL
        group: wp.array(dtype=wp.int32),  # type: ignore[valid-type]  # Warp's kernel DSL
        counter: wp.array(dtype=wp.int32),  # type: ignore[valid-type]  # Warp's kernel DSL
        ctrl: wp.array2d(dtype=float),  # type: ignore[valid-type]  # Warp's kernel DSL
    ):
        world, j = wp.tid()
        ctrl[world, j] = control[group[world], counter[0], j]

    @wp.kernel(enable_backward=False)
    def check(
        qpos: wp.array2d(dtype=float),  # type: ignore[valid-type]  # Warp's kernel DSL
        qvel: wp.array2d(dtype=float),  # type: ignore[valid-type]  # Warp's kernel DSL
        act: wp.array2d(dtype=float),  # type: ignore[valid-type]  # Warp's kernel DSL
        counter: wp.array(dtype=wp.int32),  # type: ignore[valid-type]  # Warp's kernel DSL
        limit: wp.float64,
        never: wp.int32,
        first_bad: wp.array(dtype=wp.int32),  # type: ignore[valid-type]  # Warp's kernel DSL
    ):
        world = wp.tid()
        if first_bad[world] != never:
            return
        bad = wp.int32(0)  # a dynamic variable (a constant cannot change in a loop)
        for i in range(qpos.shape[1]):
            if not wp.isfinite(qpos[world, i]):
                bad = 1
        for i in range(qvel.shape[1]):
            if not (wp.isfinite(qvel[world, i]) and wp.float64(wp.abs(qvel[world, i])) <= limit):
                bad = 1
        for i in range(act.shape[1]):
            if not wp.isfinite(act[world, i]):
                bad = 1
        if bad != 0:
            first_bad[world] = counter[0] + 1

    @wp.kernel(enable_backward=False)
    def advance(counter: wp.array(dtype=wp.int32)):  # type: ignore[valid-type]  # Warp's kernel DSL
        counter[0] = counter[0] + 1

    return {"set_ctrl": set_ctrl, "check": check, "advance": advance}


def _record_kernels(wp: Any) -> dict[str, Any]:
    """``record``, ``record_vec3`` and ``record_mat33``: a step's columns into its row."""
    return {
        "record": _record_kernel(wp, float, 1),
        "record_vec3": _record_kernel(wp, wp.vec3, 3),
        "record_mat33": _record_kernel(wp, wp.mat33, 9),
    }


def _record_kernel(wp: Any, value: Any, width: int) -> Any:
    """The kernel that records a ``value`` column (``width`` floats: 1, 3 or 9) into its row."""

    @wp.kernel(enable_backward=False)
    def record(
        source: wp.array2d(dtype=value),  # type: ignore[valid-type]  # Warp's kernel DSL
        columns: wp.array(dtype=wp.int32),  # type: ignore[valid-type]  # Warp's kernel DSL
        counter: wp.array(dtype=wp.int32),  # type: ignore[valid-type]  # Warp's kernel DSL
        row_of_step: wp.array(dtype=wp.int32),  # type: ignore[valid-type]  # Warp's kernel DSL
        out: wp.array3d(dtype=float),  # type: ignore[valid-type]  # Warp's kernel DSL
    ):
        world, i = wp.tid()
        row = row_of_step[counter[0]]
        if row >= 0:
            if wp.static(width == 1):
                out[row, world, i] = source[world, columns[i]]
            elif wp.static(width == 3):
                v = source[world, columns[i]]
                for k in range(3):
                    out[row, world, 3 * i + k] = v[k]
            else:
                m = source[world, columns[i]]
                for r in range(3):
                    for c in range(3):
                        out[row, world, 9 * i + 3 * r + c] = m[r, c]

    return record


def _square_error(wp: Any) -> Any:
    """``square_error``: a world's squared joint errors at its target rows, summed."""

    @wp.kernel(enable_backward=False)
    def square_error(
        qpos: wp.array2d(dtype=float),  # type: ignore[valid-type]  # Warp's kernel DSL
        columns: wp.array(dtype=wp.int32),  # type: ignore[valid-type]  # Warp's kernel DSL
        quantum: wp.array(dtype=wp.float64),  # type: ignore[valid-type]  # Warp's kernel DSL
        group: wp.array(dtype=wp.int32),  # type: ignore[valid-type]  # Warp's kernel DSL
        counter: wp.array(dtype=wp.int32),  # type: ignore[valid-type]  # Warp's kernel DSL
        row_of_step: wp.array2d(dtype=wp.int32),  # type: ignore[valid-type]  # Warp's kernel DSL
        target: wp.array3d(dtype=wp.float64),  # type: ignore[valid-type]  # Warp's kernel DSL
        total: wp.array(dtype=wp.float64),  # type: ignore[valid-type]  # Warp's kernel DSL
    ):
        world = wp.tid()
        g = group[world]
        row = row_of_step[g, counter[0]]
        if row < 0:
            return
        s = wp.float64(0.0)
        for j in range(columns.shape[0]):
            q = wp.float64(qpos[world, columns[j]])
            if quantum[j] > wp.float64(0.0):
                q = wp.round(q / quantum[j]) * quantum[j]
            y = target[g, row, j]
            if wp.isfinite(y):
                d = q - y
                s = s + d * d
        total[world] = total[world] + s

    return square_error
