"""MuJoCo Warp, imported and started for zmpkit, and its devices.

Warp is imported only when a batch runs (``pip install 'zmpkit[gpu]'``); it starts with
zmpkit's persistent kernel cache (:mod:`~zmpkit.sim.warp_cache`) and logs warnings only.
"""

from typing import Any

from zmpkit.errors import ParameterError
from zmpkit.sim.warp_cache import configure_kernel_cache

__all__ = ["import_warp", "warp_device", "warp_runtime"]

_INSTALL_HINT = "pip install 'zmpkit[gpu]'"  # the extra: mujoco-warp==4.0.0 (brings warp-lang)


def import_warp() -> tuple[Any, Any]:
    """The ``warp`` and ``mujoco_warp`` modules, Warp configured (module docstring).

    Raises:
        ModuleNotFoundError: MuJoCo Warp is not installed (``pip install 'zmpkit[gpu]'``).
    """
    try:
        import mujoco_warp
        import warp
    except ImportError as exc:
        raise ModuleNotFoundError(
            f"rollout_warp needs MuJoCo Warp, which is not installed ({exc}); "
            f"install it with: {_INSTALL_HINT}"
        ) from exc
    configure_kernel_cache(warp)  # before warp.init(): zmpkit's persistent kernel cache
    _quiet_warp(warp)
    return warp, mujoco_warp


def _quiet_warp(wp: Any) -> None:
    """Warp's log level raised from its default (info) to warnings.

    At info Warp prints its start-up banner and a line per kernel module it loads (about 60
    per fit), which would bury a command's own output; warnings (a missing CUDA driver, a
    kernel that failed to compile) still show. A level other than the default is kept.
    """
    if wp.config.log_level == wp.LOG_INFO:
        wp.config.log_level = wp.LOG_WARNING


def warp_runtime(device: str | None = None) -> tuple[Any, str]:
    """Warp, started with zmpkit's kernel cache, and the name of ``device`` on it.

    Args:
        device: Warp device (``"cuda:0"``, ``"cpu"``); ``None`` is Warp's default.

    Returns:
        The ``warp`` module and the device's name, e.g. ``"cuda:0"`` or ``"cpu"``.

    Raises:
        ModuleNotFoundError: MuJoCo Warp is not installed (``pip install 'zmpkit[gpu]'``).
        ParameterError: an unknown device.
    """
    wp, _ = import_warp()
    return wp, str(warp_device(wp, device))


def warp_device(wp: Any, device: str | None) -> Any:
    """The Warp device named ``device`` (``None``: Warp's default), or an error naming the valid."""
    try:
        return wp.get_device(device)
    except (RuntimeError, ValueError) as exc:
        valid = [str(d) for d in wp.get_devices()]
        raise ParameterError(f"unknown Warp device {device!r}; available: {valid}") from exc
