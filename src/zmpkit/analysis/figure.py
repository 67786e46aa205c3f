"""Matplotlib set-up shared by every figure: a non-interactive backend and a saver.

A figure never ends a run whose data were written: if matplotlib cannot draw it (data of
extreme range, e.g. ``±1.7e308``, make its tick locators fail), :func:`save_figure` writes a
placeholder image that says why and issues a :class:`~zmpkit.errors.FigureWarning`.
"""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")  # figures are files; never open a window, also on headless CI

import matplotlib.pyplot as plt
from matplotlib.figure import Figure

from zmpkit._validate import shorten
from zmpkit.errors import FigureWarning

__all__ = ["new_figure", "save_figure"]


def new_figure(
    rows: int = 1, cols: int = 1, *, width_in: float = 8.0, height_in: float = 4.5
) -> tuple[Figure, Any]:
    """Return ``(figure, axes)`` with a shared style; ``axes`` is an array when rows·cols > 1."""
    fig, axes = plt.subplots(
        rows, cols, figsize=(width_in, height_in), squeeze=rows * cols == 1, layout="constrained"
    )
    return fig, axes


def save_figure(fig: Figure, path: str | Path, dpi: int = 120) -> Path:
    """Save ``fig`` as PNG at ``path``, close it, and return the path.

    If the figure cannot be drawn, a placeholder naming the reason is saved instead and a
    :class:`~zmpkit.errors.FigureWarning` is issued.
    """
    path = Path(path)
    try:
        fig.savefig(path, dpi=dpi)
    except Exception as exc:  # any drawing failure: the run's data are already written
        reason = shorten(f"{type(exc).__name__}: {exc}", 120)
        _placeholder(path, reason, dpi)
        warnings.warn(f"could not draw {path.name} ({reason})", FigureWarning, stacklevel=2)
    finally:
        plt.close(fig)
    return path


def _placeholder(path: Path, reason: str, dpi: int) -> None:
    """A small image saying that the figure at ``path`` could not be drawn, and why."""
    fig = plt.figure(figsize=(6.0, 1.5))
    try:
        fig.text(0.5, 0.5, f"figure not drawn:\n{reason}", ha="center", va="center", wrap=True)
        fig.savefig(path, dpi=dpi)
    finally:
        plt.close(fig)
