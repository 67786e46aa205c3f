"""Where each effect's numbers land in a compiled model: the builder's MJCF, without the MJCF.

:mod:`zmpkit.sim.builder` writes each effect as MJCF attributes; MuJoCo compiles them into
model fields. The functions here write the same numbers straight into those fields, one
row per candidate (a :class:`~zmpkit.sim.world_fields.FieldWrite`), exactly as the compiler
would have: each number is first rounded as the builder prints it (:func:`mjcf_number`,
10 significant digits) and then transformed as the compiler transforms it (a ``dcmotor``'s
electrical time constant ``L/R``).

- **M** (:func:`~zmpkit.sim.builder.add_motor`): the joint's ``frictionloss`` ->
  ``dof_frictionloss``; ``resistance`` -> ``actuator_gainprm[:, 0]``; the ``controller``
  (:func:`~zmpkit.sim.builder.dcmotor_controller`) gains -> ``actuator_gainprm[:, 4:7]``;
  ``damping`` -> ``actuator_damping``.
- **I**: ``inductance`` -> ``actuator_dynprm[:, 0] = L / R``.
- **G** (:func:`~zmpkit.sim.builder.add_gear_compliance`): the gear tendon's ``stiffness``,
  ``damping`` and dead band ``springlength = [-b/2, b/2]`` -> ``tendon_stiffness``,
  ``tendon_damping``, ``tendon_lengthspring``.
- **F** (:func:`~zmpkit.sim.builder.add_flex_joint`): ``stiffness[0]`` -> ``jnt_stiffness``,
  ``damping`` -> ``dof_damping``; a softening spring's stage tendons (dead band, stiffness
  step) too.
- **C** (a body's ``<inertial>``): ``mass``, ``pos``, ``diaginertia`` -> ``body_mass``,
  ``body_ipos``, ``body_inertia`` (and what ``mj_setConst`` derives from them:
  :data:`~zmpkit.sim.world_fields.SETCONST_FIELDS`).

Arrays are ``(ncandidate,)`` (one value per candidate, every element) or ``(ncandidate, k)``
(one per candidate and element). That the fields equal those of each candidate's compiled
MJCF is tested on every fit parameter of the robots' catalogues.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np
from numpy.typing import ArrayLike, NDArray

from zmpkit.sim.builder import GEAR_JOINT_SUFFIX
from zmpkit.sim.spring import softening_breakpoints, softening_segments
from zmpkit.sim.world_fields import FieldWrite

__all__ = [
    "dcmotor_writes",
    "flex_writes",
    "frictionloss_writes",
    "gear_writes",
    "inertial_writes",
    "mjcf_number",
    "softening_flex_writes",
]

_GAINS = slice(4, 7)
"""The controller's (kp, ki, kd) in ``actuator_gainprm`` of a ``dcmotor``."""
_RESISTANCE = 0
"""The winding resistance in ``actuator_gainprm`` of a ``dcmotor``."""
_TIME_CONSTANT = 0
"""The electrical time constant ``L/R`` in ``actuator_dynprm`` of a ``dcmotor``."""


def mjcf_number(values: ArrayLike) -> NDArray[np.float64]:
    """The numbers MuJoCo reads back from the builder's MJCF (``f"{v:.10g}"``), elementwise.

    Each distinct value is printed and read once (a batch repeats its values over joints).
    """
    array = np.asarray(values, dtype=np.float64)
    distinct, where = np.unique(array.ravel(), return_inverse=True)
    read = np.array([float(f"{v:.10g}") for v in distinct.tolist()], dtype=np.float64)
    return read[where].reshape(array.shape)


def _columns(values: ArrayLike, k: int) -> NDArray[np.float64]:
    """``values`` as ``(ncandidate, k)``: a ``(ncandidate,)`` column repeated over k."""
    array = np.asarray(values, dtype=np.float64)
    if array.ndim == 1:
        array = array[:, None]
    return np.broadcast_to(array, (array.shape[0], k))


def _flat(model: mujoco.MjModel, field: str, rows: Sequence[int], column: int) -> list[int]:
    """Flat indices of ``field[rows, column]`` (C order)."""
    width = int(np.prod(np.shape(getattr(model, field))[1:], dtype=np.int64))
    return [row * width + column for row in rows]


def _actuators(model: mujoco.MjModel, joints: Sequence[str]) -> list[int]:
    return [int(model.actuator(j).id) for j in joints]


def frictionloss_writes(
    model: mujoco.MjModel, joints: Sequence[str], coulomb: ArrayLike
) -> list[FieldWrite]:
    """A driven joint's ``frictionloss`` [N·m] (M: the motor's Coulomb friction at the link)."""
    dofs = [int(model.jnt_dofadr[model.joint(j).id]) for j in joints]
    return [FieldWrite.of("dof_frictionloss", dofs, mjcf_number(_columns(coulomb, len(dofs))))]


