"""The demo's numeric outputs as a golden set: normalise, compare, regenerate.

``zmpkit demo`` writes its numbers into a few text files (:data:`GOLDEN_FILES`). A refactor
must leave every one of them unchanged; ``tests/pipelines/test_demo.py`` runs the demo and
compares its files with the copies under :data:`GOLDEN_DIR`.

The normaliser drops only what legitimately varies from run to run: wall-clock times, dates,
absolute paths and package versions (keys matching :data:`VARIABLE_KEY_PARTS`; a string
holding an absolute path of the run's own folder). Every other value stays: numbers are
compared to a relative tolerance of :data:`REL_TOL`, text exactly.

The numbers are deterministic on one *instruction set*, not across them: NumPy's kernels and
OpenBLAS pick their code at run time by the CPU's features (AVX-512 against AVX2), and their
last-bit differences grow over a simulated walk to 1e-4 of a Table 1 entry. The golden set
was therefore made, and is compared, with both held to the x86-64-v3 level (AVX2 and FMA,
:data:`REFERENCE_CPU_ENV`), which every x86-64 machine from 2015 on runs alike: MuJoCo's
wheel has no run-time dispatch. A machine below that level cannot reproduce it
(:func:`reference_cpu_missing`).

Regenerate the golden set after an *intended* output change, from a demo folder::

    PYTHONPATH=src:tests python -m helpers.golden_demo OUT_DIR   # zmpkit demo --out OUT_DIR

or run the slow test with ``ZMPKIT_UPDATE_GOLDEN=1`` (it writes the set and passes).
"""

from __future__ import annotations

import csv
import io
import json
import math
import sys
from pathlib import Path
from typing import Any

import yaml

GOLDEN_DIR = Path(__file__).resolve().parent.parent / "pipelines" / "golden" / "demo"
"""Where the golden copies live (the demo's relative paths below it)."""
GOLDEN_FILES = (
    "step_metrics.csv",
    "dlipm.yaml",
    "balance/table1.csv",
    "balance/params.yaml",
    "walk_none/summary.json",
    "walk_all/summary.json",
    "compensate/summary.json",
    "compensate/compensation.json",
    *(
        f"balance/datasets/{plane}_{kind}/meta.json"
        for plane in ("sagittal", "frontal")
        for kind in ("lipm", "dlipm", "linear")
    ),
)
"""The demo's numeric outputs: model metrics and parameters, Table 1, the identified
parameters and each balance sweep's settings and trials, both walks' summaries, the
compensation's summary and details."""
FINGERPRINTED = ("walk_none/timeseries.csv", "walk_all/timeseries.csv", "balance/datasets/*/*.csv")
"""Time series too large to keep (about 60 MB): kept as a fingerprint, per column its number
of values and their sum (:func:`fingerprints`), in ``fingerprints.json``."""
FINGERPRINT_FILE = "fingerprints.json"
REFERENCE_CPU_ENV = {
    "NPY_DISABLE_CPU_FEATURES": "X86_V4 AVX512_ICL AVX512_SPR",
    "OPENBLAS_CORETYPE": "Haswell",
}
"""The environment that holds NumPy's dispatch (>= 2.4 feature names) and OpenBLAS's kernels
(NumPy's and SciPy's copies alike) to AVX2 and FMA: the golden set's instruction set."""
UPDATE_ENV = "ZMPKIT_UPDATE_GOLDEN"
"""Set to 1 to (re)write the golden set from the run instead of comparing."""
REL_TOL = 1e-9
"""Relative tolerance on every number [-]."""
ABS_TOL = 1e-15
"""Absolute tolerance, for numbers that are zero up to rounding [their unit]."""
VARIABLE_KEY_PARTS = ("wall", "elapsed", "date", "started", "version", "path", "host")
"""A mapping key containing one of these names a value that varies run to run: dropped."""


def reference_cpu_missing() -> str | None:
    """Why this machine cannot run the golden set's instruction set, or None when it can."""
    from numpy._core._multiarray_umath import __cpu_features__

    missing = [f for f in ("AVX2", "FMA3") if not __cpu_features__.get(f, False)]
    if missing:
        return f"this CPU lacks {' and '.join(missing)}: the golden set is made with them"
    return None


def normalise(value: Any) -> Any:
    """``value`` without the entries that vary run to run (see :data:`VARIABLE_KEY_PARTS`)."""
    if isinstance(value, dict):
        return {
            k: normalise(v)
            for k, v in value.items()
            if not any(part in str(k).lower() for part in VARIABLE_KEY_PARTS)
        }
    if isinstance(value, list | tuple):
        return [normalise(v) for v in value]
    if isinstance(value, str) and value.startswith("/"):
        return "<absolute path>"
    return value


