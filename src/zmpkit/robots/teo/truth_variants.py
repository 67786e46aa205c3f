r"""Truth variants of the virtual TEO: robots the shipped truth does not describe.

The balance method must hold on a robot other than the one it was tuned on. Each variant is
the shipped truth document with one physical change (issue 14's test cases), written as a
truth file that ``zmpkit balance --truth FILE`` reads:

=================  ==========================================================================
``stiff_flex``     foot and hip structural compliance × 0.6 (every stage's stiffness / 0.6)
``soft_flex``      foot and hip structural compliance × 1.6
``backlash_x3``    gear lost motion × 3
``payload_plus3``  3 kg more at the trunk payload
``ft_offsets``     other F-T offsets (mirrored, Fz offsets of the opposite sign, 1.5 × size)
``combined``       soft flex, backlash × 3, +3 kg and the other offsets together
``variability``    the shipped robot with trial-to-trial variability (:data:`VARIABILITY`):
                   trials in sequence without reset, stance differences, F-T offset drift,
                   per-sensor per-axis F-T gain errors
=================  ==========================================================================

A compliance scale :math:`\kappa` divides the base stiffness :math:`k_0` of the softening
spring :math:`\delta = \tau/k_0 + \tau|\tau|/(k_0\tau_s)` (:mod:`zmpkit.sim.spring`), so both
terms, hence the deflection at every load, scale by :math:`\kappa`.
"""

from __future__ import annotations

import copy
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import yaml

from zmpkit.errors import ParameterError
from zmpkit.robots.teo.truth import DEFAULT_TRUTH_PATH

__all__ = [
    "TRUTH_VARIANTS",
    "VARIABILITY",
    "truth_variant",
    "write_truth_variant",
    "write_truth_variants",
]

Doc = dict[str, Any]

_FOOT_HIP_FLEX = ("foot_pitch_flex", "foot_roll_flex", "hip_roll_flex")
PAYLOAD_EXTRA_KG = 3.0
"""Extra trunk payload of ``payload_plus3`` [kg]."""
BACKLASH_SCALE = 3.0
"""Lost-motion scale of ``backlash_x3`` [-]."""


def _scale_compliance(doc: Doc, scale: float) -> Doc:
    for entry in doc["flex"]:
        if any(entry["name"].endswith(part) for part in _FOOT_HIP_FLEX):
            entry["stiffness"] = [float(k) / scale for k in entry["stiffness"]]
    return doc


def _backlash(doc: Doc) -> Doc:
    doc["gear"]["backlash"] = float(doc["gear"]["backlash"]) * BACKLASH_SCALE
    return doc


def _payload(doc: Doc) -> Doc:
    doc["payload"]["mass_kg"] = float(doc["payload"]["mass_kg"]) + PAYLOAD_EXTRA_KG
    return doc


def _offsets(doc: Doc) -> Doc:
    """Right and left offsets swapped, F_z (index 2) negated, all 1.5 × as large."""
    right, left = (list(map(float, doc["sensors"]["ft_offset"][s])) for s in ("right", "left"))
    flip = [1.5, 1.5, -1.5, 1.5, 1.5, 1.5]
    doc["sensors"]["ft_offset"] = {
        "right": [f * v for f, v in zip(flip, left, strict=True)],
        "left": [f * v for f, v in zip(flip, right, strict=True)],
    }
    return doc


VARIABILITY: Mapping[str, Any] = {
    "variability": {"sequence": True, "previous_hold_s": 5.0, "stance_std_rad": 0.003},
    "ft_offset_drift_std": [0.02, 0.02, 0.05, 0.01, 0.01, 0.001],
    "ft_gain_error": {
        "right": [0.01, 0.012, 0.008, 0.02, 0.015, 0.01],
        "left": [0.012, 0.008, 0.01, -0.005, 0.005, 0.01],
    },
}
"""ASSUMED trial-to-trial variability, sized so repeated LIPM steps at 0.06 m scatter by
about paper A's ±3 points of percent (std ≈ 1.8 points over seeds 0-5): stance offsets of
0.003 rad (0.17°) per leaning joint, F-T offset drift rates of std (0.02, 0.02, 0.05 N/s,
0.01, 0.01, 0.001 N·m/s), each sensor's gains within ±2 % per axis, and each trial after
the previous target's lean held 5 s."""


def _variability(doc: Doc) -> Doc:
    doc["variability"] = dict(VARIABILITY["variability"])
    doc["sensors"]["ft_offset_drift_std"] = list(VARIABILITY["ft_offset_drift_std"])
    doc["sensors"]["ft_gain_error"] = copy.deepcopy(dict(VARIABILITY["ft_gain_error"]))
    return doc


def _combined(doc: Doc) -> Doc:
    return _offsets(_payload(_backlash(_scale_compliance(doc, 1.6))))


TRUTH_VARIANTS: Mapping[str, Callable[[Doc], Doc]] = {
    "stiff_flex": lambda d: _scale_compliance(d, 0.6),
    "soft_flex": lambda d: _scale_compliance(d, 1.6),
    "backlash_x3": _backlash,
    "payload_plus3": _payload,
    "ft_offsets": _offsets,
    "combined": _combined,
    "variability": _variability,
}
"""Variant name → change applied to a copy of the shipped truth document."""


def truth_variant(name: str, base: Mapping[str, Any] | None = None) -> Doc:
    """The truth document of variant ``name``, built from ``base`` (default: shipped truth).

    Raises:
        ParameterError: on an unknown name, listing the valid ones.
    """
    if name not in TRUTH_VARIANTS:
        raise ParameterError(f"unknown truth variant {name!r}; valid: {', '.join(TRUTH_VARIANTS)}")
    if base is None:
        base = yaml.safe_load(DEFAULT_TRUTH_PATH.read_text(encoding="utf-8"))
    return TRUTH_VARIANTS[name](copy.deepcopy(dict(base)))


def write_truth_variant(name: str, out_dir: str | Path) -> Path:
    """Write variant ``name`` as ``<out_dir>/teo_<name>.yaml``; returns the path."""
    folder = Path(out_dir)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"teo_{name}.yaml"
    header = f"# Virtual TEO truth variant {name!r} (zmpkit.robots.teo.truth_variants).\n"
    path.write_text(header + yaml.safe_dump(truth_variant(name), sort_keys=False), "utf-8")
    return path


def write_truth_variants(out_dir: str | Path) -> tuple[Path, ...]:
    """Write every variant of :data:`TRUTH_VARIANTS` into ``out_dir``."""
    return tuple(write_truth_variant(name, out_dir) for name in TRUTH_VARIANTS)