def dcmotor_writes(
    model: mujoco.MjModel,
    joints: Sequence[str],
    gains: tuple[ArrayLike, ArrayLike, ArrayLike] | None = None,
    resistance: ArrayLike | None = None,
    inductance: ArrayLike | None = None,
    damping: ArrayLike | None = None,
) -> list[FieldWrite]:
    """The fields of the ``dcmotor`` of each of ``joints`` (effects M and I).

    Args:
        model: the compiled template.
        joints: the driven joints (each actuator is named after its joint).
        gains: the controller's motor-side (kp, ki, kd)
            (:func:`~zmpkit.sim.builder.dcmotor_controller`'s first three); None: unchanged.
        resistance: the winding resistance [Ω]; None: unchanged.
        inductance: the winding inductance [H] (I on); needs ``resistance``, since the
            compiler keeps ``L / R``; None: unchanged.
        damping: the rotor's viscous friction [N·m·s/rad]; None: unchanged.
    """
    ids = _actuators(model, joints)
    k = len(ids)
    writes = []
    if gains is not None:
        for column, gain in enumerate(gains, start=_GAINS.start):
            values = mjcf_number(_columns(gain, k))
            writes.append(
                FieldWrite.of(
                    "actuator_gainprm", _flat(model, "actuator_gainprm", ids, column), values
                )
            )
    if resistance is not None:
        ohms = mjcf_number(_columns(resistance, k))
        index = _flat(model, "actuator_gainprm", ids, _RESISTANCE)
        writes.append(FieldWrite.of("actuator_gainprm", index, ohms))
        if inductance is not None:
            henry = mjcf_number(_columns(inductance, k))
            index = _flat(model, "actuator_dynprm", ids, _TIME_CONSTANT)
            writes.append(FieldWrite.of("actuator_dynprm", index, henry / ohms))
    if damping is not None:
        writes.append(FieldWrite.of("actuator_damping", ids, mjcf_number(_columns(damping, k))))
    return writes


def gear_writes(
    model: mujoco.MjModel,
    joints: Sequence[str],
    stiffness: ArrayLike,
    damping: ArrayLike,
    backlash: ArrayLike,
) -> list[FieldWrite]:
    """The gear tendon of each of ``joints`` (G).

    Its stiffness [N·m/rad], damping [N·m·s/rad] and the dead band ``[-b/2, b/2]`` of the
    backlash ``b`` [rad].
    """
    ids = [int(model.tendon(j + GEAR_JOINT_SUFFIX).id) for j in joints]
    k = len(ids)
    half = 0.5 * _columns(backlash, k)
    band = np.stack([mjcf_number(-half), mjcf_number(half)], axis=-1).reshape(-1, 2 * k)
    lower = _flat(model, "tendon_lengthspring", ids, 0)
    index = [i for low in lower for i in (low, low + 1)]
    return [
        FieldWrite.of("tendon_stiffness", ids, mjcf_number(_columns(stiffness, k))),
        FieldWrite.of("tendon_damping", ids, mjcf_number(_columns(damping, k))),
        FieldWrite.of("tendon_lengthspring", index, band),
    ]


def flex_writes(
    model: mujoco.MjModel, joints: Sequence[str], stiffness: ArrayLike, damping: ArrayLike
) -> list[FieldWrite]:
    """Flexible-link joints with polynomial springs (F).

    The linear stiffness ``k1`` [N·m/rad] and the damping [N·m·s/rad] of each of ``joints``.
    """
    ids = [int(model.joint(j).id) for j in joints]
    dofs = [int(model.jnt_dofadr[i]) for i in ids]
    return [
        FieldWrite.of("jnt_stiffness", ids, mjcf_number(_columns(stiffness, len(ids)))),
        FieldWrite.of("dof_damping", dofs, mjcf_number(_columns(damping, len(dofs)))),
    ]


def softening_flex_writes(
    model: mujoco.MjModel,
    joint: str,
    stiffness: ArrayLike,
    softening_torque: ArrayLike,
    torque_range: ArrayLike,
    stages: int,
    damping: ArrayLike,
) -> list[FieldWrite]:
    """A flexible-link joint with a softening spring (F; :mod:`zmpkit.sim.spring`).

    ``(ncandidate,)`` columns of its ``k0`` [N·m/rad], ``τ_s`` and ``τ_max`` [N·m] and
    damping [N·m·s/rad]: the joint's first-segment stiffness and damping, and each stage
    tendon's dead band ``[-δ_j, δ_j]`` [rad] and stiffness step [N·m/rad].
    """
    n = np.shape(stiffness)[0]
    k0 = _columns(stiffness, 1)[:, 0]
    points = softening_breakpoints(
        k0, _columns(softening_torque, 1)[:, 0], _columns(torque_range, 1)[:, 0], stages
    )
    segments = softening_segments(points, _columns(torque_range, 1)[:, 0], stages)
    writes = flex_writes(model, [joint], np.asarray(segments[0]).reshape(n), damping)
    for j in range(1, stages):
        tendon = int(model.tendon(f"{joint}_stage{j}").id)
        edge = np.asarray(points[j])
        band = np.stack([mjcf_number(-edge), mjcf_number(edge)], axis=-1)
        index = _flat(model, "tendon_lengthspring", [tendon], 0)
        step = np.asarray(segments[j] - segments[j - 1])
        writes += [
            FieldWrite.of("tendon_lengthspring", [index[0], index[0] + 1], band),
            FieldWrite.of("tendon_stiffness", [tendon], mjcf_number(step)),
        ]
    return writes


def inertial_writes(
    model: mujoco.MjModel, body: str, mass: ArrayLike, com: ArrayLike, inertia: ArrayLike
) -> list[FieldWrite]:
    """A body's ``<inertial>`` (C).

    Its mass [kg], CoM ``(ncandidate, 3)`` [m, body frame] and diagonal inertia
    ``(ncandidate, 3)`` [kg·m²]. The fields derived from them: ``mj_setConst``.
    """
    b = int(model.body(body).id)
    return [
        FieldWrite.of("body_mass", [b], mjcf_number(_columns(mass, 1))),
        FieldWrite.of("body_ipos", [3 * b, 3 * b + 1, 3 * b + 2], mjcf_number(com)),
        FieldWrite.of("body_inertia", [3 * b, 3 * b + 1, 3 * b + 2], mjcf_number(inertia)),
    ]