def read_normalised(path: Path) -> Any:
    """A demo output file as plain data, normalised: JSON/YAML as parsed, CSV as rows."""
    text = path.read_text(encoding="utf-8")
    if path.suffix == ".json":
        return normalise(json.loads(text))
    if path.suffix in (".yaml", ".yml"):
        return normalise(yaml.safe_load(text))
    if path.suffix == ".csv":
        return normalise([list(row) for row in csv.reader(io.StringIO(text))])
    raise ValueError(f"no normaliser for {path.name}; expected .json, .yaml or .csv")


def dump(data: Any, suffix: str) -> str:
    """The normalised data as the text of a golden file (JSON/YAML keep full float precision)."""
    if suffix == ".json":
        return json.dumps(data, indent=0) + "\n"
    if suffix in (".yaml", ".yml"):
        return yaml.safe_dump(data, sort_keys=False)
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="\n").writerows(data)
    return buffer.getvalue()


def differences(got: Any, want: Any, where: str = "") -> list[str]:
    """Where ``got`` differs from ``want``: numbers beyond the tolerances, any other change."""
    if isinstance(want, dict) and isinstance(got, dict):
        if list(got) != list(want):
            return [f"{where}: keys {list(got)} != {list(want)}"]
        return [d for k in want for d in differences(got[k], want[k], f"{where}/{k}")]
    if isinstance(want, list) and isinstance(got, list):
        if len(got) != len(want):
            return [f"{where}: length {len(got)} != {len(want)}"]
        return [
            d
            for i, (g, w) in enumerate(zip(got, want, strict=True))
            for d in differences(g, w, f"{where}[{i}]")
        ]
    a, b = _number(got), _number(want)
    if a is not None and b is not None:
        same = (math.isnan(a) and math.isnan(b)) or math.isclose(
            a, b, rel_tol=REL_TOL, abs_tol=ABS_TOL
        )
        return [] if same else [f"{where}: {got!r} != {want!r}"]
    return [] if got == want else [f"{where}: {got!r} != {want!r}"]


def _number(value: Any) -> float | None:
    """A number (a bool is not one; a CSV cell that parses as a float is)."""
    if isinstance(value, bool) or value is None:
        return None
    if isinstance(value, int | float):
        return float(value)
    if isinstance(value, str):
        try:
            return float(value)
        except ValueError:
            return None
    return None


def fingerprints(out: Path) -> dict[str, dict[str, list[float]]]:
    """Per large CSV of :data:`FINGERPRINTED`, per column: [number of values, their sum].

    Empty cells are not counted; a column of text is left out.
    """
    found: dict[str, dict[str, list[float]]] = {}
    for pattern in FINGERPRINTED:
        for path in sorted(out.glob(pattern)):
            with path.open(encoding="utf-8") as f:
                rows = list(csv.reader(f))
            columns: dict[str, list[float]] = {}
            for k, name in enumerate(rows[0]):
                cells = [row[k] for row in rows[1:] if row[k] != ""]
                values = [_number(c) for c in cells]
                if cells and all(v is not None for v in values):
                    columns[name] = [
                        float(len(values)),
                        math.fsum(v for v in values if v is not None),
                    ]
            found[path.relative_to(out).as_posix()] = columns
    return found


def compare_with_golden(out: Path) -> list[str]:
    """The differences of a demo folder's outputs from the golden set (empty: unchanged)."""
    found = []
    for name in GOLDEN_FILES:
        golden = GOLDEN_DIR / name
        found += differences(read_normalised(out / name), read_normalised(golden), name)
    want = json.loads((GOLDEN_DIR / FINGERPRINT_FILE).read_text(encoding="utf-8"))
    found += differences(fingerprints(out), want, FINGERPRINT_FILE)
    return found


def write_golden(out: Path) -> None:
    """(Re)write the golden set from the demo folder ``out``."""
    for name in GOLDEN_FILES:
        source = out / name
        target = GOLDEN_DIR / name
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(dump(read_normalised(source), source.suffix), encoding="utf-8")
    lines = [
        f"{json.dumps(k)}: {json.dumps(v, separators=(',', ':'))}"
        for k, v in fingerprints(out).items()
    ]
    prints = "{\n" + ",\n".join(lines) + "\n}\n"  # one line a file
    (GOLDEN_DIR / FINGERPRINT_FILE).write_text(prints, encoding="utf-8")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: python -m helpers.golden_demo DEMO_OUT_DIR")
    write_golden(Path(sys.argv[1]))
    print(f"golden set written to {GOLDEN_DIR}")
