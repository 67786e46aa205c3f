"""Where MuJoCo Warp's compiled kernels are kept between runs (the persistent kernel cache).

Warp compiles its kernels (CUDA or, on its CPU device, LLVM) on first use and keeps them in
a kernel cache; a fresh machine compiles for minutes. zmpkit points that cache at a folder
of its own, fixed before ``warp.init()``:

- ``$ZMPKIT_CACHE_DIR/warp`` when ``ZMPKIT_CACHE_DIR`` is set (and not empty);
- else ``$XDG_CACHE_HOME/zmpkit/warp`` when ``XDG_CACHE_HOME`` is an absolute path;
- else ``~/.cache/zmpkit/warp``.

Warp adds a folder per Warp version below it (``.../warp/1.19.0``), so an upgrade never
loads stale kernels. Warp's own setting wins: with ``WARP_CACHE_PATH`` in the environment,
or ``warp.config.kernel_cache_dir`` set (or Warp initialised) before zmpkit loads MuJoCo
Warp, zmpkit leaves the location alone. ``zmpkit warp warm-up`` fills the cache.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

__all__ = ["CACHE_ENV", "cache_file_count", "configure_kernel_cache", "warp_cache_base"]

CACHE_ENV = "ZMPKIT_CACHE_DIR"
"""Environment variable naming zmpkit's cache folder (Warp's kernels go in its ``warp``)."""
_WARP_ENV = "WARP_CACHE_PATH"


def warp_cache_base(environ: Mapping[str, str] | None = None) -> Path:
    """The folder zmpkit gives Warp for its kernel cache (Warp adds a version folder below).

    Args:
        environ: the environment to read (``os.environ`` if ``None``).
    """
    env = os.environ if environ is None else environ
    own = env.get(CACHE_ENV, "")
    if own:
        return Path(own).expanduser() / "warp"
    xdg = env.get("XDG_CACHE_HOME", "")
    root = Path(xdg) if xdg and Path(xdg).is_absolute() else Path("~/.cache").expanduser()
    return root / "zmpkit" / "warp"


def configure_kernel_cache(wp: Any, environ: Mapping[str, str] | None = None) -> bool:
    """Point Warp's kernel cache at :func:`warp_cache_base` unless Warp's own setting wins.

    Call it after ``import warp`` and before ``warp.init()``; afterwards it changes nothing.

    Args:
        wp: the ``warp`` module.
        environ: the environment to read (``os.environ`` if ``None``).

    Returns:
        True if zmpkit set the location; False if Warp's own (``WARP_CACHE_PATH``, a
        ``kernel_cache_dir`` already set, or an initialised Warp) stays.
    """
    env = os.environ if environ is None else environ
    if env.get(_WARP_ENV) or wp.config.kernel_cache_dir is not None:
        return False
    wp.config.kernel_cache_dir = str(warp_cache_base(env))
    return True


def cache_file_count(path: str | Path) -> int:
    """Files below ``path`` (0 if it does not exist): a cache's kernels and their sources."""
    return sum(len(files) for _, _, files in os.walk(path))
