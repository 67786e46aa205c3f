"""MuJoCo's warnings routed to Python logging instead of stdout and ``MUJOCO_LOG.TXT``.

MuJoCo reports a diverging simulation ("Nan, Inf or huge value in QACC at DOF 0. The
simulation is unstable.") by printing it and appending it to ``MUJOCO_LOG.TXT`` in the
working folder. A fit evaluates thousands of candidates, some of which diverge on purpose
(the bounds are wide); zmpkit detects that from the warning counters
(``data.warning[mjWARN_BADQACC]``), charges the candidate the failure cost, and carries on,
so the printed lines are noise and the log file litter. :func:`route_mujoco_warnings`
sends them to the ``zmpkit.mujoco`` logger at debug level instead (``logging`` with level
DEBUG shows them). The ``zmpkit`` command installs it; a library user may call it, and it
never replaces a handler someone else installed.
"""

from __future__ import annotations

import logging

import mujoco

__all__ = ["LOGGER_NAME", "route_mujoco_warnings"]

LOGGER_NAME = "zmpkit.mujoco"
"""The logger MuJoCo's warnings go to, at debug level."""
_LOG = logging.getLogger(LOGGER_NAME)


def _to_log(message: str) -> None:
    _LOG.debug("MuJoCo warning: %s", message)


def route_mujoco_warnings() -> bool:
    """Install the handler unless another one is installed; True if ours is in place."""
    current = mujoco.get_mju_user_warning()
    if current is _to_log:
        return True
    if current is not None:
        return False
    mujoco.set_mju_user_warning(_to_log)
    return True
