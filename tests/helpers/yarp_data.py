"""YARP yarpdatadumper dumps for tests: a port's folder with info.log and data.log."""

from __future__ import annotations

from pathlib import Path

import numpy as np

T0 = 1712345678.25
"""The first sender stamp of the dumps [s since the epoch]."""


def fmt(values: np.ndarray) -> str:
    """Values as a bottle's space-separated numbers (repr: read back exactly)."""
    return " ".join(repr(float(v)) for v in values)


def write_dump(folder: Path, port: str, bodies: list[str], stamps: np.ndarray) -> Path:
    """A yarpdatadumper folder for ``port``: info.log and data.log with these bottles."""
    folder.mkdir(parents=True)
    (folder / "info.log").write_text(
        f"Type: Bottle;\nStamp: tx;\n[{T0 - 1:.6f}] {port} [connected]\n"
    )
    lines = [
        f"{k} {float(t)!r} {body}" for k, (t, body) in enumerate(zip(stamps, bodies, strict=True))
    ]
    (folder / "data.log").write_text("\n".join(lines) + "\n")
    return folder
