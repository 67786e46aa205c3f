"""Matplotlib set-up shared by every figure: a non-interactive backend and a saver."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # figures are files; never open a window, also on headless CI

import matplotlib.pyplot as plt
from matplotlib.figure import Figure

__all__ = ["new_figure", "save_figure"]


def new_figure(rows: int = 1, cols: int = 1, *, width_in: float = 8.0, height_in: float = 4.5):
    """Return ``(figure, axes)`` with a shared style; ``axes`` is an array when rows·cols > 1."""
    fig, axes = plt.subplots(
        rows, cols, figsize=(width_in, height_in), squeeze=rows * cols == 1, layout="constrained"
    )
    return fig, axes


def save_figure(fig: Figure, path: str | Path, dpi: int = 120) -> Path:
    """Save ``fig`` as PNG at ``path``, close it, and return the path."""
    path = Path(path)
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path
